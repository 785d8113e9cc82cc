#include "hapticbench/proxy/rigid_body.h"

#include <catch2/catch.hpp>
#include <numbers>

#include "tests/support/proxy_fixtures.h"

namespace hb {
namespace {

TEST_CASE("tool pose and twist are the COM state moved to the tool-frame origin", "[rigid_body]") {
  RigidBody body;
  body.centre_of_mass = Vec3(0.01, 0.02, -0.03);
  RigidBodyState state;
  state.x = Vec3(1, 2, 3);
  state.q = Quat(Eigen::AngleAxisd(0.5 * std::numbers::pi, Vec3::UnitZ()));
  state.v = Vec3(0.1, 0, 0);
  state.w = Vec3(0, 0, 2);
  // R c for a quarter turn about z: (−0.02, 0.01, −0.03).
  const Pose pose = tool_pose(body, state);
  CHECK((pose.p - Vec3(1.02, 1.99, 3.03)).norm() < 1e-12);
  // Origin velocity = v + ω × (origin − COM) = (0.1,0,0) + (0,0,2) × (0.02,−0.01,0.03).
  const Twist twist = tool_twist(body, state);
  CHECK((twist.v - Vec3(0.12, 0.04, 0)).norm() < 1e-12);
  const RigidBodyState back = state_at_rest(body, pose);
  CHECK((back.x - state.x).norm() < 1e-12);
  CHECK(back.v.norm() == 0);
}

TEST_CASE("gyroscopic torque Jacobian matches central differences", "[rigid_body]") {
  const Mat3 rotation =
      Quat(Eigen::AngleAxisd(0.8, Vec3(1, 2, -1).normalized())).toRotationMatrix();
  const Mat3 inertia = rotation * Vec3(1e-3, 2e-3, 4e-3).asDiagonal() * rotation.transpose();
  const Vec3 w(3, -1, 2);
  Mat3 numeric;
  const double h = 1e-6;
  for (int c = 0; c < 3; ++c) {
    Vec3 d = Vec3::Zero();
    d[c] = h;
    numeric.col(c) =
        (gyroscopic_torque(inertia, w + d) - gyroscopic_torque(inertia, w - d)) / (2 * h);
  }
  const Mat3 analytic = gyroscopic_torque_jacobian(inertia, w);
  INFO("analytic\n" << analytic << "\nnumeric\n" << numeric);
  CHECK((analytic - numeric).norm() <= 1e-6 * numeric.norm());
  // A spin about a principal axis has no gyroscopic torque.
  CHECK(gyroscopic_torque(inertia, rotation.col(2)).norm() < 1e-15);
}

}  // namespace
}  // namespace hb
