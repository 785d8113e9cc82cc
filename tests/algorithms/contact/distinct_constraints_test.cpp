// Repeated constraints (a tile corner each of four tiles makes) are solved
// once: the search finds exactly the repeats, bit for bit, and the
// constrained step with them merged is the step of the same contacts when
// nothing can be merged.
#include "algorithms/contact/distinct_constraints.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "algorithms/contact/constrained_step.h"
#include "hapticbench/input_error.h"

namespace hb {
namespace {

// A 6 × 6 grid of tile corners (1 cm apart) under a tool face 2 cm below
// its centre of mass, slightly tilted so that the corners' bounds differ;
// every corner is listed `copies` times, the copies spread through the list
// as the tiles that share it are: constraint k is corner (k / 2) mod 36, so
// corner c comes first at 2c, then at 2c + 1, 72 + 2c, 73 + 2c.
std::vector<GaussConstraint> tile_corners(int copies) {
  std::vector<GaussConstraint> constraints;
  for (int k = 0; k < 36 * copies; ++k) {
    const int corner = (k / 2) % 36;
    const double x = 0.01 * (corner / 6 - 2.5), y = 0.01 * (corner % 6 - 2.5);
    constraints.push_back(
        GaussConstraint{Vec3::UnitZ(), Vec3(x, y, -0.02), 1e-5 * (0.3 * x - 0.2 * y)});
  }
  return constraints;
}

// Whether constraint k of tile_corners is a copy of one listed before it.
bool is_copy(std::size_t k) { return k % 2 == 1 || k >= 72; }

// The same constraints with every copy moved by one unit in the last place
// of its bound: no longer equal, so none is merged.
std::vector<GaussConstraint> nudged_apart(std::vector<GaussConstraint> constraints) {
  for (std::size_t k = 0; k < constraints.size(); ++k)
    if (is_copy(k)) constraints[k].rhs = std::nextafter(constraints[k].rhs, 1.0);
  return constraints;
}

Mat6 coupling_metric() {
  Mat6 metric = Mat6::Identity();
  metric.block<3, 3>(0, 0) *= 2000;
  metric.block<3, 3>(3, 3) *= 5;
  return metric;
}

}  // namespace

TEST_CASE("the repeats found are exactly the equal constraints") {
  std::vector<GaussConstraint> constraints = tile_corners(3);  // 108, 36 distinct
  std::vector<double> friction(constraints.size(), 0.5);
  // Not repeats: another μ, and a bound of −0 where the first has +0 (the
  // other copies of corner 0 keep +0).
  friction[15] = 0.4;  // corner 7's second
  constraints[0].rhs = 0.0;
  constraints[1].rhs = -0.0;
  constraints[72].rhs = 0.0;
  constraints[73].rhs = 0.0;
  DistinctConstraints distinct;
  REQUIRE(distinct.reduce(constraints, friction));
  REQUIRE(distinct.constraints().size() == 38);
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    const int d = distinct.distinct_of(static_cast<int>(k));
    const auto first = static_cast<std::size_t>(distinct.first_of(d));
    CHECK(first <= k);
    CHECK(constraints[first].lever == constraints[k].lever);
    CHECK(std::signbit(constraints[first].rhs) == std::signbit(constraints[k].rhs));
    CHECK(friction[first] == friction[k]);
    CHECK(distinct.friction()[static_cast<std::size_t>(d)] == friction[k]);
  }
  CHECK(distinct.distinct_of(1) != distinct.distinct_of(0));
  CHECK(distinct.distinct_of(72) == distinct.distinct_of(0));
  CHECK(distinct.distinct_of(15) != distinct.distinct_of(14));
  CHECK(distinct.distinct_of(86) == distinct.distinct_of(14));
  CHECK(distinct.first_of(distinct.distinct_of(86)) == 14);

  SECTION("no repeats, or too few constraints to look") {
    std::vector<GaussConstraint> once;
    for (std::size_t k = 0; k < 72; k += 2) once.push_back(constraints[k + 2]);
    CHECK_FALSE(distinct.reduce(once, {}));
    const std::vector<GaussConstraint> few(constraints.begin() + 2, constraints.begin() + 34);
    CHECK_FALSE(distinct.reduce(few, {}));  // 32, 16 of them copies: not looked for
  }
}

// One solve of the repeated constraints and one of the same contacts
// nudged apart, each by its own solver; solve(solver, constraints, active).
struct TwoSteps {
  ConstrainedStep merged, unmerged;
  std::vector<int> merged_active;
};
template <class Solve>
TwoSteps solve_both(const std::vector<GaussConstraint>& repeated, Solve&& solve) {
  TwoSteps steps;
  ConstrainedStepSolver merged_solver, apart_solver;
  std::vector<int> apart_active;
  steps.merged = solve(merged_solver, repeated, steps.merged_active);
  steps.unmerged = solve(apart_solver, nudged_apart(repeated), apart_active);
  return steps;
}

TEST_CASE("a step with repeated constraints merged is the step of the contacts unmerged") {
  const std::vector<GaussConstraint> repeated = tile_corners(4);
  const std::vector<GaussConstraint> apart = nudged_apart(repeated);
  const Mat6 metric = coupling_metric();
  Vec6 unconstrained;
  unconstrained << 0.002, -0.001, -0.004, 0.02, -0.03, 0.01;  // pressed in, pushed and turned
  for (const double mu : {0.0, 0.6}) {
    CAPTURE(mu);
    const std::vector<double> friction(repeated.size(), mu);
    const TwoSteps steps = solve_both(
        repeated, [&](ConstrainedStepSolver& solver,
                      const std::vector<GaussConstraint>& constraints, std::vector<int>& active) {
          return solver.solve(metric, unconstrained, constraints, friction, active);
        });
    const ConstrainedStep& merged = steps.merged;
    REQUIRE(merged.feasible);
    REQUIRE(steps.unmerged.feasible);
    CHECK((merged.step - steps.unmerged.step).norm() <= 1e-12 * unconstrained.norm());
    REQUIRE(merged.impulses.size() == repeated.size());
    // The first of equal constraints carries the impulse, its copies none;
    // the total wrench is the unmerged one's.
    Vec6 merged_wrench = Vec6::Zero(), unmerged_wrench = Vec6::Zero();
    for (std::size_t k = 0; k < repeated.size(); ++k) {
      if (is_copy(k)) CHECK(merged.impulses[k].isZero(0));
      merged_wrench += merged.impulses[k].x() * constraint_row(repeated[k]);
      unmerged_wrench += steps.unmerged.impulses[k].x() * constraint_row(apart[k]);
    }
    if (mu == 0) CHECK((merged_wrench - unmerged_wrench).norm() <= 1e-9 * unmerged_wrench.norm());
    for (const int k : steps.merged_active)  // first occurrences, by their own index
      CHECK_FALSE(is_copy(static_cast<std::size_t>(k)));

    // Warm-started from its own result: the same step again, to the
    // sweeps' tolerance (1e-9 per contact).
    ConstrainedStepSolver solver;
    std::vector<int> active = steps.merged_active;
    const ConstrainedStep& again =
        solver.solve(metric, unconstrained, repeated, friction, active, merged.impulses);
    CHECK((again.step - merged.step).norm() <= 1e-8);
  }

  SECTION("an implicit step's system, not symmetric") {
    Mat6 system = coupling_metric();
    system(3, 4) += 0.5;
    system(4, 3) -= 0.5;
    const std::vector<double> friction(repeated.size(), 0.3);
    const TwoSteps steps = solve_both(
        repeated, [&](ConstrainedStepSolver& solver,
                      const std::vector<GaussConstraint>& constraints, std::vector<int>& active) {
          return solver.solve_system(system, unconstrained, constraints, friction, active);
        });
    CHECK((steps.merged.step - steps.unmerged.step).norm() <= 1e-12 * unconstrained.norm());
  }
}

TEST_CASE("a bad repeated constraint is named by its own index") {
  std::vector<GaussConstraint> constraints = tile_corners(3);
  constraints[100].normal = Vec3(0, 0, 2);  // after 64 copies that are merged
  ConstrainedStepSolver solver;
  std::vector<int> active;
  CHECK_THROWS_WITH(solver.solve(coupling_metric(), Vec6::Zero(), constraints, {}, active),
                    Catch::Contains("constraints[100].normal"));

  SECTION("a warm-start index out of range, after copies") {
    constraints[100].normal = Vec3::UnitZ();
    active = {3, 90, -1};
    CHECK_THROWS_WITH(solver.solve(coupling_metric(), Vec6::Zero(), constraints, {}, active),
                      Catch::Contains("warm_active[2]"));
  }
}

}  // namespace hb
