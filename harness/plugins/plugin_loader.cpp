#include "harness/plugins/plugin_loader.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <optional>
#include <span>
#include <system_error>
#include <utility>

#include "algorithms/registry.h"
#include "hapticbench/input_error.h"
#include "hapticbench/plugin.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

// Set by refuse_plugins: why this process loads no plugin.
std::string& refusal_reason() {
  static std::string reason;
  return reason;
}

ScenarioPlugins& scenario_plugin_policy() {
  static ScenarioPlugins policy = ScenarioPlugins::kOnlyLoaded;
  return policy;
}

std::vector<LoadedPlugin>& plugins() {
  static std::vector<LoadedPlugin> loaded;
  return loaded;
}

// The paths HAPTICBENCH_PLUGINS lists, ':'-separated; empty entries skipped.
std::vector<std::string> listed_plugins() {
  const char* value = std::getenv(kPluginsVariable);
  std::vector<std::string> paths;
  const std::string list = value ? value : "";
  for (std::size_t start = 0; start < list.size();) {
    const std::size_t end = std::min(list.find(':', start), list.size());
    if (end > start) paths.push_back(list.substr(start, end - start));
    start = end + 1;
  }
  return paths;
}

// Appends the plugin to HAPTICBENCH_PLUGINS unless it is listed.
void export_to_children(const std::string& path) {
  std::vector<std::string> paths = listed_plugins();
  if (std::find(paths.begin(), paths.end(), path) != paths.end()) return;
  paths.push_back(path);
  std::string list;
  for (const std::string& listed : paths) list += (list.empty() ? "" : ":") + listed;
  setenv(kPluginsVariable, list.c_str(), 1);
}

// Closes the library unless released: a plugin that fails a check leaves
// nothing loaded.
struct LibraryHandle {
  void* handle = nullptr;
  ~LibraryHandle() {
    if (handle) dlclose(handle);
  }
  void* release() { return std::exchange(handle, nullptr); }
};

}  // namespace

void refuse_plugins(const std::string& reason) {
  refusal_reason() = reason.empty() ? "plugins are refused in this program" : reason;
}

LoadedPlugin load_plugin(const fs::path& path, const std::string& field) {
  std::error_code error;
  const fs::file_type type = fs::status(path, error).type();
  const std::string shown = path.string();
  if (!refusal_reason().empty())
    throw InputError(shown, field, "cannot load the plugin: " + refusal_reason());
  if (type == fs::file_type::not_found)
    throw InputError(shown, field, "cannot load the plugin: no such file");
  if (type != fs::file_type::regular)
    throw InputError(shown, field,
                     "cannot load the plugin: it is not a regular file (a folder, FIFO or "
                     "device); expected a shared library (.so)");
  const std::string absolute = fs::canonical(path, error).string();
  for (const LoadedPlugin& plugin : plugins())
    if (plugin.path == absolute) return plugin;

  LibraryHandle library{dlopen(absolute.c_str(), RTLD_NOW | RTLD_LOCAL)};
  if (!library.handle) {
    const char* reason = dlerror();
    throw InputError(shown, field,
                     std::string("cannot load the plugin as a shared library: ") +
                         (reason ? reason : "unknown reason"));
  }
  const auto entry_point =
      reinterpret_cast<PluginEntryPoint>(dlsym(library.handle, kPluginEntryPoint));
  if (!entry_point)
    throw InputError(shown, field,
                     std::string("not a hapticbench plugin: it exports no ") + kPluginEntryPoint +
                         "() (define it with HAPTICBENCH_PLUGIN, hapticbench/plugin.h)");
  const PluginDescription* description = entry_point();
  if (!description)
    throw InputError(shown, field, std::string(kPluginEntryPoint) + "() returned no description");
  if (description->abi_version != kPluginAbiVersion)
    throw InputError(shown, field,
                     "built for plugin ABI version " + std::to_string(description->abi_version) +
                         ", but this hapticbench loads version " +
                         std::to_string(kPluginAbiVersion) +
                         "; rebuild the plugin against this hapticbench's package");
  if (!description->name || (!description->algorithms && description->algorithm_count != 0))
    throw InputError(shown, field, "its plugin description has no name or no algorithm rows");
  const std::span<const AlgorithmEntry> rows(description->algorithms, description->algorithm_count);
  if (rows.empty()) throw InputError(shown, field, "the plugin registers no algorithm");
  register_algorithms(rows, absolute);  // throws on a taken name, registering nothing

  LoadedPlugin loaded{absolute, description->name, {}};
  for (const AlgorithmEntry& row : rows) loaded.algorithms.emplace_back(row.name);
  library.release();  // its renderers' code must stay mapped for the process's life
  export_to_children(absolute);
  plugins().push_back(std::move(loaded));
  return plugins().back();
}

const std::vector<LoadedPlugin>& loaded_plugins() { return plugins(); }

void set_scenario_plugins(ScenarioPlugins policy) { scenario_plugin_policy() = policy; }

ScenarioPlugins scenario_plugins() { return scenario_plugin_policy(); }

std::optional<std::string> scenario_plugin_refusal(const fs::path& path) {
  if (scenario_plugin_policy() != ScenarioPlugins::kOnlyLoaded) return std::nullopt;
  std::error_code error;
  const std::string absolute = fs::canonical(path, error).string();
  for (const LoadedPlugin& plugin : plugins())
    if (!error && plugin.path == absolute) return std::nullopt;
  return "names the plugin " + path.string() +
         ", a shared library whose code runs when it is loaded; a scenario alone never loads "
         "one: allow it with --plugin " +
         path.string() + " (or list it in " + kPluginsVariable +
         "), or allow every plugin the scenarios name with " + kAllowScenarioPluginsFlag;
}

bool load_scenario_plugin(const fs::path& path, const std::string& field) {
  if (scenario_plugin_policy() == ScenarioPlugins::kNotLoaded && refusal_reason().empty())
    return false;
  if (const std::optional<std::string> refused = scenario_plugin_refusal(path))
    throw InputError(path.string(), field, *refused);
  load_plugin(path, field);
  return true;
}

void load_plugins_from_environment() {
  for (const std::string& path : listed_plugins()) {
    if (fs::path(path).is_relative())
      throw InputError(path, kPluginsVariable,
                       "a relative plugin path would load from whatever folder the command runs "
                       "in; expected an absolute path");
    load_plugin(path, kPluginsVariable);
  }
}

}  // namespace hb
