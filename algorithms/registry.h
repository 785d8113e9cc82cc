// The one table that names and builds every rendering algorithm: the
// built-in rows of registry.cpp, then the rows plugins register.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "hapticbench/algorithm_entry.h"
#include "hapticbench/param_set.h"
#include "hapticbench/renderer.h"
#include "hapticbench/scene.h"

namespace hb {

/// Every algorithm, in the order `hapticbench list` shows them: built-in
/// rows first, then plugins' rows in the order they were registered.
std::span<const AlgorithmEntry> algorithm_table();

/// The entry named `name`, or nullptr.
const AlgorithmEntry* find_algorithm(std::string_view name);

/// "unknown algorithm \"NAME\" (known: ...; a renderer built outside
/// hapticbench loads with --plugin PATH.so, docs/plugins.md)".
std::string unknown_algorithm_message(std::string_view name);

/// Where an algorithm comes from: "" for a built-in one, else the plugin's
/// origin as given to register_algorithms.
std::string algorithm_origin(std::string_view name);

/// Adds rows to the table (a plugin's). Throws InputError naming `origin`
/// when a name is empty or already taken (by a built-in algorithm, another
/// plugin or another row of the same plugin); nothing is added then. The
/// rows' strings and functions must outlive the process's use of them.
void register_algorithms(std::span<const AlgorithmEntry> rows, const std::string& origin);

/// Builds a renderer by name. Throws InputError naming `field` for an
/// unknown name, and the parameter's field for bad or unknown parameters.
std::unique_ptr<Renderer> create_renderer(const std::string& name, const RenderContext& context,
                                          const ParamSet& params, const std::string& field);

}  // namespace hb
