// Writing a scenario's outcome as a run folder, all or nothing: the one
// place that decides what a run folder holds, for `run` and `sweep` alike.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "harness/run/scenario_runner.h"

namespace hb {

/// A file a caller adds to a run folder beside the standard ones.
struct RunFolderFile {
  std::string name;  ///< file name inside the run folder
  std::string content;
};

/// Writes `folder` through a staging folder: ticks_<label>.csv per
/// algorithm (and schedule_<label>.csv per multi-rate one), summary.json,
/// junit.xml, then `extra_files`. The folder is
/// replaced only once every file is written, so an interrupted write leaves
/// the previous folder (or none) in place. Only an empty folder or a folder
/// hapticbench wrote is replaced (InputError otherwise); returns true when
/// an earlier folder of hapticbench's was.
/// `sweep_job`: the folder is a sweep job's, whose stale staging the sweep
/// removed before its jobs started (StagedRunFolder's remove_stale).
bool write_scenario_run_folder(const std::filesystem::path& folder, const ScenarioOutcome& outcome,
                               const std::vector<RunFolderFile>& extra_files = {},
                               bool sweep_job = false);

}  // namespace hb
