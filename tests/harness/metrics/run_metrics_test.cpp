#include "harness/metrics/run_metrics.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "harness/metrics/budgets.h"
#include "harness/metrics/spectrum.h"

namespace hb {
namespace {

TEST_CASE("energy above a cutoff separates low and high frequencies") {
  const double rate = 1000;
  // Frequencies on DFT bins (k * rate / 1024), so no energy leaks between bins.
  const double bin_hz = rate / 1024;
  std::vector<double> low(1024), high(1024), mixed(1024);
  for (std::size_t i = 0; i < low.size(); ++i) {
    const double t = static_cast<double>(i) / rate;
    low[i] = 3.0 + std::sin(2 * std::numbers::pi * 10 * bin_hz * t);
    high[i] = std::sin(2 * std::numbers::pi * 256 * bin_hz * t);
    mixed[i] = low[i] + high[i];
  }
  CHECK(energy_fraction_above(low, rate, 100) < 1e-12);
  CHECK(energy_fraction_above(high, rate, 100) > 1 - 1e-12);
  CHECK(energy_fraction_above(mixed, rate, 100) == Approx(0.5).margin(1e-12));
  CHECK(energy_fraction_above(std::vector<double>(10, 2.0), rate, 100) == 0.0);
}

// Feeds a synthetic run: device moving along x at 0.1 m/s, display given per tick.
struct SyntheticRun {
  std::vector<DeviceSample> samples;
  MetricsAccumulator metrics{MetricsSettings{}};
  void tick(const Wrench& display, const std::optional<Wrench>& ideal, int64_t step_ns,
            uint32_t flags = 0, std::optional<double> penetration = std::nullopt,
            Vec3 proxy_offset = Vec3::Zero()) {
    DeviceSample s;
    s.tick = static_cast<int64_t>(samples.size());
    s.t_ns = s.tick * kTickNs;
    s.pose.p = Vec3(0.1e-3 * static_cast<double>(s.tick), 0, 0);
    s.twist.v = Vec3(0.1, 0, 0);
    samples.push_back(s);
    TickRecord r;
    r.device = &samples.back();
    r.result.display = display;
    r.result.proxy = s.pose;
    r.result.proxy.p += proxy_offset;
    r.result.flags = flags;
    r.step_ns = step_ns;
    TickEvaluation e;
    e.ideal_display = ideal;
    e.penetration_m = penetration;
    if (ideal) e.reference_contact = ideal->force.norm() > 0;
    metrics.add(r, e);
  }
};

TEST_CASE("energy drift is the slope of the passivity energy over time") {
  // The device moves along +x at 0.1 m/s: a display of (−2, 0, 0) N takes
  // 0.2 J/s from it (E grows at 0.2 J/s), (+3, 0, 0) N gives 0.3 J/s away.
  for (const double fx : {-2.0, 3.0, 0.0}) {
    SyntheticRun run;
    for (int k = 0; k < 5000; ++k)
      run.tick(Wrench{Vec3(fx, 0, 0), Vec3::Zero()}, std::nullopt, 100);
    const RunMetrics m = run.metrics.finish();
    REQUIRE(m.stability.energy_drift_j_per_s);
    CHECK(*m.stability.energy_drift_j_per_s == Approx(-fx * 0.1).margin(1e-9));
  }
  // A periodic exchange (a spring pressed and released) has no trend.
  SyntheticRun spring;
  for (int k = 0; k < 4000; ++k)
    spring.tick(Wrench{Vec3(std::sin(2 * std::numbers::pi * k / 1000.0), 0, 0), Vec3::Zero()},
                std::nullopt, 100);
  CHECK(std::abs(*spring.metrics.finish().stability.energy_drift_j_per_s) < 1e-4);
  SyntheticRun one;
  one.tick(Wrench{}, std::nullopt, 100);
  CHECK_FALSE(one.metrics.finish().stability.energy_drift_j_per_s);
}

TEST_CASE(
    "chatter: a proxy alternating from tick to tick at the end of the run, not a smooth one") {
  // The device moves along x at a constant 0.1 m/s (no second difference).
  // A proxy offset by ±a on alternate ticks has a second difference of 4a.
  const double a = 20e-6;
  SyntheticRun late;  // settled for three quarters of the run, then alternating
  for (int k = 0; k < 4000; ++k)
    late.tick(Wrench{}, std::nullopt, 100, 0, std::nullopt,
              Vec3(0, 0, k >= 3000 ? (k % 2 ? a : -a) : 0.0));
  const RunMetrics m = late.metrics.finish();
  CHECK(m.stability.proxy_chatter_m == Approx(4 * a).epsilon(0.01));
  CHECK(m.stability.device_chatter_m < 1e-12);
  CHECK(m.stability.chatters);
  // The same oscillation in the first half only has died out by the end.
  SyntheticRun early;
  for (int k = 0; k < 4000; ++k)
    early.tick(Wrench{}, std::nullopt, 100, 0, std::nullopt,
               Vec3(0, 0, k < 2000 ? (k % 2 ? a : -a) : 0.0));
  CHECK_FALSE(early.metrics.finish().stability.chatters);
  // One jump of 0.1 mm in the last quarter (a proxy leaving contact that
  // becomes the device) is no oscillation, though its RMS is above 1 µm.
  SyntheticRun jump;
  for (int k = 0; k < 4000; ++k)
    jump.tick(Wrench{}, std::nullopt, 100, 0, std::nullopt, Vec3(0, 0, k < 3500 ? 1e-4 : 0.0));
  const RunMetrics jumped = jump.metrics.finish();
  CHECK(jumped.stability.proxy_chatter_m > 1e-6);
  CHECK_FALSE(jumped.stability.chatters);
  // Below the 1 µm floor; and a proxy lagging the device smoothly by up to
  // 2 mm at 2 Hz (0.16 m/s² relative acceleration): no chatter.
  SyntheticRun small, smooth;
  for (int k = 0; k < 4000; ++k) {
    small.tick(Wrench{}, std::nullopt, 100, 0, std::nullopt, Vec3(0, 0, k % 2 ? 1e-7 : -1e-7));
    const double angle = 2 * std::numbers::pi * 2 * k / 1000.0;
    smooth.tick(Wrench{}, std::nullopt, 100, 0, std::nullopt,
                Vec3(-0.001 * (1 - std::cos(angle)), 0, 0));
  }
  CHECK_FALSE(small.metrics.finish().stability.chatters);
  const RunMetrics lag = smooth.metrics.finish();
  CHECK(lag.stability.proxy_chatter_m < 2e-7);
  CHECK_FALSE(lag.stability.chatters);
}

TEST_CASE("chatter on a run long enough to merge its blocks is still the last quarter's") {
  // 4096 blocks of 50 ticks are 204,800 ticks; past that, blocks merge.
  const double a = 20e-6;
  const int ticks = 240000;
  SyntheticRun late;
  for (int k = 0; k < ticks; ++k)
    late.tick(Wrench{}, std::nullopt, 100, 0, std::nullopt,
              Vec3(0, 0, k >= ticks / 4 * 3 ? (k % 2 ? a : -a) : 0.0));
  const RunMetrics m = late.metrics.finish();
  CHECK(m.stability.proxy_chatter_m == Approx(4 * a).epsilon(0.01));
  CHECK(m.stability.chatters);
}

TEST_CASE("slow updates: time spread over the ticks until installation, count over 1 ms") {
  // Ten ticks of 100 ns; updates of 3 ms (installed 3 ticks later), 0.5 ms
  // (1 tick) and 2 ms (2 ticks) starting at ticks 0, 3 and 4.
  MetricsAccumulator metrics{MetricsSettings{}};
  std::vector<DeviceSample> samples(10);
  const std::map<int, std::pair<int64_t, int64_t>> updates = {
      {0, {3'000'000, 3}}, {3, {500'000, 1}}, {4, {2'000'000, 2}}};
  for (int k = 0; k < 10; ++k) {
    samples[k].tick = k;
    TickRecord r;
    r.device = &samples[k];
    r.step_ns = 100;
    if (const auto it = updates.find(k); it != updates.end()) {
      r.slow_started = true;
      r.slow_ns = it->second.first;
      r.slow_latency_ticks = it->second.second;
    }
    metrics.add(r, TickEvaluation{});
  }
  const RunMetrics m = metrics.finish();
  CHECK(m.timing.slow_updates_over_tick == 2);
  REQUIRE(m.timing.slow_update_ns);
  CHECK(m.timing.slow_update_ns->count == 3);
  // Per tick: 1,000,100 ns at ticks 0-2 and 4-5, 500,100 at tick 3, 100 after.
  CHECK(m.timing.cpu_per_tick_ns.mean == Approx((5 * 1'000'100.0 + 500'100 + 4 * 100) / 10));
  CHECK(m.timing.cpu_per_tick_ns.percentiles.p50 == 500'100);
  CHECK(m.timing.cpu_per_tick_ns.percentiles.max == 1'000'100);
}

TEST_CASE("slow data age: mean, 99th percentile and maximum over the ticks that had data") {
  // A slow loop 10 ticks late whose next update starts as one installs:
  // the data a step uses is 10, 11, ..., 19 ticks old, over and over (1,000
  // ticks); 20 ticks before the first installation have none. Nearest rank:
  // the 99th percentile of 100 cycles of 10..19 is 19 (rank 990 of 1,000).
  MetricsAccumulator metrics{MetricsSettings{}};
  std::vector<DeviceSample> samples(1020);
  for (int k = 0; k < 1020; ++k) {
    samples[k].tick = k;
    TickRecord r;
    r.device = &samples[k];
    r.step_ns = 100;
    r.slow_data_age_ticks = k < 20 ? -1 : 10 + (k - 20) % 10;
    metrics.add(r, TickEvaluation{});
  }
  const RunMetrics m = metrics.finish();
  REQUIRE(m.timing.slow_data_age_mean_ticks);
  CHECK(*m.timing.slow_data_age_mean_ticks == Approx(14.5));
  CHECK(m.timing.slow_data_age_p99_ticks == 19);
  CHECK(m.timing.slow_data_age_max_ticks == 19);
  // One tick in a hundred 40 ticks old: the maximum, not the 99th percentile.
  MetricsAccumulator rare{MetricsSettings{}};
  for (int k = 0; k < 1000; ++k) {
    TickRecord r;
    r.device = &samples[k];
    r.slow_data_age_ticks = k % 100 == 99 && k < 900 ? 40 : 2;
    rare.add(r, TickEvaluation{});
  }
  const RunMetrics rm = rare.finish();
  CHECK(rm.timing.slow_data_age_p99_ticks == 2);
  CHECK(rm.timing.slow_data_age_max_ticks == 40);
}

TEST_CASE("force error, direction error and penetration against the reference") {
  SyntheticRun run;
  run.samples.reserve(10);
  Wrench ideal;
  ideal.force = Vec3(0, 0, 10);
  Wrench rendered;
  rendered.force = Vec3(0, 10 * std::sin(0.1), 10 * std::cos(0.1));  // 0.1 rad off, same size
  run.tick(rendered, ideal, 100, 0, 0.002);
  run.tick(rendered, ideal, 200, 0, 0.0);
  const RunMetrics m = run.metrics.finish();
  const double chord = 2 * 10 * std::sin(0.05);
  CHECK(*m.accuracy.force_err_rms_n == Approx(chord));
  CHECK(*m.accuracy.force_dir_err_max_deg == Approx(0.1 * 180 / std::numbers::pi));
  CHECK(*m.accuracy.penetration_max_m == Approx(0.002));
  CHECK(*m.accuracy.penetration_rms_m == Approx(0.002));
  CHECK(*m.accuracy.penetration_ticks == 1);
  CHECK(m.timing.ticks == 2);
  CHECK(m.timing.contact_step_ns->count == 2);
  CHECK_FALSE(m.timing.free_space_step_ns);
}

TEST_CASE("metrics without a reference are absent, not zero") {
  SyntheticRun run;
  run.samples.reserve(10);
  run.tick(Wrench{}, std::nullopt, 100);
  const RunMetrics m = run.metrics.finish();
  CHECK_FALSE(m.accuracy.force_err_rms_n);
  CHECK_FALSE(m.accuracy.penetration_max_m);
  CHECK_FALSE(m.timing.slow_update_ns);
  CHECK(m.transparency.free_space_ticks == 1);
  const BudgetVerdict verdict = evaluate_budget("force_err_rms_n", 1.0, m);
  CHECK_FALSE(verdict.pass);
  CHECK_FALSE(verdict.value);
}

TEST_CASE("passivity energy is the held wrench's work at the device port") {
  SyntheticRun run;
  run.samples.reserve(200);
  // Display pushes along +x while the device moves along +x by 0.1 mm a
  // tick: energy flows out of the virtual world, 2 N * 0.1 mm for each of
  // the 99 ticks whose wrench was held while the device moved.
  Wrench display;
  display.force = Vec3(2, 0, 0);
  for (int k = 0; k < 100; ++k) run.tick(display, std::nullopt, 10);
  const RunMetrics m = run.metrics.finish();
  CHECK(m.stability.passivity_energy_final_j == Approx(-99 * 2 * 0.1e-3));
  CHECK(m.stability.passivity_energy_min_j == Approx(m.stability.passivity_energy_final_j));
  CHECK(m.stability.force_jump_max_n == 0);
  CHECK(budget_is_lower_bound("passivity_energy_min_mj"));
  // The budget is in mJ, the summary's field in J: -19.8 mJ.
  CHECK(*evaluate_budget("passivity_energy_min_mj", 0.0, m).value == Approx(-19.8));
  CHECK_FALSE(evaluate_budget("passivity_energy_min_mj", 0.0, m).pass);
  CHECK_FALSE(evaluate_budget("passivity_energy_min_mj", -10.0, m).pass);
  CHECK(evaluate_budget("passivity_energy_min_mj", -20.0, m).pass);
}

TEST_CASE("non-finite wrenches are counted and treated as zero, divergence is flagged") {
  SyntheticRun run;
  run.samples.reserve(10);
  Wrench bad;
  bad.force = Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0);
  Wrench small;
  small.force = Vec3(1, 0, 0);
  run.tick(small, std::nullopt, 10);
  run.tick(bad, std::nullopt, 10);
  run.tick(small, std::nullopt, 10, 0, std::nullopt, Vec3(0.5, 0, 0));
  const RunMetrics m = run.metrics.finish();
  CHECK(m.stability.nonfinite == 1);
  CHECK(m.stability.force_jump_max_n == Approx(1.0));  // 1 -> 0 (zeroed) -> 1
  CHECK(m.stability.diverged);
  CHECK(*m.stability.diverged_at_tick == 2);
  CHECK(m.stability.max_proxy_separation_m == Approx(0.5));
  CHECK_FALSE(evaluate_budget("nonfinite", 0, m).pass);
  CHECK(evaluate_budget("nonfinite", 1, m).pass);
  CHECK_FALSE(evaluate_budget("diverged", 0, m).pass);
}

TEST_CASE("timing budgets read microseconds and deadline misses count ticks over 1 ms") {
  SyntheticRun run;
  run.samples.reserve(200);
  for (int k = 0; k < 100; ++k) run.tick(Wrench{}, std::nullopt, k < 98 ? 50'000 : 2'000'000);
  const RunMetrics m = run.metrics.finish();
  CHECK(m.timing.over_budget == 2);
  CHECK(*budget_metric("tick_p50_us", m) == Approx(50));
  CHECK(*budget_metric("tick_max_us", m) == Approx(2000));
  // No slow loop: the CPU time per tick is the step's; its mean is exact.
  CHECK(*budget_metric("cpu_per_tick_mean_us", m) == Approx((98 * 50.0 + 2 * 2000.0) / 100));
  CHECK(*budget_metric("cpu_per_tick_p99_us", m) == Approx(2000));
  CHECK_THROWS_AS(budget_metric("tick_p90_us_typo", m), std::invalid_argument);
  // Not every metric of the table is a budget.
  CHECK_THROWS_AS(budget_metric("embree_penetration_max_m", m), std::invalid_argument);
}

TEST_CASE("the contact normal error against the oracle is a budget, absent without an oracle") {
  SyntheticRun run;
  run.samples.reserve(10);
  run.tick(Wrench{}, std::nullopt, 100);
  CHECK_FALSE(budget_metric("contact_normal_err_rms_deg", run.metrics.finish()));

  MetricsAccumulator with_oracle(MetricsSettings{});
  TickRecord record;
  DeviceSample device;
  record.device = &device;
  TickEvaluation evaluation;
  evaluation.oracle.emplace();
  evaluation.oracle->contact_checks = {{3.0, 0.0}, {4.0, 0.0}};  // degrees, metres
  with_oracle.add(record, evaluation);
  const RunMetrics m = with_oracle.finish();
  CHECK(*budget_metric("contact_normal_err_rms_deg", m) == Approx(std::sqrt(12.5)));
  CHECK_FALSE(evaluate_budget("contact_normal_err_rms_deg", 3.0, m).pass);
  CHECK(evaluate_budget("contact_normal_err_rms_deg", 4.0, m).pass);
}

}  // namespace
}  // namespace hb
