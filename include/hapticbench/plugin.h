// A renderer built outside hapticbench: a shared library (a CMake MODULE
// linking hapticbench::renderer) that defines its algorithm rows and
// declares them with HAPTICBENCH_PLUGIN. `hapticbench --plugin PATH.so
// COMMAND ...`, the HAPTICBENCH_PLUGINS variable or a scenario's "plugins"
// load it; its algorithms then run like built-in ones (parameters, budgets,
// caches, sweeps, reports). docs/plugins.md walks through an example.
//
//   namespace {
//   std::unique_ptr<hb::Renderer> create_mine(const hb::RenderContext&, const hb::ParamSet&);
//   const hb::AlgorithmEntry kMine[] = {{"mine", "what it does", &create_mine}};
//   }  // namespace
//   HAPTICBENCH_PLUGIN("my_renderers", kMine)
#pragma once

#include <cstddef>
#include <cstdint>
#include <iterator>

#include "hapticbench/algorithm_entry.h"

namespace hb {

/// The plugin interface's version, counted on its own. It changes whenever
/// a type shared with plugins (Renderer, RenderContext, ParamSet,
/// AlgorithmEntry, ...) changes its layout or meaning; a plugin built
/// against another version is refused.
inline constexpr uint32_t kPluginAbiVersion = 2;

/// What a plugin's entry point returns. abi_version comes first and stays
/// first in every version, so that any host can read it.
struct PluginDescription {
  uint32_t abi_version;              ///< kPluginAbiVersion of the headers it was built with
  const char* name;                  ///< the plugin's name, for listings and messages
  const AlgorithmEntry* algorithms;  ///< its rows, valid while it is loaded
  std::size_t algorithm_count;
};

/// The entry point's name and type, as hapticbench looks it up.
inline constexpr const char* kPluginEntryPoint = "hapticbench_plugin";
using PluginEntryPoint = const PluginDescription* (*)();

}  // namespace hb

/// Defines the plugin's entry point for a name and an array of rows.
#define HAPTICBENCH_PLUGIN(PLUGIN_NAME, ALGORITHM_ROWS)                                            \
  extern "C" __attribute__((visibility("default"))) const hb::PluginDescription*                   \
  hapticbench_plugin() {                                                                           \
    static const hb::PluginDescription description{                                                \
        hb::kPluginAbiVersion, PLUGIN_NAME, std::data(ALGORITHM_ROWS), std::size(ALGORITHM_ROWS)}; \
    return &description;                                                                           \
  }
