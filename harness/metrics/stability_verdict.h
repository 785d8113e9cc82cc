// The one definition of a stable run. `hapticbench stability` and `zwidth`
// judge their probes with it, every run's summary.json carries it
// (runs[].stability.verdict), and the report's stress matrix, its stiffness
// sweeps and scripts/stability-sweep read it from there.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "harness/metrics/run_metrics.h"

namespace hb {

/// What a stable run must satisfy besides displaying no non-finite wrench,
/// not diverging and not tunnelling.
enum class StabilityCriterion {
  kAll,          ///< passivity and oscillation
  kPassivity,    ///< energy minimum >= −ε: the port energy in open loop, the
                 ///< energy the hand put into the device in closed loop
  kOscillation,  ///< no proxy chatter, and in closed loop no limit cycle
};

/// "all", "passivity", "oscillation"; nullopt for anything else.
std::optional<StabilityCriterion> stability_criterion_named(std::string_view name);
/// The inverse of stability_criterion_named.
const char* stability_criterion_name(StabilityCriterion criterion);

/// The criterion as result files state it.
std::string stability_criterion_text(StabilityCriterion criterion, double epsilon_j);

/// How to judge.
struct StabilityOptions {
  StabilityCriterion criterion = StabilityCriterion::kAll;
  double epsilon_j = 1e-6;  ///< J: how far below zero the energy minimum may go
};

/// The checks, in the order a verdict tries them; a failed run names the first one it failed.
enum class StabilityCheck {
  kNone,        ///< stable: no check failed
  kNonfinite,   ///< a displayed wrench was non-finite (zeroed) on some tick
  kDiverged,    ///< the proxy left the device (stability.diverged)
  kTunnelled,   ///< the proxy's tool passed through a scene object
  kPassivity,   ///< energy minimum below −ε
  kChatter,     ///< the proxy kept oscillating tick to tick
  kLimitCycle,  ///< closed loop: the device oscillated in a limit cycle
};

/// "", "nonfinite", "diverged", "tunnelled", "passivity", "chatter", "limit_cycle".
const char* stability_check_name(StabilityCheck check);

struct StabilityResult {
  bool stable = false;
  StabilityCheck failed = StabilityCheck::kNone;
  /// For people, the failed check with its figure ("diverged at tick 812",
  /// "passivity −3.1 mJ", "chatters 13 µm"); for a stable run the figure
  /// behind the pass: the deepest penetration where one is measured, else
  /// the energy minimum.
  std::string reason;
};

/// The verdict on one run's metrics.
StabilityResult judge_stability(const RunMetrics& metrics, const StabilityOptions& options = {});

}  // namespace hb
