#include "hapticbench/proxy/penalty_contact.h"

#include <catch2/catch.hpp>

#include "hapticbench/proxy/integrator.h"
#include "hapticbench/proxy/virtual_coupling.h"
#include "tests/support/proxy_fixtures.h"

namespace hb {
namespace {

TEST_CASE("penalty contact pushes along the normal by k d minus normal damping", "[penalty]") {
  ContactPlane plane;
  plane.tool_point = Vec3(0.01, 0.02, -0.03);
  plane.plane_point = Vec3(0, 0, 0.1);
  plane.normal = Vec3(0, 0.6, 0.8);
  RigidBodyState state;
  state.q = Quat(Eigen::AngleAxisd(0.5, Vec3::UnitY()));
  state.v = Vec3(0, -0.1, -0.2);
  state.w = Vec3(0.3, 0, 1);
  const Vec3 lever = state.q.toRotationMatrix() * plane.tool_point;
  // Put the tool point 4 mm below the plane along the normal.
  state.x =
      plane.plane_point - 0.004 * plane.normal - lever + Vec3(0.05, 0, 0);  // slid along the plane
  const PenaltyGains gains{3000, 2};

  CHECK(contact_depth(plane, state) == Approx(0.004).epsilon(1e-12));
  const ForceEvaluation f = evaluate_penalty_contact(plane, gains, state, false);
  const double normal_speed = plane.normal.dot(state.v + state.w.cross(lever));
  const Vec3 expected = (3000 * 0.004 - 2 * normal_speed) * plane.normal;
  CHECK((f.wrench.force - expected).norm() < 1e-12);
  CHECK((f.wrench.torque - lever.cross(expected)).norm() < 1e-12);

  // Moved 1 mm above the plane: no force at all.
  state.x += 0.005 * plane.normal;
  const ForceEvaluation free = evaluate_penalty_contact(plane, gains, state, true);
  CHECK(test::as_vector(free.wrench).norm() == 0);
  CHECK(free.stiffness.norm() == 0);
  CHECK(free.damping.norm() == 0);
}

TEST_CASE("penalty contact only pushes: leaving faster than k d / b, nothing acts", "[penalty]") {
  ContactPlane plane;  // the plane z = 0, the tool point at the centre of mass
  const PenaltyGains gains{3000, 50};
  RigidBodyState state;
  state.x = Vec3(0, 0, -0.002);                    // 2 mm deep: k d = 6 N
  const double release_speed = 3000 * 0.002 / 50;  // 0.12 m/s
  state.v = Vec3(0.01, 0, 0.9 * release_speed);    // leaving, slower than that
  ForceEvaluation f = evaluate_penalty_contact(plane, gains, state, true);
  CHECK(f.wrench.force.z() == Approx(6 - 50 * 0.9 * release_speed).epsilon(1e-12));
  CHECK(f.damping(2, 2) == Approx(-50).epsilon(1e-12));
  state.v.z() = 1.1 * release_speed;  // faster: unclamped, it would pull with 0.6 N
  f = evaluate_penalty_contact(plane, gains, state, true);
  CHECK(test::as_vector(f.wrench).norm() == 0);
  CHECK(f.stiffness.norm() == 0);
  CHECK(f.damping.norm() == 0);
}

TEST_CASE("penalty contact Jacobians match central differences", "[penalty]") {
  ContactPlane plane;
  plane.tool_point = Vec3(0.03, -0.01, 0.02);
  plane.plane_point = Vec3(0.01, 0.02, 0.0);
  plane.normal = Vec3(0.2, -0.3, 1).normalized();
  RigidBodyState state;
  state.q = Quat(Eigen::AngleAxisd(1.1, Vec3(1, -2, 0.5).normalized()));
  state.v = Vec3(0.05, 0.02, -0.1);
  state.w = Vec3(1.5, -2, 0.7);
  const Vec3 lever = state.q * plane.tool_point;
  state.x = plane.plane_point - 0.003 * plane.normal - lever;
  const PenaltyGains gains{3000, 2};

  const ForceEvaluation f = evaluate_penalty_contact(plane, gains, state, true);
  REQUIRE(f.wrench.force.norm() > 1);
  const auto numeric = test::numeric_jacobian(
      [&](const RigidBodyState& s) {
        return evaluate_penalty_contact(plane, gains, s, false).wrench;
      },
      state);
  const auto analytic = test::analytic_jacobian(f);
  INFO("analytic\n" << analytic << "\nnumeric\n" << numeric);
  CHECK((analytic - numeric).norm() <= 1e-6 * numeric.norm());
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

namespace hb {
namespace {

// One implicit step of a 50 g point proxy under the coupling to `device_z`,
// with or without a penalty contact against the plane z = 0.
RigidBodyState step_against_plane(const RigidBodyState& start, double device_z, bool with_contact,
                                  const PenaltyGains& gains) {
  RigidBody body;
  body.mass_kg = 0.05;
  body.inertia_body = 1e-5 * Mat3::Identity();
  const ContactPlane plane;  // z = 0, the tool point at the centre of mass
  PenaltyPlaneForces contact;
  contact.use(std::span<const ContactPlane>(&plane, 1), gains);
  Pose device;
  device.p = Vec3(0, 0, device_z);
  CouplingWithContacts forces(CouplingForce(CouplingGains{2000, 5, 5, 0.05}, body, device, Twist{}),
                              with_contact ? &contact : nullptr);
  return implicit_euler_step(body, start, forces, 1e-3);
}

TEST_CASE("over an implicit step a penalty contact pushes or lets go, never pulls", "[penalty]") {
  // 0.2 mm deep, the coupling pulling the proxy out: the linearised law
  // integrated over the whole tick ends below zero (k d is used up within
  // the tick while the damping term grows), which applied a pull of
  // −0.29 N before the contact was released on it.
  const PenaltyGains gains{3000, 2};
  for (const double speed : {0.0, 0.02, 0.1}) {  // leaving at these speeds, m/s
    RigidBodyState start;
    start.x = Vec3(0, 0, -0.0002);
    start.v = Vec3(0, 0, speed);
    INFO("leaving at " << speed << " m/s");
    const RigidBodyState free = step_against_plane(start, 0.01, false, gains);
    const RigidBodyState pressed = step_against_plane(start, 0.01, true, gains);
    // A contact that only pushes can only speed the proxy's way out.
    CHECK(pressed.v.z() >= free.v.z() - 1e-12);
  }
  // Approaching, it pushes back as before (no release).
  RigidBodyState approaching;
  approaching.x = Vec3(0, 0, -0.0002);
  approaching.v = Vec3(0, 0, -0.05);
  const RigidBodyState free = step_against_plane(approaching, -0.01, false, gains);
  const RigidBodyState pressed = step_against_plane(approaching, -0.01, true, gains);
  CHECK(pressed.v.z() > free.v.z() + 1e-3);
}

}  // namespace
}  // namespace hb
