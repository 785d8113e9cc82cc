#include "hapticbench/proxy/quasi_static.h"

#include <catch2/catch.hpp>

#include "hapticbench/proxy/penalty_contact.h"
#include "hapticbench/proxy/virtual_coupling.h"
#include "tests/support/proxy_fixtures.h"

namespace hb {
namespace {

// One contact plane as a spring force model.
class PlaneSpring : public ForceModel {
 public:
  explicit PlaneSpring(ContactPlane plane, double stiffness)
      : plane_(plane), gains_{stiffness, 0} {}
  ForceEvaluation evaluate(const RigidBodyState& state, bool with_jacobians) override {
    return evaluate_penalty_contact(plane_, gains_, state, with_jacobians);
  }

 private:
  ContactPlane plane_;
  PenaltyGains gains_;
};

RigidBody offset_frame() {
  RigidBody frame;
  frame.centre_of_mass = Vec3(0.005, 0.01, -0.02);
  return frame;
}

TEST_CASE("in free space the massless proxy sits on the device", "[quasi_static]") {
  const RigidBody frame = offset_frame();
  QuasiStaticProxy proxy(frame, CouplingGains{2000, 0, 5, 0}, 1e-3, QuasiStaticSettings{});
  proxy.reset(Pose{});
  DeviceSample device;
  device.pose =
      Pose{Vec3(0.01, -0.02, 0.03), Quat(Eigen::AngleAxisd(0.6, Vec3(1, 2, 2).normalized()))};
  uint32_t flags = 0;
  int64_t newton_steps = 0;
  const Wrench display = proxy.advance(device, nullptr, flags, newton_steps);
  CHECK(proxy.converged());
  CHECK(newton_steps >= 1);
  CHECK(newton_steps <= 8);
  CHECK((proxy.tool_pose().p - device.pose.p).norm() < 1e-9);
  CHECK(proxy.tool_pose().q.angularDistance(device.pose.q) < 1e-9);
  CHECK(display.force.norm() < 1e-6);
  CHECK(display.torque.norm() < 1e-8);
  CHECK(flags == 0);

  // Held still, the next tick starts at the answer.
  int64_t again = 0;
  proxy.advance(device, nullptr, flags, again);
  CHECK(again <= 1);
}

TEST_CASE("the coupling dampers see the massless proxy's motion over the tick", "[quasi_static]") {
  const RigidBody frame = offset_frame();
  QuasiStaticProxy proxy(frame, CouplingGains{2000, 5, 5, 0.05}, 1e-3, QuasiStaticSettings{});
  proxy.reset(Pose{});
  DeviceSample device;
  device.pose.p = Vec3(0.001, -0.002, 0.0005);  // moved, not turned, device reports no velocity
  uint32_t flags = 0;
  int64_t newton_steps = 0;
  const Wrench display = proxy.advance(device, nullptr, flags, newton_steps);
  // Springs relaxed; display = −b_T (0 − Δp/Δt).
  CHECK((display.force - 5 * device.pose.p / 1e-3).norm() < 1e-9);
  CHECK(display.torque.norm() < 1e-9);
}

TEST_CASE("against a plane the massless proxy settles where the springs balance in series",
          "[quasi_static]") {
  const RigidBody frame = offset_frame();
  const double k_t = 2000;
  const double k_c = 3000;
  QuasiStaticProxy proxy(frame, CouplingGains{k_t, 0, 5, 0}, 1e-3, QuasiStaticSettings{});
  proxy.reset(Pose{});
  // The tool's frame origin touches the plane z = 0 (normal +z).
  ContactPlane plane;
  plane.tool_point = -frame.centre_of_mass;
  plane.plane_point = Vec3::Zero();
  plane.normal = Vec3::UnitZ();
  PlaneSpring contact(plane, k_c);

  DeviceSample device;
  const double depth = 0.005;
  device.pose.p = Vec3(0.002, 0.001, -depth);
  uint32_t flags = 0;
  int64_t newton_steps = 0;
  const Wrench display = proxy.advance(device, &contact, flags, newton_steps);
  REQUIRE(proxy.converged());
  // k_T (z_p − z_h) = k_c (−z_p): z_p = k_T z_h / (k_T + k_c).
  CHECK(proxy.tool_pose().p.z() == Approx(-k_t * depth / (k_t + k_c)).epsilon(1e-9));
  CHECK(proxy.tool_pose().p.x() == Approx(0.002).epsilon(1e-9));
  // The tool origin is on the plane's line of action: the proxy does not turn.
  CHECK(proxy.tool_pose().q.angularDistance(Quat::Identity()) < 1e-9);
  // Undamped coupling: the displayed force is the series spring's.
  CHECK(display.force.z() == Approx(k_t * k_c / (k_t + k_c) * depth).epsilon(1e-9));
}

TEST_CASE("an off-centre contact makes the proxy turn until the couple balances",
          "[quasi_static]") {
  RigidBody frame;  // COM at the tool origin
  const double k_r = 5;
  QuasiStaticProxy proxy(frame, CouplingGains{2000, 0, k_r, 0}, 1e-3, QuasiStaticSettings{});
  proxy.reset(Pose{});
  // A contact point 5 cm out along x, its plane pressing down along −z with a stiff spring.
  ContactPlane plane;
  plane.tool_point = Vec3(0.05, 0, 0);
  plane.plane_point = Vec3(0.05, 0, -0.001);
  plane.normal = -Vec3::UnitZ();
  PlaneSpring contact(plane, 1e5);
  DeviceSample device;  // at the origin
  uint32_t flags = 0;
  int64_t newton_steps = 0;
  proxy.advance(device, &contact, flags, newton_steps);
  REQUIRE(proxy.converged());
  // Balance by hand: rotation φ about y lowers/raises the point by 0.05 sin φ, pure couple from
  // the spring is (r × F); translation z_p: forces k_t z_p = F, torque k_r φ = 0.05 F cos φ.
  const Pose pose = proxy.tool_pose();
  const Vec3 point = pose.transform_point(plane.tool_point);
  const double depth = plane.normal.dot(plane.plane_point - point);
  REQUIRE(depth > 0);
  const Vec3 force = 1e5 * depth * plane.normal;
  CHECK((2000 * (-pose.p) + force).norm() < 1e-6);
  const Vec3 theta = rotation_vector(pose.q.conjugate());
  CHECK((k_r * theta + (point - pose.p).cross(force)).norm() < 1e-8);
  CHECK(theta.norm() > 1e-3);  // it did turn
}

}  // namespace
}  // namespace hb
