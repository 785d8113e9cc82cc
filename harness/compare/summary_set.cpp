#include "harness/compare/summary_set.h"

#include <algorithm>
#include <system_error>

#include "hapticbench/input_error.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

constexpr const char* kSummaryFile = "summary.json";

// A run folder being written or replaced (StagedRunFolder's
// "<name>.partial-<pid>" and "<name>.old-<pid>") is not part of the suite.
bool is_transient_folder(const std::string& name) {
  return name.empty() || name[0] == '.' || name.find(".partial-") != std::string::npos ||
         name.find(".old-") != std::string::npos;
}

ScenarioSummary read_run_folder(const fs::path& folder) {
  ScenarioSummary summary = read_scenario_summary(folder / kSummaryFile);
  summary.run_folder = folder;
  return summary;
}

}  // namespace

const ScenarioSummary* SummarySet::find_scenario(const std::string& name) const {
  for (const ScenarioSummary& scenario : scenarios)
    if (scenario.scenario_name == name) return &scenario;
  return nullptr;
}

SummarySet load_summary_set(const fs::path& path) {
  SummarySet set;
  set.path = path.string();
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error || !fs::exists(status))
    throw InputError(set.path, "",
                     "no such file or folder; expected a run folder, a summary.json file or a "
                     "folder of run folders");
  if (!fs::is_directory(status)) {
    set.scenarios.push_back(read_scenario_summary(path));
    return set;
  }
  if (fs::exists(path / kSummaryFile)) {
    set.scenarios.push_back(read_run_folder(path));
    return set;
  }

  std::vector<fs::path> folders;
  for (const fs::directory_entry& entry : fs::directory_iterator(path)) {
    if (!entry.is_directory() || is_transient_folder(entry.path().filename().string())) continue;
    if (fs::exists(entry.path() / kSummaryFile)) folders.push_back(entry.path());
  }
  if (folders.empty())
    throw InputError(set.path, "",
                     "no summary.json here or in any subfolder; expected a run folder, a "
                     "summary.json file or a folder of run folders");
  std::sort(folders.begin(), folders.end());
  set.is_suite = true;
  for (const fs::path& folder : folders) {
    ScenarioSummary summary = read_run_folder(folder);
    if (const ScenarioSummary* earlier = set.find_scenario(summary.scenario_name))
      throw InputError(summary.source, "/scenario/name",
                       "scenario \"" + summary.scenario_name + "\" is also in " + earlier->source +
                           "; a suite holds each scenario once");
    set.scenarios.push_back(std::move(summary));
  }
  return set;
}

}  // namespace hb
