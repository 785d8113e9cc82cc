// The one table that names and builds every rendering algorithm.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "algorithms/core/param_set.h"
#include "algorithms/core/scene.h"
#include "algorithms/proxy/renderer.h"

namespace hb {

struct AlgorithmEntry {
  std::string_view name;     ///< the `name` in a scenario's algorithms[]
  std::string_view summary;  ///< one line for `hapticbench list`
  std::unique_ptr<Renderer> (*create)(const RenderContext& context, const ParamSet& params);
  /// Its contacts carry the scene objects' Coulomb friction ("friction");
  /// the others are frictionless whatever the scene says.
  bool renders_friction = false;
};

/// Every algorithm, in the order `hapticbench list` shows them.
std::span<const AlgorithmEntry> algorithm_table();

/// The entry named `name`, or nullptr.
const AlgorithmEntry* find_algorithm(std::string_view name);

/// Builds a renderer by name. Throws InputError naming `field` for an
/// unknown name, and the parameter's field for bad or unknown parameters.
std::unique_ptr<Renderer> create_renderer(const std::string& name, const RenderContext& context,
                                          const ParamSet& params, const std::string& field);

}  // namespace hb
