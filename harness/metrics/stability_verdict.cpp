#include "harness/metrics/stability_verdict.h"

#include "harness/metrics/formatted_number.h"

namespace hb {

std::optional<StabilityCriterion> stability_criterion_named(std::string_view name) {
  if (name == "all") return StabilityCriterion::kAll;
  if (name == "passivity") return StabilityCriterion::kPassivity;
  if (name == "oscillation") return StabilityCriterion::kOscillation;
  return std::nullopt;
}

const char* stability_criterion_name(StabilityCriterion criterion) {
  switch (criterion) {
    case StabilityCriterion::kPassivity:
      return "passivity";
    case StabilityCriterion::kOscillation:
      return "oscillation";
    case StabilityCriterion::kAll:
      break;
  }
  return "all";
}

std::string stability_criterion_text(StabilityCriterion criterion, double epsilon_j) {
  const std::string base =
      "stable: the run displayed no non-finite wrench, did not diverge (proxy farther than "
      "max(0.1 m, 5 tool radii) from the device, or reset) and its tool did not tunnel through "
      "the scene";
  const std::string passivity =
      "its energy minimum was >= -" + std::to_string(epsilon_j) +
      " J (the port energy in open loop; in closed loop the energy the hand put into the "
      "device, display_energy_min_j)";
  const std::string oscillation =
      "the proxy did not chatter (its position's tick-to-tick second difference, RMS over the "
      "last quarter of the run, below max(1 um, 10 times the device's)) and, in closed loop, "
      "the device had no limit cycle (docs/closed-loop.md)";
  switch (criterion) {
    case StabilityCriterion::kPassivity:
      return base + ", and " + passivity;
    case StabilityCriterion::kOscillation:
      return base + ", and " + oscillation;
    case StabilityCriterion::kAll:
      break;
  }
  return base + ", " + passivity + ", and " + oscillation;
}

const char* stability_check_name(StabilityCheck check) {
  switch (check) {
    case StabilityCheck::kNone:
      return "";
    case StabilityCheck::kNonfinite:
      return "nonfinite";
    case StabilityCheck::kDiverged:
      return "diverged";
    case StabilityCheck::kTunnelled:
      return "tunnelled";
    case StabilityCheck::kPassivity:
      return "passivity";
    case StabilityCheck::kChatter:
      return "chatter";
    case StabilityCheck::kLimitCycle:
      return "limit_cycle";
  }
  return "";
}

StabilityResult judge_stability(const RunMetrics& metrics, const StabilityOptions& options) {
  const StabilityMetrics& s = metrics.stability;
  const bool passivity = options.criterion != StabilityCriterion::kOscillation;
  const bool oscillation = options.criterion != StabilityCriterion::kPassivity;
  // In closed loop the energy the hand put in, else the port energy.
  const double energy_min_j =
      metrics.closed_loop ? metrics.closed_loop->display_energy_min_j : s.passivity_energy_min_j;
  StabilityResult result;
  const auto fail = [&](StabilityCheck check, std::string reason) {
    result.failed = check;
    result.reason = std::move(reason);
    return result;
  };
  if (s.nonfinite > 0)
    return fail(StabilityCheck::kNonfinite,
                "non-finite on " + std::to_string(s.nonfinite) + " ticks");
  if (s.diverged)
    return fail(StabilityCheck::kDiverged,
                s.diverged_at_tick ? "diverged at tick " + std::to_string(*s.diverged_at_tick)
                                   : std::string("diverged"));
  if (s.tunnelled && *s.tunnelled > 0)
    return fail(StabilityCheck::kTunnelled, "tunnelled " + std::to_string(*s.tunnelled) + "×");
  if (passivity && energy_min_j < -options.epsilon_j)
    return fail(StabilityCheck::kPassivity,
                "passivity " + formatted("%.3g", energy_min_j * 1e3) + " mJ");
  if (oscillation && s.chatters)
    return fail(StabilityCheck::kChatter,
                "chatters " + formatted("%.2g", s.proxy_chatter_m * 1e6) + " µm");
  if (oscillation && metrics.closed_loop && metrics.closed_loop->limit_cycles.limit_cycle) {
    const auto& cycles = metrics.closed_loop->limit_cycles;
    std::string reason = "limit cycle";
    if (cycles.amplitude_m) reason += " " + formatted("%.2g", *cycles.amplitude_m * 1e6) + " µm";
    if (cycles.frequency_hz) reason += " at " + formatted("%.3g", *cycles.frequency_hz) + " Hz";
    return fail(StabilityCheck::kLimitCycle, reason);
  }
  result.stable = true;
  if (metrics.accuracy.penetration_max_m)
    result.reason = "pen " + formatted("%.2g", *metrics.accuracy.penetration_max_m * 1e3) + " mm";
  else
    result.reason = "E_min " + formatted("%.2g", energy_min_j * 1e3) + " mJ";
  return result;
}

}  // namespace hb
