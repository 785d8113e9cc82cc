// The frictional constrained step: stopped by its sweep limit, it still
// returns a feasible step that moves the proxy (never a freeze); on a
// planar contact of many points and when its sweeps are cut short,
// friction stays in Coulomb's cone and the residual says how close the step
// is to Coulomb's law.
#include "algorithms/contact/constrained_step.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

namespace hb {
namespace {

// The god-object's quasi-static problem: metric K = diag(k_t I, k_r I).
Mat6 coupling_metric(double k_t, double k_r) {
  Mat6 metric = Mat6::Identity();
  metric.block<3, 3>(0, 0) *= k_t;
  metric.block<3, 3>(3, 3) *= k_r;
  return metric;
}

// The skew-symmetric pattern of a spin's gyroscopic Jacobian (unitless).
Mat3 spin_matrix() {
  Mat3 spin;
  spin << 0, -0.8, -0.5, 0.8, 0, 0.3, 0.5, -0.3, 0;
  return spin;
}

// A 64 g cube's implicit-step matrix at 1 kHz (mass and inertia plus
// Δt b + Δt² k on the diagonal) with `gyroscopic` times spin_matrix() on
// its rotational block.
Mat6 spinning_cube_system(double gyroscopic) {
  Mat6 system = Mat6::Zero();
  system.diagonal() << 0.071, 0.071, 0.071, 6.9e-5, 7.2e-5, 7.0e-5;
  system.block<3, 3>(3, 3) += gyroscopic * spin_matrix();
  return system;
}

// One frictional solve with at most `sweeps` Gauss–Seidel sweeps.
ConstrainedStep solve_with_sweeps(int sweeps, const Mat6& metric, const Vec6& unconstrained,
                                  const std::vector<GaussConstraint>& constraints,
                                  const std::vector<double>& friction) {
  ConstrainedStepSolver solver(FrictionalContactSettings{sweeps, 1e-12});
  std::vector<int> active;
  return solver.solve(metric, unconstrained, constraints, friction, active);
}

TEST_CASE("a frictional step stopped by its sweep limit is feasible and moves") {
  // A 4 cm face resting on the plane z = 0 at its four corners (centre of
  // mass 2 cm above), μ = 0.8, pulled sideways and down: the sweeps need
  // more than one pass to settle the stick–slip split.
  std::vector<GaussConstraint> constraints;
  for (double x : {-0.02, 0.02})
    for (double y : {-0.02, 0.02})
      constraints.push_back(GaussConstraint{Vec3::UnitZ(), Vec3(x, y, -0.02), 0});
  const std::vector<double> friction(constraints.size(), 0.8);
  const Mat6 metric = coupling_metric(2000, 5);
  Vec6 unconstrained;
  unconstrained << 0.004, 0.001, -0.003, 0.02, -0.05, 0.01;
  for (int sweeps : {1, 300}) {
    INFO(sweeps << " sweeps");
    const ConstrainedStep step =
        solve_with_sweeps(sweeps, metric, unconstrained, constraints, friction);
    CHECK(step.feasible);
    if (sweeps == 1) CHECK_FALSE(step.converged);
    for (const GaussConstraint& c : constraints)
      CHECK(constraint_row(c).dot(step.step) >= c.rhs - 1e-12);
    CHECK(step.step.head<2>().norm() > 1e-4);  // it slid: friction 0.8 cannot hold this pull
  }
}

TEST_CASE("a ring contact of twelve points slides with exactly mu times its normal force") {
  // Twelve points on a 2 cm circle in the plane z = 0, the centre of mass
  // 2.3 cm above, μ = 0.8; the coupling (1,000 N/m) presses 6 N down and
  // pulls 10 N along x, more than friction can hold. All twelve are hull
  // vertices: the sweeps see them all, the tool slides with friction
  // μ F_n, and the ring's symmetry about the x–z plane leaves no yaw.
  constexpr double kMu = 0.8;
  std::vector<GaussConstraint> constraints;
  for (int i = 0; i < 12; ++i) {
    const double angle = 2 * std::numbers::pi * i / 12;
    constraints.push_back(GaussConstraint{
        Vec3::UnitZ(), Vec3(0.02 * std::cos(angle), 0.02 * std::sin(angle), -0.023), 0});
  }
  const std::vector<double> friction(constraints.size(), kMu);
  const Mat6 metric = coupling_metric(1000, 2);
  Vec6 unconstrained;
  unconstrained << 0.01, 0, -0.006, 0, 0, 0;
  const ConstrainedStep step = solve_with_sweeps(300, metric, unconstrained, constraints, friction);
  REQUIRE(step.feasible);
  // The contact force is the coupling's: K (a − a^u), translational part.
  const Vec3 force = 1000 * (step.step.head<3>() - unconstrained.head<3>());
  const double normal = force.z(), tangential = force.head<2>().norm();
  INFO("normal " << normal << " N, friction " << tangential << " N, yaw " << step.step(5));
  CHECK(normal > 5.9);
  CHECK(tangential <= kMu * normal * (1 + 1e-6));
  CHECK(tangential >= kMu * normal * (1 - 1e-3));
  CHECK(std::abs(step.step(5)) < 1e-9);  // no spurious yaw
  CHECK(step.coulomb_residual < 1e-6);
  for (const GaussConstraint& c : constraints)
    CHECK(constraint_row(c).dot(step.step) >= c.rhs - 1e-9);
}

TEST_CASE("friction stays in the cone when the sweeps stop early or leave rows out") {
  // A 6 × 6 grid of coplanar points (the sweeps keep the four corners,
  // the hull's vertices; the others are left to the QP) under a tilting
  // pull: however few sweeps run, the step holds every constraint, the
  // total friction never exceeds μ times the total normal force, the
  // contact wrench does no positive work (the normal forces do none, so
  // friction dissipates), and a converged solve is on Coulomb's law.
  constexpr double kMu = 0.5;
  std::vector<GaussConstraint> constraints;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      constraints.push_back(
          GaussConstraint{Vec3::UnitZ(), Vec3(-0.02 + 0.008 * i, -0.02 + 0.008 * j, -0.03), 0});
  const std::vector<double> friction(constraints.size(), kMu);
  const Mat6 metric = coupling_metric(2000, 5);
  Vec6 unconstrained;
  unconstrained << 0.004, 0.002, -0.003, 0.03, -0.06, 0.02;
  for (int sweeps : {1, 3, 10, 1000}) {
    INFO(sweeps << " sweeps");
    const ConstrainedStep step =
        solve_with_sweeps(sweeps, metric, unconstrained, constraints, friction);
    REQUIRE(step.feasible);
    for (const GaussConstraint& c : constraints)
      CHECK(constraint_row(c).dot(step.step) >= c.rhs - 1e-9);
    const Vec3 force = 2000 * (step.step.head<3>() - unconstrained.head<3>());
    CHECK(force.head<2>().norm() <= kMu * force.z() * (1 + 1e-9));
    const Vec6 contact_wrench = metric * (step.step - unconstrained);
    CHECK(contact_wrench.dot(step.step) <= 1e-12);
    if (step.converged) CHECK(step.coulomb_residual < kCoulombResidualTolerance);
    if (sweeps == 1000) CHECK(step.converged);
  }
}

TEST_CASE("a non-symmetric system is solved with its full matrix, as its closed form") {
  // A 64 g cube's implicit step at 1 kHz with the smoke suite's coupling
  // (k_t 2,000 N/m, b_t 5 N·s/m, k_r 5 N·m/rad, b_r 0.05 N·m·s/rad): mass
  // and inertia plus Δt b + Δt² k on the diagonal, and the parts that are
  // not symmetric: the gyroscopic Jacobian of a 20 rad/s spin and half the
  // cross product of a 2.5 N·m coupling torque (Δt² ½ [τ]×), a few per cent
  // of the rotational diagonal. One contact, pushed into: the exact answer
  // is λ = (b − J a_u) / (J A⁻¹ Jᵀ), a = a_u + A⁻¹ Jᵀ λ.
  Mat6 system = spinning_cube_system(2.5e-6);
  const Mat3 spin = spin_matrix();
  Mat3 cross;
  cross << 0, 2e-6, -1e-6, 1e-6, 0, 3e-6, -2e-6, 1e-6, 0;
  system.block<3, 3>(0, 3) += cross;
  system.block<3, 3>(3, 0) -= cross.transpose();
  const GaussConstraint contact{Vec3(0.1, -0.2, 1).normalized(), Vec3(0.03, 0.01, -0.02), 0.001};
  Vec6 unconstrained;
  unconstrained << 0.01, 0.0, -0.02, 0.5, -0.3, 0.2;
  const Eigen::Matrix<double, 1, 6> row = constraint_row(contact).transpose();
  REQUIRE(row.dot(unconstrained) < contact.rhs);  // pushed into the contact
  const Vec6 response_row = system.partialPivLu().solve(row.transpose());
  const double impulse = (contact.rhs - row.dot(unconstrained)) / row.dot(response_row);
  const Vec6 exact = unconstrained + impulse * response_row;

  const std::vector<GaussConstraint> constraints{contact};
  ConstrainedStepSolver solver;
  std::vector<int> active;
  const Vec6 step = solver.solve_system(system, unconstrained, constraints, {}, active).step;
  INFO(
      "passes " << solver.solve_system(system, unconstrained, constraints, {}, active).skew_passes);
  CHECK((step - exact).norm() <= 1e-5 * (exact - unconstrained).norm());
  CHECK(row.dot(step) == Approx(contact.rhs).margin(1e-12));

  std::vector<int> symmetric_active;
  const Vec6 symmetric_step = solver
                                  .solve(0.5 * (system + system.transpose()), unconstrained,
                                         constraints, {}, symmetric_active)
                                  .step;
  CHECK((symmetric_step - exact).norm() > 1e-3 * (exact - unconstrained).norm());

  // A symmetric system takes one pass; so does a step the contact leaves
  // free. A strongly skewed one stops at the pass limit, feasible.
  std::vector<int> free_active;
  const Mat6 symmetric = 0.5 * (system + system.transpose());
  CHECK(solver.solve_system(symmetric, unconstrained, constraints, {}, free_active).skew_passes ==
        1);
  const GaussConstraint far{contact.normal, contact.lever, -1.0};
  const std::vector<GaussConstraint> loose{far};
  const ConstrainedStep& free_step =
      solver.solve_system(system, unconstrained, loose, {}, free_active);
  CHECK(free_step.skew_passes == 1);
  CHECK((free_step.step - unconstrained).norm() <= 1e-12);
  Mat6 skewed = system;
  skewed.block<3, 3>(3, 3) += 4e-5 * spin;
  const ConstrainedStep& skewed_step =
      solver.solve_system(skewed, unconstrained, constraints, {}, free_active);
  CHECK(skewed_step.skew_passes <= ConstrainedStepSolver::kSkewPasses);
  CHECK(row.dot(skewed_step.step) >= contact.rhs - 1e-12);
}

TEST_CASE("a frictional non-symmetric solve after another gives what a new solver gives") {
  // The skew passes of one solve share its contact rows; nothing of them
  // may reach the next solve. Two problems with friction on one solver, in
  // turn and again, each exactly as a solver of its own solves it.
  const Mat6 system = spinning_cube_system(2.5e-5);
  Vec6 unconstrained;
  unconstrained << 0.01, 0.004, -0.02, 0.5, -0.3, 0.2;
  // A 5 × 5 face on a plane (rows reduced to the hull's corners) and a
  // tilted face of 3 × 3.
  std::vector<GaussConstraint> flat, tilted;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      flat.push_back(
          GaussConstraint{Vec3::UnitZ(), Vec3(-0.02 + 0.01 * i, -0.02 + 0.01 * j, -0.03), 0});
  const Vec3 normal = Vec3(0.3, -0.1, 1).normalized();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      tilted.push_back(
          GaussConstraint{normal, Vec3(-0.01 + 0.01 * i, 0.01 * j, -0.025), -0.0005 * i});
  const std::vector<double> flat_mu(flat.size(), 0.5), tilted_mu(tilted.size(), 0.3);

  const auto fresh = [&](const std::vector<GaussConstraint>& c, const std::vector<double>& mu) {
    ConstrainedStepSolver solver;
    std::vector<int> active;
    return solver.solve_system(system, unconstrained, c, mu, active);
  };
  const ConstrainedStep flat_alone = fresh(flat, flat_mu);
  const ConstrainedStep tilted_alone = fresh(tilted, tilted_mu);
  REQUIRE(flat_alone.skew_passes > 1);
  REQUIRE(tilted_alone.skew_passes > 1);
  ConstrainedStepSolver shared;
  for (int round = 0; round < 2; ++round) {
    std::vector<int> flat_active, tilted_active;
    const ConstrainedStep flat_step =
        shared.solve_system(system, unconstrained, flat, flat_mu, flat_active);
    CHECK(flat_step.step == flat_alone.step);
    CHECK(flat_step.impulses == flat_alone.impulses);
    const ConstrainedStep tilted_step =
        shared.solve_system(system, unconstrained, tilted, tilted_mu, tilted_active);
    CHECK(tilted_step.step == tilted_alone.step);
    CHECK(tilted_step.impulses == tilted_alone.impulses);
    // The symmetric solve of the same solver builds its own rows as well.
    std::vector<int> active;
    ConstrainedStepSolver other;
    std::vector<int> other_active;
    const Mat6 symmetric = 0.5 * (system + system.transpose());
    CHECK(shared.solve(symmetric, unconstrained, flat, flat_mu, active).step ==
          other.solve(symmetric, unconstrained, flat, flat_mu, other_active).step);
  }
}

TEST_CASE("a solver that keeps its metric's factors solves as a new one when the metric changes") {
  // Four corners of a face pressed and pulled, with and without friction;
  // the metrics alternate, one of them one unit in the last place off in a
  // single entry (a kept factorisation of the other would show).
  std::vector<GaussConstraint> constraints;
  for (double x : {-0.02, 0.02})
    for (double y : {-0.02, 0.02})
      constraints.push_back(GaussConstraint{Vec3::UnitZ(), Vec3(x, y, -0.02), 0});
  Vec6 unconstrained;
  unconstrained << 0.003, -0.001, -0.002, 0.02, 0.01, -0.03;
  const Mat6 metric = coupling_metric(2000, 5);
  Mat6 nudged = metric;
  nudged(3, 3) = std::nextafter(nudged(3, 3), 10.0);
  Mat6 other = coupling_metric(1500, 3);
  other(0, 4) = other(4, 0) = 0.2;  // a centre of mass off the frame
  for (const double mu : {0.0, 0.6}) {
    CAPTURE(mu);
    const std::vector<double> friction(constraints.size(), mu);
    ConstrainedStepSolver shared;
    for (const Mat6* m :
         std::vector<const Mat6*>{&metric, &nudged, &other, &metric, &metric, &nudged}) {
      ConstrainedStepSolver fresh;
      std::vector<int> shared_active, fresh_active;
      const ConstrainedStep step =
          shared.solve(*m, unconstrained, constraints, friction, shared_active);
      const ConstrainedStep& alone =
          fresh.solve(*m, unconstrained, constraints, friction, fresh_active);
      CHECK(step.step == alone.step);
      CHECK(step.impulses == alone.impulses);
    }
  }
}

}  // namespace
}  // namespace hb
