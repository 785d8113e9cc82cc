// Plugins: shared libraries with renderers built against the installed
// package (include/hapticbench/plugin.h, docs/plugins.md). Loading one
// registers its algorithms in the registry; they then run like built-in ones.
#pragma once

#include <filesystem>
#include <optional>
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

/// What happens to a plugin a scenario file names ("plugins"): a data file
/// alone never makes hapticbench run code.
enum class ScenarioPlugins {
  kOnlyLoaded,  ///< used only when already loaded (--plugin, HAPTICBENCH_PLUGINS); else refused
  kAllowed,     ///< loaded (--allow-scenario-plugins)
  kNotLoaded,   ///< never loaded, and algorithms only they register go unchecked (validate)
};
void set_scenario_plugins(ScenarioPlugins policy);
ScenarioPlugins scenario_plugins();

/// The name of the command line flag that allows scenario plugins.
inline constexpr const char* kAllowScenarioPluginsFlag = "--allow-scenario-plugins";

/// Why the policy refuses the plugin a scenario names at `path` (naming
/// the flags that allow it), or nullopt when it may be used.
std::optional<std::string> scenario_plugin_refusal(const std::filesystem::path& path);

/// Loads the plugin a scenario names at `path` (field `field` of the
/// scenario), under the policy above. Returns false when it was left
/// unloaded (kNotLoaded); throws InputError when the policy refuses it
/// (scenario_plugin_refusal), or as load_plugin does.
bool load_scenario_plugin(const std::filesystem::path& path, const std::string& field);

/// From now on, this process refuses every plugin (load_plugin throws
/// InputError with `reason`): programs that read untrusted scenarios, such
/// as the fuzz targets, must not open the shared libraries those name.
void refuse_plugins(const std::string& reason);

/// Every plugin loaded so far, in load order.
const std::vector<LoadedPlugin>& loaded_plugins();

/// Loads the plugins HAPTICBENCH_PLUGINS lists. A relative entry is refused
/// (InputError): it would load from whatever folder the command runs in.
void load_plugins_from_environment();

}  // namespace hb
