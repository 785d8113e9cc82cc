// A sweep expanded into jobs: the cartesian product of its scenarios and
// grid values, each job a complete scenario of its own.
#pragma once

#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hapticbench/input_error.h"
#include "harness/scenario/json_pointer.h"
#include "harness/scenario/scenario.h"
#include "harness/sweep/sweep_spec.h"

namespace hb {

struct SweepJob {
  std::size_t index = 0;           ///< position in the sweep's job order, 0-based
  std::string name;                ///< "<scenario name>__<key>=<value>__..."; the run folder's name
  std::size_t scenario_index = 0;  ///< which of SweepSpec::scenario_paths it derives from
  std::string scenario_path;       ///< that scenario file
  std::filesystem::path base_dir;  ///< the scenario file's folder, absolute
  /// (grid key, value) in grid order.
  std::vector<std::pair<std::string, nlohmann::ordered_json>> grid_values;
  /// The job's scenario: grid values set, name replaced by the job's name,
  /// algorithms kept per only_algorithms, mesh and trace file paths absolute
  /// (so the JSON runs from anywhere, e.g. `hapticbench run scenario.json`).
  nlohmann::ordered_json scenario;
};

/// A sweep's errors gathered so that one check reports every one at once
/// (a grid of 7 values with 2 bad ones names both). Errors about jobs that
/// say the same are listed once with the jobs' names.
class SweepErrors {
 public:
  explicit SweepErrors(std::string sweep_file) : sweep_file_(std::move(sweep_file)) {}
  /// An error of the sweep as a whole (a grid key, a label), kept as it is.
  void add(const InputError& error);
  /// An error of one job's scenario.
  void add_for_job(const std::string& job_name, const InputError& error);
  bool empty() const { return entries_.empty(); }
  /// Nothing when empty; one error as it is (a job's named "<sweep file>:
  /// job <name>: ..."); several as one InputError on the sweep file that
  /// lists them all, one per line.
  void throw_if_any() const;

 private:
  struct Entry {
    InputError error;
    std::vector<std::string> jobs;  ///< empty for an error of the sweep as a whole
  };
  std::string sweep_file_;
  std::vector<Entry> entries_;
};

/// Expands the sweep: scenarios in order, then grid keys in file order, the
/// last key varying fastest. Reads each scenario file as JSON only (nothing
/// is loaded or built). Throws InputError naming the sweep file when a grid
/// key's parent does not exist in a scenario (the message names the key and
/// the scenario), when an only_algorithms label matches nothing, or when
/// two jobs would share a name; a scenario file that is not a JSON object
/// with a "name" is reported against that file, noting the sweep entry.
/// Every such error is reported at once (SweepErrors).
std::vector<SweepJob> expand_sweep_jobs(const SweepSpec& spec);

/// The job's scenario as written to its run folder (scenario.json) and as
/// loaded: the text a job's content hash covers.
std::string sweep_job_scenario_text(const SweepJob& job);

/// An InputError about a job, re-anchored on the sweep file:
/// "<sweep file>: job <name>: <original message with its file and field>".
InputError sweep_job_error(const SweepSpec& spec, const SweepJob& job, const InputError& error);

}  // namespace hb
