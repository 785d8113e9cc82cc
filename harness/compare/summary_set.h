// One side of a comparison as given on the command line: a run folder (it
// holds summary.json and perhaps ticks_<label>.csv files), a summary.json
// file, or a suite folder whose subfolders are run folders (out/smoke/,
// reports/baselines/smoke/).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "harness/compare/scenario_summary.h"

namespace hb {

struct SummarySet {
  std::string path;  ///< as given
  /// True for a folder of run folders; scenarios are then matched by name.
  bool is_suite = false;
  /// One summary for a run folder or file; a suite's in subfolder name order.
  std::vector<ScenarioSummary> scenarios;

  /// The scenario with this name, or nullptr.
  const ScenarioSummary* find_scenario(const std::string& name) const;
};

/// Loads every summary under `path`. Throws InputError naming the file and
/// what is wrong: a missing path, a folder with no summary.json in it or in
/// any subfolder, a summary that does not parse or lacks a contract key, or
/// a suite holding one scenario twice.
SummarySet load_summary_set(const std::filesystem::path& path);

}  // namespace hb
