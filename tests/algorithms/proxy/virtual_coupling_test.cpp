#include "hapticbench/proxy/virtual_coupling.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "tests/support/proxy_fixtures.h"

namespace hb {
namespace {

RigidBody offset_body() {
  RigidBody body;
  body.mass_kg = 0.3;
  body.centre_of_mass = Vec3(0.01, -0.02, 0.03);
  body.inertia_body = Vec3(2e-4, 3e-4, 4e-4).asDiagonal();
  return body;
}

TEST_CASE("coupling pulls the proxy's tool-frame origin towards the device's", "[coupling]") {
  const RigidBody body = offset_body();
  const CouplingGains gains{2000, 5, 5, 0.05};
  RigidBodyState state;
  state.q = Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
  state.x = Vec3(0.1, 0.2, 0.3);
  // The tool-frame origin, computed from the rotation matrix: x − R c.
  const Mat3 r = state.q.toRotationMatrix();
  const Vec3 origin = state.x - r * body.centre_of_mass;

  Pose device{origin + Vec3(0.003, -0.001, 0.002), state.q};
  const CouplingEvaluation c = evaluate_coupling(gains, body, state, device, Twist{}, false);
  const Vec3 expected_force = 2000 * Vec3(0.003, -0.001, 0.002);
  CHECK((c.on_proxy.wrench.force - expected_force).norm() < 1e-9);
  // About the COM the force acts with lever origin − COM = −R c.
  CHECK((c.on_proxy.wrench.torque - (-r * body.centre_of_mass).cross(expected_force)).norm() <
        1e-9);
  // The device displays the reaction about its tool-frame origin: no couple here.
  CHECK((c.display.force + expected_force).norm() < 1e-9);
  CHECK(c.display.torque.norm() < 1e-12);
}

TEST_CASE("coupling couple is k_R times the rotation from proxy to device", "[coupling]") {
  const RigidBody body = offset_body();
  const CouplingGains gains{2000, 5, 5, 0.05};
  RigidBodyState state;
  state.q = Quat(Eigen::AngleAxisd(0.4, Vec3::UnitX()));
  state.x = state.q * body.centre_of_mass;  // tool origin at the world origin
  // Device turned a further 0.25 rad about world z.
  Pose device{Vec3::Zero(), Quat(Eigen::AngleAxisd(0.25, Vec3::UnitZ())) * state.q};
  const CouplingEvaluation c = evaluate_coupling(gains, body, state, device, Twist{}, false);
  CHECK(c.on_proxy.wrench.force.norm() < 1e-12);
  CHECK((c.display.torque - (-5 * 0.25 * Vec3::UnitZ())).norm() < 1e-12);
}

TEST_CASE("coupling damper sees the velocity of the tool origin, not of the COM", "[coupling]") {
  const RigidBody body = offset_body();
  const CouplingGains gains{0, 5, 0, 0.05};
  RigidBodyState state;
  state.q = Quat(Eigen::AngleAxisd(-0.3, Vec3(0, 1, 1).normalized()));
  state.v = Vec3(0.1, 0, -0.2);
  state.w = Vec3(1, -2, 0.5);
  const Vec3 lever = -(state.q.toRotationMatrix() * body.centre_of_mass);
  Twist device{Vec3(0.05, 0.05, 0.05), Vec3(0, 0, 1)};
  Pose device_pose{state.x + lever, state.q};
  const CouplingEvaluation c = evaluate_coupling(gains, body, state, device_pose, device, false);
  const Vec3 origin_velocity = state.v + state.w.cross(lever);
  CHECK((c.on_proxy.wrench.force - 5 * (device.v - origin_velocity)).norm() < 1e-12);
  CHECK((-c.display.torque - 0.05 * (device.w - state.w)).norm() < 1e-12);
}

TEST_CASE("coupling Jacobians match central differences (COM offset, rotated)", "[coupling]") {
  const RigidBody body = offset_body();
  const CouplingGains gains{2000, 5, 5, 0.05};
  RigidBodyState state;
  state.x = Vec3(0.02, -0.01, 0.05);
  state.q = Quat(Eigen::AngleAxisd(0.9, Vec3(0.3, -1, 0.4).normalized()));
  state.v = Vec3(0.1, -0.3, 0.2);
  state.w = Vec3(2, -1, 3);
  const Pose device{Vec3(0.03, 0.0, 0.04),
                    Quat(Eigen::AngleAxisd(1.3, Vec3(1, 1, -0.2).normalized()))};
  const Twist device_twist{Vec3(0.2, 0.1, -0.1), Vec3(-1, 0.5, 0.2)};

  const ForceEvaluation f =
      evaluate_coupling(gains, body, state, device, device_twist, true).on_proxy;
  const auto numeric = test::numeric_jacobian(
      [&](const RigidBodyState& s) {
        return evaluate_coupling(gains, body, s, device, device_twist, false).on_proxy.wrench;
      },
      state);
  const auto analytic = test::analytic_jacobian(f);
  INFO("analytic\n" << analytic << "\nnumeric\n" << numeric);
  CHECK((analytic - numeric).norm() <= 1e-6 * numeric.norm());
  // Each block on its own too, so a wrong small block is not hidden by k_T.
  for (int r = 0; r < 2; ++r) {
    for (int c = 0; c < 4; ++c) {
      const Mat3 a = analytic.block<3, 3>(3 * r, 3 * c);
      const Mat3 n = numeric.block<3, 3>(3 * r, 3 * c);
      INFO("block " << r << "," << c);
      CHECK((a - n).norm() <= 1e-6 * std::max(n.norm(), 1e-3));
    }
  }
}

}  // namespace
}  // namespace hb
