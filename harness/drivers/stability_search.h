// Stability searches over scenario parameters (`hapticbench stability`,
// `hapticbench zwidth`): a probe is one run of one algorithm of a scenario
// with some of its fields set, judged by the one verdict of
// stability_verdict.h; the largest stable value of a field is found by
// bracketing and bisection on a log scale.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "harness/closed_loop/small_signal.h"
#include "harness/metrics/stability_verdict.h"
#include "harness/progress/progress_display.h"
#include "harness/run/run_request.h"

namespace hb {

/// One run at one setting of the fields searched.
struct StabilityProbe {
  std::vector<std::pair<std::string, double>> settings;  ///< JSON pointer, value
  bool stable = false;
  StabilityCheck failed = StabilityCheck::kNone;  ///< the verdict's first failed check
  std::string reason;                             ///< the verdict's reason
  bool diverged = false;
  int64_t nonfinite = 0;
  double passivity_min_j = 0;
  double max_separation_m = 0;
  bool chatters = false;
  double proxy_chatter_m = 0;
  // Closed loop only.
  std::optional<double> display_energy_min_j;
  std::optional<bool> limit_cycle;
  std::optional<double> limit_cycle_amplitude_m, limit_cycle_frequency_hz;
};

/// {"value" (the last setting's), "stable", ...} as stability.json lists runs.
nlohmann::ordered_json probe_json(const StabilityProbe& probe);

/// Runs one algorithm of a scenario file with fields set (the file is
/// read once; each probe loads the changed document as a scenario).
class ScenarioProber {
 public:
  /// Throws InputError naming the file when it cannot be read or is not
  /// JSON, or names no algorithm with that label (or name).
  ScenarioProber(std::string scenario_path, std::string label, StabilityCriterion criterion,
                 double epsilon_j, ProgressDisplay& progress);

  /// Loads the scenario with `settings` applied, without running it:
  /// throws InputError naming the field when one cannot be set or the
  /// scenario is invalid with it.
  void check(const std::vector<std::pair<std::string, double>>& settings);

  /// One full run with `settings` applied, judged by the criterion.
  StabilityProbe probe(const std::vector<std::pair<std::string, double>>& settings);

  /// The small-signal k_t limit (small_signal.h) of the scenario with
  /// `settings` applied, at its coupling damping; a note instead for an
  /// open-loop scenario or a renderer the model does not cover.
  SmallSignalLimit small_signal(const std::vector<std::pair<std::string, double>>& settings);

  const std::string& scenario_name() const { return name_; }
  const std::string& algorithm() const { return algorithm_; }
  /// The labelled algorithm's "integrator" parameter; empty when not given.
  const std::string& integrator() const { return integrator_; }

 private:
  /// A run of the labelled algorithm with `settings` made.
  RunRequest request(const std::vector<std::pair<std::string, double>>& settings);
  /// The request's scenario; notes the algorithm's name and integrator.
  Scenario load(const RunRequest& request);

  ScenarioSource source_;  ///< the file, read once
  std::string label_;
  StabilityCriterion criterion_;
  double epsilon_j_;
  ProgressDisplay& progress_;
  std::string name_, algorithm_, integrator_;
  int runs_ = 0;
};

/// The outcome of a search for the largest stable value.
struct StabilityBracket {
  std::optional<double> largest_stable;     ///< null: unstable at the range's bottom
  std::optional<double> smallest_unstable;  ///< null: stable at the range's top
  std::vector<StabilityProbe> probes;       ///< in the order run
  /// Set when the verdicts are not monotonic in the value (a stable value
  /// above an unstable one among the probes): what was seen. Both ends are
  /// then null: there is no limit to report, only that.
  std::string non_monotonic;
};

/// What a bracket without both ends means, for people: "" when it has both;
/// else that the range's bottom was already unstable (the search assumes
/// stability is lost as the value grows, so it cannot look below LO) or that
/// its top was still stable.
std::string bracket_note(const StabilityBracket& bracket, double low, double high);

/// Probes `low` (unstable: done), then `high` (stable: done), then bisects
/// the log of the interval until smallest_unstable / largest_stable − 1 <=
/// tolerance (at most 64 probes).
StabilityBracket search_largest_stable(const std::function<StabilityProbe(double)>& probe,
                                       double low, double high, double tolerance);

}  // namespace hb
