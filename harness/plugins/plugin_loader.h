// Plugins: shared libraries with renderers built against the installed
// package (include/hapticbench/plugin.h, docs/plugins.md). Loading one
// registers its algorithms in the registry; they then run like built-in ones.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace hb {

/// Name of the environment variable listing plugins to load at start-up,
/// ':'-separated. Loading a plugin adds it here, so that the processes a
/// command starts (sweep jobs, instruction counting, Slurm jobs) load it too.
inline constexpr const char* kPluginsVariable = "HAPTICBENCH_PLUGINS";

struct LoadedPlugin {
  std::string path;                     ///< absolute, as loaded
  std::string name;                     ///< the name the plugin gives itself
  std::vector<std::string> algorithms;  ///< the algorithm names it registered
};

/// Loads the plugin at `path` and registers its algorithms; loading a file
/// that is already loaded does nothing. Throws InputError naming the path
/// (and `field`, where a scenario named it) when the file is missing, is not
/// a shared library that loads, lacks the entry point, was built for another
/// plugin ABI version, or names an algorithm that already exists; nothing is
/// registered then.
LoadedPlugin load_plugin(const std::filesystem::path& path, const std::string& field = "");

/// From now on, this process refuses every plugin (load_plugin throws
/// InputError with `reason`): programs that read untrusted scenarios, such
/// as the fuzz targets, must not open the shared libraries those name.
void refuse_plugins(const std::string& reason);

/// Every plugin loaded so far, in load order.
const std::vector<LoadedPlugin>& loaded_plugins();

/// Loads the plugins HAPTICBENCH_PLUGINS lists.
void load_plugins_from_environment();

}  // namespace hb
