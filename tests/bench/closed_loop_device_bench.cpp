// Cost of closed-loop replay's device model per tick (ClosedLoopDevice:
// advance over a tick, then the report step() is given), with the desk
// device's defaults (Coulomb friction: 16 substeps) and without friction
// (one exact step). Run: build/tests/bench/closed_loop_device_bench
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "harness/closed_loop/closed_loop_device.h"

namespace hb {
namespace {

void device_tick(benchmark::State& state, bool friction) {
  ClosedLoopModel model;
  if (!friction) {
    model.device.friction_n = 0;
    model.device.friction_nm = 0;
  }
  ClosedLoopDevice device(model, 1e-3);
  // A slow circle with a turn, computed before the timing: the intent moves
  // every tick.
  std::vector<Pose> intents(1000);
  for (std::size_t i = 0; i < intents.size(); ++i) {
    const double t = 1e-3 * static_cast<double>(i);
    intents[i].p = 0.01 * Vec3(std::cos(t), std::sin(t), 0);
    intents[i].q = Quat(Eigen::AngleAxisd(0.2 * std::sin(t), Vec3::UnitZ()));
  }
  device.reset(intents[0]);
  Wrench wrench;
  wrench.force = Vec3(0.3, -0.2, 1.5);
  wrench.torque = Vec3(0.01, 0.02, -0.01);
  int64_t tick = 0;
  for (auto _ : state) {
    const std::size_t now = static_cast<std::size_t>(tick) % (intents.size() - 1);
    device.advance(wrench, intents[now], intents[now + 1]);
    benchmark::DoNotOptimize(device.report(++tick));
  }
}

void BM_device_tick_with_friction(benchmark::State& state) { device_tick(state, true); }
void BM_device_tick_frictionless(benchmark::State& state) { device_tick(state, false); }
BENCHMARK(BM_device_tick_with_friction);
BENCHMARK(BM_device_tick_frictionless);

}  // namespace
}  // namespace hb

BENCHMARK_MAIN();
