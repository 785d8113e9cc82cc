// A sweep file (scenarios/sweeps/README.md): scenarios and a grid of values
// to set in them by JSON pointer, read and checked before anything runs.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace hb {

/// One grid key: where to set a value in each scenario and the values to try.
struct SweepGridAxis {
  std::string pointer;  ///< JSON pointer (RFC 6901) into a scenario, e.g. "/coupling/k_t"
  std::vector<nlohmann::ordered_json> values;  ///< in file order, at least one
};

struct SweepSpec {
  std::string path;  ///< the sweep file, as given
  std::string name;  ///< names the default output folder out/sweeps/<name>/
  /// Scenario files as written in the sweep (relative to the sweep file)...
  std::vector<std::string> scenario_entries;
  /// ...and resolved against the sweep file's folder; parallel to scenario_entries.
  std::vector<std::string> scenario_paths;
  std::vector<SweepGridAxis> grid;  ///< in file order; the last key varies fastest
  /// Labels to keep in every job's scenario; empty keeps all algorithms.
  std::vector<std::string> only_algorithms;
};

/// Reads and checks a sweep file: keys, the scenario files' existence,
/// pointer syntax, value lists. Throws InputError naming the file, the JSON
/// pointer of the field (e.g. "/grid/~1coupling~1k_t") and what was expected.
SweepSpec load_sweep_spec(const std::string& path);

/// The same, from text; `path` names the file in errors and anchors the
/// scenario paths.
SweepSpec parse_sweep_spec(const std::string& json_text, const std::string& path);

}  // namespace hb
