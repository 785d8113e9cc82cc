// A scenario: scene, tool, device trace, algorithms to run, ground truth to
// use and budgets to meet, loaded and validated from JSON (DESIGN.md keys).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hapticbench/param_set.h"
#include "hapticbench/renderer.h"
#include "hapticbench/scene.h"
#include "harness/closed_loop/closed_loop_model.h"
#include "harness/trace/device_trajectory.h"

namespace hb {

struct AlgorithmSpec {
  std::string name;         ///< registry name (checked against the registry when a run reads it)
  std::string pointer;      ///< its entry in the scenario, "/algorithms/<i>"
  std::string label;        ///< unique in the scenario; defaults to name
  ParamSet params;          ///< prefix "/algorithms/<i>/params"
  std::string params_json;  ///< the params object as written (compact JSON), for summaries
};

struct ReferenceSpec {
  std::string oracle = "none";  ///< none, a backend's name (oracle_backends()), all (or both)
  std::vector<std::string> oracle_backends;  ///< what `oracle` names, in oracle_backends() order
  int64_t exact_every = 10;                  ///< evaluation period of exact backends (CGAL), ticks
  std::string analytic = "auto";             ///< auto or none
  /// auto: the mesh force reference (harness/reference/rigid_proxy_reference.h)
  /// where the closed forms do not cover the scene; none: no force reference there.
  std::string force = "auto";
  int64_t force_every = 1;  ///< the mesh force reference on ticks k with k % force_every == 0
  /// Spacing (m) of the tool surface samples whose penetration the oracles
  /// measure; 0 = automatic (a fortieth of the tool's bounding diameter).
  double sample_spacing_m = 0;

  void switch_off_oracle() {
    oracle = "none";
    oracle_backends.clear();
  }
};

/// A budget a run must meet, e.g. {"tick_p99_us", 1000}.
struct Budget {
  std::string name;
  double limit = 0;
};

/// A plugin file a scenario names ("plugins"): read as data; whether it
/// loads is the plugin policy's to say when a run reads the scenario
/// (harness/run/run_request.h).
struct ScenarioPlugin {
  std::string path;     ///< resolved against the scenario's folder
  std::string pointer;  ///< "/plugins/<i>"
};

struct Scenario {
  std::string name;
  std::string path;          ///< the file it came from
  std::string description;   ///< the scenario's "description", for people ("" when absent)
  std::string content_hash;  ///< hash of the file bytes and of every file it names
  /// What kind of scenario it is, for reports: "stress" puts its runs in the
  /// stress matrix (docs/stress.md). Names of letters, digits, '_', '.', '-', '='.
  std::vector<std::string> tags;
  RenderContext context;          ///< scene, tool (with mass properties), coupling, device, gravity
  DeviceTrajectory trajectory;    ///< the trace on the 1 kHz clock, computed on demand
  std::string trace_description;  ///< "generator press (seed 1)" or the trace file path
  std::vector<ScenarioPlugin> plugins;  ///< in the order named
  std::vector<AlgorithmSpec> algorithms;
  ReferenceSpec reference;
  std::vector<Budget> budgets;
  /// Labels whose instability is the point of the scenario ("expected_unstable":
  /// {label: why}), so that an unstable run of theirs does not fail the command.
  std::map<std::string, std::string> expected_unstable;
  /// Closed-loop replay ("closed_loop" block, docs/closed-loop.md): the
  /// trace is the operator's intent and a hand and a device are integrated
  /// between ticks. Empty: open loop, the trace is the device.
  std::optional<ClosedLoopModel> closed_loop;
  /// Physical settings outside their plausible range ("/coupling/k_t: ..."),
  /// warned about by run and validate (docs/limits.md gives the ranges).
  std::vector<std::string> warnings;
};

/// A physical setting's plausible range: outside it a run is allowed but
/// warned about, since absurd settings can pass budgets. docs/limits.md's
/// table is `hapticbench list --limits`.
struct PlausibleRange {
  std::string_view pointer;  ///< the scenario field
  std::string_view unit;
  double low, high;  ///< in unit
  std::string_view why;
  /// The setting's value in a loaded scenario; NaN where it does not apply
  /// (a closed-loop setting of an open-loop scenario).
  double (*value)(const Scenario& scenario);
};

/// Every plausible range, in the order the warnings check them.
std::span<const PlausibleRange> plausible_ranges();

/// Budget names a scenario may use.
const std::vector<std::string>& known_budget_names();

/// Loads, validates and resolves a scenario file: meshes loaded and
/// validated, shapes meshed, mass properties computed, the trace read or
/// generated and resampled to 1 kHz. Throws InputError naming the file, the
/// JSON path of the field (e.g. "/tool/density") and what was expected.
/// Reading runs no code the file names: plugins are returned as paths, and
/// algorithm names are checked against the registry by the run request
/// (read_scenario in harness/run/run_request.h), after the plugins the
/// policy allows are loaded.
/// Same as load_scenario_json on the file's bytes with its own folder as
/// base_dir.
Scenario load_scenario(const std::string& path);

/// Loads a scenario from JSON text that did not come from a file of its own
/// (e.g. a sweep job: a scenario with values replaced). source_path is what
/// errors name and what Scenario::path holds; relative mesh and trace paths
/// resolve against base_dir (as written when base_dir is empty). The content
/// hash covers json_text and every file it names.
Scenario load_scenario_json(const std::string& json_text, const std::string& source_path,
                            const std::filesystem::path& base_dir);

}  // namespace hb
