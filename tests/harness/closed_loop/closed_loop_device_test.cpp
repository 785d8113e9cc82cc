// The device held by a hand: energy balance, closed-form motions, friction,
// encoders and the velocity estimate.
#include "harness/closed_loop/closed_loop_device.h"

#include <catch2/catch.hpp>
#include <cmath>

namespace hb {
namespace {

constexpr double kDeviceTickS = 1e-3;

// A model without friction, encoders, filter or damping, to compare with
// closed forms; tests switch on what they need.
ClosedLoopModel ideal_model() {
  ClosedLoopModel model;
  model.hand = {0.1, 1e-3, 300, 0, 1, 0};
  model.device.mass_kg = 0.05;
  model.device.inertia_kgm2 = 2e-4;
  model.device.b_t = 0;
  model.device.b_r = 0;
  model.device.friction_n = 0;
  model.device.friction_nm = 0;
  model.device.encoder_m = 0;
  model.device.encoder_rad = 0;
  model.device.velocity_filter_hz = 0;
  return model;
}

Pose intent_at(const Vec3& p, double angle_z) {
  Pose pose;
  pose.p = p;
  pose.q = Quat(Eigen::AngleAxisd(angle_z, Vec3::UnitZ()));
  return pose;
}

TEST_CASE("without damping or friction, the intent's work is the change of stored energy") {
  // The intent pulls the hand spring at a constant speed and turns at a
  // constant rate; no wrench is displayed. With M v̇ = F_spring only, the
  // intent's work over a tick is w·M Δv, and the stored energy is
  // ½ M |v|² + ½ k |y|² (and the same for rotation).
  const ClosedLoopModel model = ideal_model();
  const double mass = model.hand.mass_kg + model.device.mass_kg;
  const double inertia = model.hand.inertia_kgm2 + model.device.inertia_kgm2;
  const Vec3 w(0.02, -0.01, 0.005);
  const double turn_rate = 0.8;  // rad/s about z
  ClosedLoopDevice device(model, kDeviceTickS);
  device.reset(intent_at(Vec3::Zero(), 0));
  auto stored = [&](const Pose& intent) {
    const Vec3 y = device.pose().p - intent.p;
    const Vec3 y_r = rotation_vector(device.pose().q * intent.q.conjugate());
    return 0.5 * mass * device.velocity().squaredNorm() + 0.5 * model.hand.k_t * y.squaredNorm() +
           0.5 * inertia * device.angular_velocity().squaredNorm() +
           0.5 * model.hand.k_r * y_r.squaredNorm();
  };
  double work = 0;
  Pose intent = intent_at(Vec3::Zero(), 0);
  const double start = stored(intent);
  for (int n = 0; n < 800; ++n) {
    const Pose next = intent_at(w * (n + 1) * kDeviceTickS, turn_rate * (n + 1) * kDeviceTickS);
    const Vec3 v0 = device.velocity(), omega0 = device.angular_velocity();
    device.advance(Wrench{}, intent, next);
    work += w.dot(mass * (device.velocity() - v0)) +
            turn_rate * inertia * (device.angular_velocity() - omega0).z();
    intent = next;
  }
  REQUIRE(std::abs(work) > 1e-6);  // the hand did work
  CHECK(stored(intent) - start == Approx(work).epsilon(1e-9));
}

TEST_CASE("a held force and torque move a free device by F t² / 2M and τ t² / 2I") {
  ClosedLoopModel model = ideal_model();
  model.hand = {0, 0, 0, 0, 0, 0};
  ClosedLoopDevice device(model, kDeviceTickS);
  const Pose still = intent_at(Vec3(0.1, 0.2, 0.3), 0);
  device.reset(still);
  Wrench wrench;
  wrench.force = Vec3(0.3, 0, -0.2);
  wrench.torque = Vec3(0, 0, 0.002);
  const int ticks = 300;
  for (int n = 0; n < ticks; ++n) device.advance(wrench, still, still);
  const double t = ticks * kDeviceTickS;
  const Vec3 moved = device.pose().p - still.p;
  CHECK((moved - wrench.force * t * t / (2 * model.device.mass_kg)).norm() < 1e-14);
  const double turned = rotation_vector(device.pose().q).z();
  CHECK(turned == Approx(0.002 * t * t / (2 * model.device.inertia_kgm2)).epsilon(1e-12));
}

TEST_CASE("Coulomb friction holds a device whose push stays within it and brakes one beyond") {
  ClosedLoopModel model = ideal_model();
  model.hand = {0, 0, 0, 0, 0, 0};
  model.device.friction_n = 0.06;
  const Pose still = intent_at(Vec3::Zero(), 0);
  Wrench wrench;
  SECTION("within: the device does not move") {
    ClosedLoopDevice device(model, kDeviceTickS);
    device.reset(still);
    wrench.force = Vec3(0.05, 0.01, 0);
    for (int n = 0; n < 200; ++n) device.advance(wrench, still, still);
    CHECK(device.pose().p.norm() == 0);
    CHECK(device.velocity().norm() == 0);
  }
  SECTION("beyond: it accelerates by (F − F_c) / M") {
    ClosedLoopDevice device(model, kDeviceTickS);
    device.reset(still);
    wrench.force = Vec3(0.1, 0, 0);
    const int ticks = 100;
    for (int n = 0; n < ticks; ++n) device.advance(wrench, still, still);
    const double t = ticks * kDeviceTickS;
    CHECK(device.pose().p.x() ==
          Approx((0.1 - 0.06) * t * t / (2 * model.device.mass_kg)).epsilon(1e-12));
  }
  SECTION("a hand spring pulling it stops within the friction band") {
    model.hand = {0.1, 1e-3, 300, 0, 1, 0};
    ClosedLoopDevice device(model, kDeviceTickS);
    device.reset(still);
    const Pose away = intent_at(Vec3(0.01, 0, 0), 0);
    device.advance(Wrench{}, still, away);
    for (int n = 0; n < 3000; ++n) device.advance(Wrench{}, away, away);
    CHECK(device.velocity().norm() == 0);
    CHECK(model.hand.k_t * (device.pose().p - away.p).norm() <= 0.06 + 1e-12);
  }
}

TEST_CASE("the device reports its encoders' pose and a filtered backward difference") {
  ClosedLoopModel model = ideal_model();
  model.hand = {0, 0, 0, 0, 0, 0};
  const Pose still = intent_at(Vec3::Zero(), 0);
  Wrench wrench;
  wrench.force = Vec3(0.05, 0, 0);
  const double a = 0.05 / model.device.mass_kg;  // m/s²
  SECTION("encoders: the reading is the nearest multiple of the resolution") {
    model.device.encoder_m = 1e-4;
    ClosedLoopDevice device(model, kDeviceTickS);
    device.reset(still);
    for (int n = 0; n < 400; ++n) {
      device.advance(wrench, still, still);
      const double reading = device.report(n + 1).pose.p.x();
      CHECK(std::abs(reading - device.pose().p.x()) <= 0.5e-4 + 1e-15);
      CHECK(std::abs(reading / 1e-4 - std::round(reading / 1e-4)) < 1e-9);
    }
  }
  SECTION("velocity: the backward difference lags a ramp by T/2, the filter by αT/(1−α) more") {
    for (double cutoff_hz : {0.0, 100.0}) {
      model.device.velocity_filter_hz = cutoff_hz;
      const double alpha = cutoff_hz > 0 ? std::exp(-2 * M_PI * cutoff_hz * kDeviceTickS) : 0;
      ClosedLoopDevice device(model, kDeviceTickS);
      device.reset(still);
      const int ticks = 300;
      for (int n = 0; n < ticks; ++n) device.advance(wrench, still, still);
      const double t = ticks * kDeviceTickS;
      const double lag = kDeviceTickS / 2 + alpha * kDeviceTickS / (1 - alpha);
      CHECK(device.report(ticks).twist.v.x() == Approx(a * (t - lag)).epsilon(1e-9));
      CHECK(device.report(ticks).tick == ticks);
    }
  }
}

TEST_CASE(
    "what the device takes in is the held wrench's work, through viscous and Coulomb friction") {
  // No hand: the held wrench is the only thing doing work on the device, so
  // its kinetic energy plus its friction losses equal F·Δx + τ·Δθ summed
  // over the ticks, while it is pushed and after, while it coasts to rest.
  ClosedLoopModel model = ideal_model();
  model.hand = {0, 0, 0, 0, 0, 0};
  model.device.b_t = 0.4;
  model.device.b_r = 2e-4;
  for (double friction : {0.0, 0.02}) {
    model.device.friction_n = friction;
    model.device.friction_nm = friction / 100;
    ClosedLoopDevice device(model, kDeviceTickS);
    const Pose still = intent_at(Vec3::Zero(), 0);
    device.reset(still);
    double work = 0;
    for (int n = 0; n < 600; ++n) {
      Wrench wrench;
      if (n < 200) {
        wrench.force = Vec3(0.08, -0.05, 0.03);
        wrench.torque = Vec3(0, 0, 1e-3);
      }
      const Pose before = device.pose();
      device.advance(wrench, still, still);
      work += wrench.force.dot(device.pose().p - before.p) +
              wrench.torque.dot(rotation_vector(device.pose().q * before.q.conjugate()));
    }
    INFO("friction " << friction);
    REQUIRE(work > 1e-5);
    CHECK(device.absorbed_energy_j() == Approx(work).epsilon(1e-6));
    if (friction > 0) CHECK(device.velocity().norm() == 0);
  }
}

}  // namespace
}  // namespace hb
