// The one stability verdict: each check fails a run with its figure, in
// order, the criterion picks passivity or oscillation, closed loop judges
// the energy the hand put in and the device's limit cycles.
#include "harness/metrics/stability_verdict.h"

#include <catch2/catch.hpp>

namespace hb {
namespace {

RunMetrics quiet_run() {
  RunMetrics m;
  m.stability.passivity_energy_min_j = 0;
  m.stability.tunnelled = 0;
  m.accuracy.penetration_max_m = 0.0019;
  return m;
}

TEST_CASE("each check fails a run with its figure, the first one failed named") {
  RunMetrics m = quiet_run();
  StabilityResult v = judge_stability(m);
  CHECK(v.stable);
  CHECK(v.failed == StabilityCheck::kNone);
  CHECK(v.reason == "pen 1.9 mm");

  m.stability.chatters = true;
  m.stability.proxy_chatter_m = 1.4e-5;
  v = judge_stability(m);
  CHECK_FALSE(v.stable);
  CHECK(v.failed == StabilityCheck::kChatter);
  CHECK(v.reason == "chatters 14 µm");

  m.stability.passivity_energy_min_j = -0.0169;  // passivity comes before chatter
  v = judge_stability(m);
  CHECK(v.failed == StabilityCheck::kPassivity);
  CHECK(v.reason == "passivity -16.9 mJ");

  m.stability.tunnelled = 9;
  CHECK(judge_stability(m).reason == "tunnelled 9×");

  m.stability.diverged = true;
  m.stability.diverged_at_tick = 20;
  CHECK(judge_stability(m).reason == "diverged at tick 20");

  m.stability.nonfinite = 3;
  v = judge_stability(m);
  CHECK(v.failed == StabilityCheck::kNonfinite);
  CHECK(v.reason == "non-finite on 3 ticks");
  CHECK(std::string(stability_check_name(v.failed)) == "nonfinite");
}

TEST_CASE("energy within epsilon of zero passes, and the criterion picks the checks") {
  RunMetrics m = quiet_run();
  m.stability.passivity_energy_min_j = -1e-7;
  CHECK(judge_stability(m).stable);  // ε = 1 µJ
  CHECK_FALSE(judge_stability(m, {StabilityCriterion::kAll, 1e-8}).stable);

  m.stability.passivity_energy_min_j = -1.0;
  CHECK_FALSE(judge_stability(m, {StabilityCriterion::kPassivity, 1e-6}).stable);
  CHECK(judge_stability(m, {StabilityCriterion::kOscillation, 1e-6}).stable);

  m.stability.passivity_energy_min_j = 0;
  m.stability.chatters = true;
  CHECK(judge_stability(m, {StabilityCriterion::kPassivity, 1e-6}).stable);
  CHECK_FALSE(judge_stability(m, {StabilityCriterion::kOscillation, 1e-6}).stable);

  // Divergence and tunnelling fail under every criterion.
  m.stability.chatters = false;
  m.stability.tunnelled = 1;
  for (StabilityCriterion c :
       {StabilityCriterion::kAll, StabilityCriterion::kPassivity, StabilityCriterion::kOscillation})
    CHECK(judge_stability(m, {c, 1e-6}).failed == StabilityCheck::kTunnelled);
}

TEST_CASE("in closed loop the hand's energy and the device's limit cycles are judged") {
  RunMetrics m = quiet_run();
  m.accuracy.penetration_max_m.reset();
  m.closed_loop = ClosedLoopMetrics{};
  m.stability.passivity_energy_min_j = -1.0;  // the port energy is not what counts here
  m.closed_loop->display_energy_min_j = 0.002;
  StabilityResult v = judge_stability(m);
  CHECK(v.stable);
  CHECK(v.reason == "E_min 2 mJ");

  m.closed_loop->display_energy_min_j = -0.002;
  CHECK(judge_stability(m).failed == StabilityCheck::kPassivity);

  m.closed_loop->display_energy_min_j = 0;
  m.closed_loop->limit_cycles.limit_cycle = true;
  m.closed_loop->limit_cycles.amplitude_m = 3e-4;
  m.closed_loop->limit_cycles.frequency_hz = 12.5;
  v = judge_stability(m);
  CHECK(v.failed == StabilityCheck::kLimitCycle);
  CHECK(v.reason == "limit cycle 3e+02 µm at 12.5 Hz");
}

TEST_CASE("criteria are named both ways") {
  for (const char* name : {"all", "passivity", "oscillation"})
    CHECK(std::string(stability_criterion_name(*stability_criterion_named(name))) == name);
  CHECK_FALSE(stability_criterion_named("stable"));
}

}  // namespace
}  // namespace hb
