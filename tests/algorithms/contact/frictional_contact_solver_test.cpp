// The frictional contact solver: stick and slip against the closed form of a
// block pushed along a plane, a box on a slope that holds or slides as μ is
// above or below tan(angle), the complementarity conditions on random
// problems and on a point pressed on a crease (in a few sweeps), the early
// stop at a clear stick, and determinism.
#include "algorithms/contact/frictional_contact_solver.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <span>
#include <vector>

namespace hb {
namespace {

// Response of a box of mass m (kg) and half extents h (m), about its centre.
Mat6 box_response(double mass_kg, const Vec3& half) {
  Mat6 response = Mat6::Zero();
  response.block<3, 3>(0, 0) = Mat3::Identity() / mass_kg;
  const double a = half.x() * half.x(), b = half.y() * half.y(), c = half.z() * half.z();
  const Vec3 inertia = mass_kg / 3.0 * Vec3(b + c, a + c, a + b);
  response.block<3, 3>(3, 3) = inertia.cwiseInverse().asDiagonal();
  return response;
}

// The four bottom corners of a box resting on the plane z = 0 (normal +z).
std::vector<FrictionalContactRow> bottom_corners(const Vec3& half, double mu) {
  std::vector<FrictionalContactRow> rows;
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0})
      rows.push_back({Vec3::UnitZ(), Vec3(sx * half.x(), sy * half.y(), -half.z()), 0.0, mu});
  return rows;
}

Vec3 total_impulse(const FrictionalContactSolution& s, std::span<const FrictionalContactRow> rows) {
  Vec3 total = Vec3::Zero();
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Vec3 t1 = s.tangent1[k];
    const Vec3 t2 = rows[k].normal.cross(t1);
    total += s.impulses[k].x() * rows[k].normal + s.impulses[k].y() * t1 + s.impulses[k].z() * t2;
  }
  return total;
}

TEST_CASE("a block pushed along a plane sticks below mu times the normal impulse and slides above",
          "[frictional_contact]") {
  const double mass = 2.0, mu = 0.5;
  const Vec3 half(0.05, 0.05, 0.05);
  const auto rows = bottom_corners(half, mu);
  FrictionalContactSolver solver;
  // Pressed into the plane at 1 m/s; the normal impulse that stops it is m·1 = 2 N·s.
  for (double push : {0.3, 0.9, 1.1, 3.0}) {
    const Vec6 free = (Vec6() << push, 0, -1.0, 0, 0, 0).finished();
    const FrictionalContactSolution& s = solver.solve(box_response(mass, half), free, rows);
    REQUIRE(s.converged);
    const Vec3 impulse = total_impulse(s, rows);
    CHECK(impulse.z() == Approx(mass * 1.0).epsilon(1e-6));
    CHECK(s.velocity(2) == Approx(0).margin(1e-8));
    if (push * mass <= mu * mass * 1.0) {  // stick: friction cancels the push
      CHECK(s.velocity(0) == Approx(0).margin(1e-8));
      CHECK(impulse.x() == Approx(-mass * push).epsilon(1e-6));
    } else {  // slip: friction is mu times the normal impulse, against the motion
      CHECK(impulse.x() == Approx(-mu * mass * 1.0).epsilon(1e-6));
      CHECK(s.velocity(0) == Approx(push - mu * 1.0).epsilon(1e-6));
    }
    CHECK(s.velocity.tail<3>().norm() == Approx(0).margin(1e-7));  // no tipping
  }
}

TEST_CASE("sliding in any direction meets the circular cone, not a pyramid",
          "[frictional_contact]") {
  const double mass = 1.0, mu = 0.4;
  const Vec3 half(0.05, 0.05, 0.05);
  const auto rows = bottom_corners(half, mu);
  FrictionalContactSolver solver;
  for (double angle = 0; angle < 2 * std::numbers::pi; angle += 0.3) {
    const Vec6 free = (Vec6() << 2 * std::cos(angle), 2 * std::sin(angle), -1, 0, 0, 0).finished();
    const FrictionalContactSolution& s = solver.solve(box_response(mass, half), free, rows);
    REQUIRE(s.converged);
    const Vec3 impulse = total_impulse(s, rows);
    CHECK(impulse.head<2>().norm() == Approx(mu * impulse.z()).epsilon(1e-6));
    CHECK(s.velocity.head<2>().normalized().dot(free.head<2>().normalized()) ==
          Approx(1).epsilon(1e-9));
  }
}

// A box on a plane tilted by `angle` (gravity g along −z of the world, the
// plane's frame used as the problem's frame): after `seconds` of 1 ms steps
// from rest, how far it slid down the slope (m).
double slide_on_slope(double angle, double mu, double seconds) {
  const double mass = 1.0, g = 9.81, dt = 1e-3;
  const Vec3 half(0.05, 0.03, 0.02);
  const Vec3 gravity(-g * std::sin(angle), 0, -g * std::cos(angle));  // plane frame, x downhill
  const auto rows = bottom_corners(half, mu);
  FrictionalContactSolver solver;
  Vec6 u = Vec6::Zero();
  double x = 0;
  std::vector<Vec3> warm;
  for (int i = 0; i < static_cast<int>(seconds / dt); ++i) {
    Vec6 free = u;
    free.head<3>() += dt * gravity;
    const FrictionalContactSolution& s = solver.solve(box_response(mass, half), free, rows, warm);
    REQUIRE(s.converged);
    warm = s.impulses;
    u = s.velocity;
    x += dt * u(0);
  }
  return -x;
}

TEST_CASE("a box on a slope holds when mu exceeds tan(angle) and slides at g(sin - mu cos) below",
          "[frictional_contact]") {
  const double angle = 20 * std::numbers::pi / 180, g = 9.81, seconds = 0.5;
  const double tan_angle = std::tan(angle);
  CHECK(std::abs(slide_on_slope(angle, tan_angle * 1.05, seconds)) < 1e-9);
  CHECK(std::abs(slide_on_slope(angle, 0.8, seconds)) < 1e-9);
  for (double mu : {0.0, 0.1, tan_angle * 0.95}) {
    const double acceleration = g * (std::sin(angle) - mu * std::cos(angle));
    // Explicit position update with the new velocity: x = a dt² n(n+1)/2.
    const int n = static_cast<int>(seconds / 1e-3);
    const double expected = acceleration * 1e-6 * n * (n + 1) / 2.0;
    CHECK(slide_on_slope(angle, mu, seconds) == Approx(expected).epsilon(1e-6));
  }
}

// Signorini and Coulomb at the solution, to `tolerance` (m/s or N·s):
// pressed contacts at their bound, the others clear of it; friction inside
// the disk, a contact inside it sticking, one on its circle opposing its slip.
void check_conditions(const FrictionalContactSolution& s,
                      std::span<const FrictionalContactRow> rows, double tolerance) {
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const FrictionalContactRow& c = rows[k];
    const Vec3 t1 = s.tangent1[k], t2 = c.normal.cross(t1);
    const Vec3 point_velocity = s.velocity.head<3>() + s.velocity.tail<3>().cross(c.lever);
    const double gap_rate = c.normal.dot(point_velocity) - c.bound;
    const Eigen::Vector2d slip(t1.dot(point_velocity), t2.dot(point_velocity));
    const Vec3& impulse = s.impulses[k];
    INFO("contact " << k);
    CHECK(impulse.x() >= 0);
    CHECK(gap_rate >= -tolerance);
    CHECK(std::abs(impulse.x() * gap_rate) <= tolerance);
    const double friction = impulse.tail<2>().norm();
    CHECK(friction <= c.friction * impulse.x() * (1 + 1e-9) + 1e-12);
    if (friction < c.friction * impulse.x() * (1 - 1e-6)) {
      CHECK(slip.norm() <= tolerance);  // inside the cone: stick
    } else if (slip.norm() > tolerance &&
               friction > 0) {  // on the cone and sliding: against the slip
      CHECK(impulse.tail<2>().normalized().dot(slip.normalized()) == Approx(-1).epsilon(1e-5));
    }
  }
}

TEST_CASE("random problems meet the complementarity conditions", "[frictional_contact]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  FrictionalContactSettings options;
  options.max_sweeps = 5000;
  options.tolerance = 1e-12;
  FrictionalContactSolver solver(options);
  for (int trial = 0; trial < 50; ++trial) {
    const int count = 1 + trial % 12;
    std::vector<FrictionalContactRow> rows;
    for (int k = 0; k < count; ++k) {
      const Vec3 normal = (Vec3::UnitZ() + 0.4 * Vec3(unit(rng), unit(rng), 0)).normalized();
      rows.push_back({normal, 0.1 * Vec3(unit(rng), unit(rng), unit(rng)), 0.01 * unit(rng),
                      0.5 * (1 + unit(rng))});
    }
    Mat6 random = Mat6::Zero();
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) random(i, j) = unit(rng);
    const Mat6 response = random * random.transpose() + 0.5 * Mat6::Identity();
    const Vec6 free =
        (Vec6() << unit(rng), unit(rng), -1, unit(rng), unit(rng), unit(rng)).finished();
    const FrictionalContactSolution& s = solver.solve(response, free, rows);
    INFO("trial " << trial << " with " << count << " contacts, sweeps " << s.sweeps);
    REQUIRE(s.converged);
    CHECK(s.residual <= options.tolerance);
    check_conditions(s, rows, 1e-6);
  }
}

TEST_CASE("a point pressed on two faces a few degrees apart converges in a few sweeps",
          "[frictional_contact]") {
  // A corner on a crease of two planes whose normals are `degrees` apart,
  // sliding on both, besides a second corner on a third plane: the normal
  // impulses of the crease push each other, and the sweeps alone took
  // 43 (2°) to 1,165 (20°) sweeps to a change of 1e-12.
  FrictionalContactSettings options;
  options.max_sweeps = 5000;
  options.tolerance = 1e-12;
  FrictionalContactSolver solver(options);
  const Vec3 corner(0.02, -0.03, -0.01);
  for (double degrees : {2.0, 4.0, 6.0, 10.0, 20.0}) {
    const double half_angle = 0.5 * degrees * std::numbers::pi / 180;
    const std::vector<FrictionalContactRow> rows = {
        {Vec3(0, std::sin(half_angle), std::cos(half_angle)), corner, 0, 0.3},
        {Vec3(0.05, -std::sin(half_angle), std::cos(half_angle)).normalized(), corner, 0, 0.3},
        {Vec3::UnitZ(), Vec3(-0.02, 0.03, -0.01), -0.002, 0.3}};
    const Vec6 free = (Vec6() << 0.3, 0.1, -1, 0.5, -0.2, 0.3).finished();
    const FrictionalContactSolution& s =
        solver.solve(box_response(1, Vec3(0.03, 0.04, 0.01)), free, rows);
    INFO(degrees << " degrees, sweeps " << s.sweeps);
    REQUIRE(s.converged);
    CHECK(s.sweeps <= 10);
    for (const Vec3& impulse : s.impulses) CHECK(impulse.x() > 0);  // every contact pressed
    check_conditions(s, rows, 1e-9);
  }
}

// Two contacts half a millimetre apart along one edge of a tilted peg, their
// normals 31 µrad apart, under the coupling's compliance (k_t = 2,000 N/m,
// k_r = 5 N·m/rad) as a displacement problem: nearly dependent, so the
// sweeps creep (the answer keeps changing by about 1e-12 m a sweep after
// 200 sweeps).
std::vector<FrictionalContactRow> peg_edge_contacts() {
  return {{Vec3(0, 0, 1), Vec3(0.005, -0.004, -0.0202), -1.6e-8, 0.3},
          {Vec3(-3.1e-5, 0, 1).normalized(), Vec3(0.0045, -0.004, -0.0202), -3.6e-12, 0.3}};
}

Mat6 coupling_compliance() {
  Mat6 response = Mat6::Zero();
  response.diagonal() << Vec3::Constant(1 / 2000.0), Vec3::Constant(1 / 5.0);
  return response;
}

Vec3 slip_of(const Vec6& u, const FrictionalContactRow& row) {
  const Vec3 v = u.head<3>() + u.tail<3>().cross(row.lever);
  return v - row.normal.dot(v) * row.normal;
}

TEST_CASE("sweeps asked to stop at a clear stick stop there and not where a contact slides",
          "[frictional_contact]") {
  const auto rows = peg_edge_contacts();
  FrictionalContactSolver full({200, 1e-12, 0}), early({200, 1e-12, 1e-7});
  SECTION("pressed and pulled along the edge well inside the cone: stuck, early") {
    const Vec6 free = (Vec6() << 6.3e-7, -5.6e-7, -2.0e-5, 2.8e-5, 3.1e-5, 0).finished();
    const FrictionalContactSolution reference = full.solve(coupling_compliance(), free, rows);
    const FrictionalContactSolution& s = early.solve(coupling_compliance(), free, rows);
    INFO("sweeps " << s.sweeps << " of " << reference.sweeps);
    CHECK_FALSE(reference.stuck);
    REQUIRE(s.stuck);
    CHECK_FALSE(s.converged);
    CHECK(s.sweeps < reference.sweeps);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      if (!(s.impulses[k].x() > 0)) continue;
      CHECK(slip_of(s.velocity, rows[k]).norm() <= 1e-7);
      CHECK(s.impulses[k].tail<2>().norm() <= kClearStickShare * 0.3 * s.impulses[k].x());
    }
    // The same motion as the sweeps' to within the slip allowed.
    CHECK((s.velocity.head<3>() - reference.velocity.head<3>()).norm() < 2e-7);
  }
  SECTION("pulled along the face past the cone: it slides, no early stop") {
    const Vec6 free = (Vec6() << 4e-5, 0, -2.0e-5, 0, 0, 0).finished();
    const FrictionalContactSolution& s = early.solve(coupling_compliance(), free, rows);
    CHECK_FALSE(s.stuck);
    double slip = 0;
    for (const FrictionalContactRow& row : rows)
      slip = std::max(slip, slip_of(s.velocity, row).norm());
    CHECK(slip > 1e-6);
  }
}

TEST_CASE("the solve is deterministic", "[frictional_contact]") {
  const auto rows = bottom_corners(Vec3(0.05, 0.04, 0.03), 0.3);
  const Vec6 free = (Vec6() << 0.7, -0.2, -1, 0.3, 0.1, 0).finished();
  FrictionalContactSolver a, b;
  const FrictionalContactSolution first =
      a.solve(box_response(1, Vec3(0.05, 0.04, 0.03)), free, rows);
  b.solve(box_response(3, Vec3(0.1, 0.1, 0.1)), free, rows);  // a different problem in between
  const FrictionalContactSolution& second =
      b.solve(box_response(1, Vec3(0.05, 0.04, 0.03)), free, rows);
  CHECK(first.velocity == second.velocity);
  CHECK(first.impulses == second.impulses);
  CHECK(first.sweeps == second.sweeps);
}

}  // namespace
}  // namespace hb
