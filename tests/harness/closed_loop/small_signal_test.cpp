// Tests for harness/closed_loop/small_signal.cpp against the closed-loop
// device itself (harness/closed_loop/closed_loop_device.cpp): a device
// held pressed against a rigid wall rendered as −k y − b v̂ from what it
// reports, friction and quantisation off, on three devices (light, the
// default desk device, heavy; filtered velocity on and off): a small
// disturbance dies out 2 % below the small-signal limit and grows 2 % above.
#include "harness/closed_loop/small_signal.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "harness/closed_loop/closed_loop_device.h"

namespace hb::small_signal_test {

constexpr double kTickS = 1e-3;
constexpr double kDampingB = 2;  // b_t, N·s/m

// The RMS of the device's travel about its mean over the last `window`
// ticks after `ticks`, pressed into a wall at z = 0 (travel y = −z) with
// stiffness k, starting 1 µm off its equilibrium.
double late_motion(const ClosedLoopModel& model, double k, int ticks, int window) {
  const Pose intent{Vec3(0, 0, -0.02), Quat::Identity()};  // 20 mm into the wall
  // Start at the pressed equilibrium, nudged: the hand's spring against k.
  const double preload_m = model.hand.k_t * 0.02 / (model.hand.k_t + k);
  ClosedLoopDevice pressed(model, kTickS);
  pressed.reset(Pose{Vec3(0, 0, -preload_m - 1e-6), Quat::Identity()});
  double sum = 0, sum_sq = 0;
  for (int n = 0; n < ticks; ++n) {
    const DeviceSample seen = pressed.report(n);
    const double y = -seen.pose.p.z();  // travel into the wall
    Wrench wrench;
    // Out of the wall along +z: the spring on the travel, the damper on
    // the reported velocity (the travel's rate is −v_z).
    if (y > 0) wrench.force.z() = k * y - kDampingB * seen.twist.v.z();
    pressed.advance(wrench, intent, intent);
    if (n >= ticks - window) {
      sum += pressed.pose().p.z();
      sum_sq += pressed.pose().p.z() * pressed.pose().p.z();
    }
  }
  const double mean = sum / window;
  return std::sqrt(std::max(0.0, sum_sq / window - mean * mean));
}

TEST_CASE("the small-signal limit separates dying from growing motion of the device itself") {
  for (const double device_mass : {0.02, 0.045, 0.5})
    for (const double filter_hz : {0.0, 100.0}) {
      CAPTURE(device_mass, filter_hz);
      ClosedLoopModel model;
      model.device.mass_kg = device_mass;
      model.device.friction_n = 0;
      model.device.encoder_m = 0;
      model.device.velocity_filter_hz = filter_hz;
      const SmallSignalLimit limit = small_signal_k_t_limit(model, kDampingB, kTickS, "god_object");
      REQUIRE(limit.k_t_n_per_m);
      const double k = *limit.k_t_n_per_m;
      CAPTURE(k);
      const double early_below = late_motion(model, 0.98 * k, 500, 200);
      const double late_below = late_motion(model, 0.98 * k, 6000, 200);
      const double early_above = late_motion(model, 1.02 * k, 500, 200);
      const double late_above = late_motion(model, 1.02 * k, 6000, 200);
      CHECK(late_below < early_below);
      CHECK(late_above > early_above);
    }
}

TEST_CASE("renderers the model does not cover get a note, not a number") {
  const SmallSignalLimit limit =
      small_signal_k_t_limit(ClosedLoopModel{}, kDampingB, kTickS, "penalty_analytic");
  CHECK_FALSE(limit.k_t_n_per_m);
  CHECK_THAT(limit.note, Catch::Contains("rigid proxy"));
}

}  // namespace hb::small_signal_test
