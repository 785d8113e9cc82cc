// Resampling onto the 1 kHz clock, checked against closed-form motions.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "harness/trace/trace.h"

namespace {

/// Angle (rad) of the rotation taking b to a.
double angle_between(const hb::Quat& a, const hb::Quat& b) {
  const hb::Quat relative = a * b.conjugate();
  // atan2 keeps full precision for tiny angles, where acos(w) would not.
  return 2.0 * std::atan2(relative.vec().norm(), std::abs(relative.w()));
}

/// Uniform motion: p(t) = p0 + v t, q(t) = exp(w t) q0 (w world frame).
struct UniformMotion {
  hb::Vec3 p0{0.1, -0.2, 0.3};
  hb::Vec3 v{0.05, 0.02, -0.01};
  hb::Quat q0 = hb::Quat(0.9, 0.1, -0.3, 0.2).normalized();
  hb::Vec3 w{0.4, -1.1, 0.7};

  hb::Pose at(double t) const {
    const double angle = w.norm() * t;
    const hb::Quat turn(Eigen::AngleAxisd(angle, w.normalized()));
    return hb::Pose{p0 + v * t, turn * q0};
  }
};

hb::Trace sample_uniform_motion(const UniformMotion& motion, int64_t period_ns, int count,
                                bool with_twist) {
  hb::Trace trace;
  for (int i = 0; i < count; ++i) {
    const int64_t t_ns = period_ns * i;
    hb::TraceSample sample{t_ns, motion.at(static_cast<double>(t_ns) * 1e-9), std::nullopt};
    if (with_twist) sample.twist = hb::Twist{motion.v, motion.w};
    trace.samples.push_back(sample);
  }
  return trace;
}

hb::TraceSample pose_sample(int64_t t_ns, const hb::Vec3& p, const hb::Quat& q) {
  return hb::TraceSample{t_ns, hb::Pose{p, q}, std::nullopt};
}

}  // namespace

TEST_CASE("a 250 Hz uniform motion is reproduced at every 1 kHz tick") {
  const UniformMotion motion;
  // 251 samples every 4 ms: 0 .. 1 s.
  const hb::Trace trace = sample_uniform_motion(motion, 4'000'000, 251, false);
  const std::vector<hb::DeviceSample> ticks = hb::resample_to_ticks(trace);
  REQUIRE(ticks.size() == 1001);
  double worst_position = 0, worst_angle = 0, worst_v = 0, worst_w = 0;
  for (std::size_t k = 0; k < ticks.size(); ++k) {
    const hb::DeviceSample& tick = ticks[k];
    REQUIRE(tick.tick == static_cast<int64_t>(k));
    REQUIRE(tick.t_ns == static_cast<int64_t>(k) * 1'000'000);
    const hb::Pose expected = motion.at(static_cast<double>(k) * 1e-3);
    worst_position = std::max(worst_position, (tick.pose.p - expected.p).norm());
    worst_angle = std::max(worst_angle, angle_between(tick.pose.q, expected.q));
    // Differences of a uniform motion are exact, one-sided ones included.
    worst_v = std::max(worst_v, (tick.twist.v - motion.v).norm());
    worst_w = std::max(worst_w, (tick.twist.w - motion.w).norm());
    REQUIRE(std::abs(tick.pose.q.norm() - 1.0) < 1e-12);
  }
  CHECK(worst_position < 1e-9);
  CHECK(worst_angle < 1e-9);
  CHECK(worst_v < 1e-9);
  CHECK(worst_w < 1e-9);
}

TEST_CASE("recorded twists are interpolated linearly, not re-estimated") {
  hb::Trace trace;
  trace.samples.push_back(pose_sample(0, hb::Vec3::Zero(), hb::Quat::Identity()));
  trace.samples.push_back(pose_sample(4'000'000, hb::Vec3::Zero(), hb::Quat::Identity()));
  // The poses do not move, so a finite difference would give zero.
  trace.samples[0].twist = hb::Twist{hb::Vec3(1, 0, 0), hb::Vec3(0, 0, 2)};
  trace.samples[1].twist = hb::Twist{hb::Vec3(3, 0, 0), hb::Vec3(0, 0, -2)};
  const auto ticks = hb::resample_to_ticks(trace);
  REQUIRE(ticks.size() == 5);
  for (int k = 0; k < 5; ++k) {
    const double alpha = k / 4.0;
    CHECK(ticks[k].twist.v.x() == Approx(1 + 2 * alpha));
    CHECK(ticks[k].twist.w.z() == Approx(2 - 4 * alpha).margin(1e-15));
  }
}

TEST_CASE("slerp takes the short way between q and a sign-flipped neighbour") {
  const hb::Vec3 z = hb::Vec3::UnitZ();
  SECTION("same rotation written with opposite sign") {
    // 0.2 rad about z, stored as -q: the long way would turn 2*pi - 0.2.
    const hb::Quat small(Eigen::AngleAxisd(0.2, z));
    hb::Trace trace;
    trace.samples.push_back(pose_sample(0, hb::Vec3::Zero(), hb::Quat::Identity()));
    trace.samples.push_back(pose_sample(2'000'000, hb::Vec3::Zero(), hb::Quat(-small.coeffs())));
    const auto ticks = hb::resample_to_ticks(trace);
    REQUIRE(ticks.size() == 3);
    const hb::Quat expected(Eigen::AngleAxisd(0.1, z));
    CHECK(angle_between(ticks[1].pose.q, expected) < 1e-12);
    // The estimated angular velocity is the short way's: 0.2 rad in 2 ms.
    CHECK(ticks[1].twist.w.z() == Approx(100.0).epsilon(1e-12));
  }
  SECTION("a turn beyond pi goes the other way round") {
    // 3.5 rad about +z is 2*pi - 3.5 = 2.783 rad about -z.
    hb::Trace trace;
    trace.samples.push_back(pose_sample(0, hb::Vec3::Zero(), hb::Quat::Identity()));
    trace.samples.push_back(
        pose_sample(2'000'000, hb::Vec3::Zero(), hb::Quat(Eigen::AngleAxisd(3.5, z))));
    const auto ticks = hb::resample_to_ticks(trace);
    const hb::Quat expected(Eigen::AngleAxisd(-(2 * std::numbers::pi - 3.5) / 2, z));
    CHECK(angle_between(ticks[1].pose.q, expected) < 1e-12);
  }
}

TEST_CASE("tick count: as many as the trace covers, or held at rest beyond it") {
  hb::Trace trace;
  trace.samples.push_back(pose_sample(0, hb::Vec3(0, 0, 0), hb::Quat::Identity()));
  trace.samples.push_back(pose_sample(10'500'000, hb::Vec3(0.0105, 0, 0), hb::Quat::Identity()));

  // Last sample at 10.5 ms: ticks 0..10.
  const auto covered = hb::resample_to_ticks(trace);
  REQUIRE(covered.size() == 11);
  CHECK(covered[10].pose.p.x() == Approx(0.010));
  CHECK(covered[10].twist.v.x() == Approx(1.0));  // one-sided difference at the end

  const auto truncated = hb::resample_to_ticks(trace, 4);
  REQUIRE(truncated.size() == 4);
  CHECK(truncated[3].t_ns == 3'000'000);

  const auto extended = hb::resample_to_ticks(trace, 20);
  REQUIRE(extended.size() == 20);
  for (int k = 11; k < 20; ++k) {
    CHECK(extended[k].t_ns == int64_t{k} * 1'000'000);
    CHECK(extended[k].pose.p.x() == 0.0105);  // the last pose, held
    CHECK(extended[k].twist.v.norm() == 0.0);
    CHECK(extended[k].twist.w.norm() == 0.0);
  }
  // Inside the trace the motion still moves at 1 m/s.
  CHECK(extended[5].twist.v.x() == Approx(1.0));
}

TEST_CASE("a trace starting after t = 0 holds its first pose until then") {
  hb::Trace trace;
  trace.samples.push_back(pose_sample(2'000'000, hb::Vec3(1, 0, 0), hb::Quat::Identity()));
  trace.samples.push_back(pose_sample(4'000'000, hb::Vec3(3, 0, 0), hb::Quat::Identity()));
  const auto ticks = hb::resample_to_ticks(trace);
  REQUIRE(ticks.size() == 5);
  CHECK(ticks[0].pose.p.x() == 1.0);
  CHECK(ticks[1].pose.p.x() == 1.0);
  CHECK(ticks[0].twist.v.norm() == 0.0);
  CHECK(ticks[3].pose.p.x() == Approx(2.0));
  CHECK(ticks[3].twist.v.x() == Approx(1000.0));
}

TEST_CASE("tick times are exact integers on long traces") {
  // 70 s at 3 samples per 7 ms: any floating-point clock would drift.
  hb::Trace trace;
  const int64_t period_ns = 7'000'000 / 3;  // 2333333 ns
  const int count = 30'000;
  trace.samples.reserve(count);
  for (int i = 0; i < count; ++i)
    trace.samples.push_back(pose_sample(
        period_ns * i, hb::Vec3(static_cast<double>(period_ns) * i, 0, 0), hb::Quat::Identity()));
  const auto ticks = hb::resample_to_ticks(trace);
  const int64_t last_ns = period_ns * (count - 1);
  REQUIRE(static_cast<int64_t>(ticks.size()) == last_ns / 1'000'000 + 1);
  const auto& last = ticks.back();
  CHECK(last.t_ns == (static_cast<int64_t>(ticks.size()) - 1) * 1'000'000);
  // Position equals time in ns along x: interpolation at the exact tick time.
  CHECK(last.pose.p.x() == Approx(static_cast<double>(last.t_ns)).epsilon(1e-15));
}
