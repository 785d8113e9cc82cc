// One row of the algorithm table: how a scenario names a rendering
// algorithm and how hapticbench builds it. Built-in algorithms are rows of
// algorithms/registry.cpp; a plugin brings its own rows (hapticbench/plugin.h).
#pragma once

#include <memory>
#include <string_view>

#include "hapticbench/param_set.h"
#include "hapticbench/renderer.h"
#include "hapticbench/scene.h"

namespace hb {

struct AlgorithmEntry {
  std::string_view name;     ///< the `name` in a scenario's algorithms[]
  std::string_view summary;  ///< one line for `hapticbench list`
  /// Builds the renderer for a scene. Reads every parameter through params
  /// (its accessors check ranges and name the field on error; a key no
  /// accessor reads is refused after create returns). Throws InputError for
  /// a scene it cannot render.
  std::unique_ptr<Renderer> (*create)(const RenderContext& context, const ParamSet& params);
  /// Its contacts carry the scene objects' Coulomb friction ("friction");
  /// the others are frictionless whatever the scene says.
  bool renders_friction = false;
};

}  // namespace hb
