// The frictional constrained step: stopped by its sweep limit, it still
// returns a feasible step that moves the proxy (never a freeze).
#include "algorithms/god_object/constrained_step.h"

#include <catch2/catch.hpp>
#include <vector>

namespace hb {
namespace {

TEST_CASE("a frictional step stopped by its sweep limit is feasible and moves") {
  // A 4 cm face resting on the plane z = 0 at its four corners (centre of
  // mass 2 cm above), μ = 0.8, pulled sideways and down: the sweeps need
  // more than one pass to settle the stick–slip split.
  std::vector<GaussConstraint> constraints;
  for (double x : {-0.02, 0.02})
    for (double y : {-0.02, 0.02})
      constraints.push_back(GaussConstraint{Vec3::UnitZ(), Vec3(x, y, -0.02), 0});
  const std::vector<double> friction(constraints.size(), 0.8);
  Mat6 metric = Mat6::Identity();
  metric.block<3, 3>(0, 0) *= 2000;  // k_t
  metric.block<3, 3>(3, 3) *= 5;     // k_r
  Vec6 unconstrained;
  unconstrained << 0.004, 0.001, -0.003, 0.02, -0.05, 0.01;
  for (int sweeps : {1, 300}) {
    INFO(sweeps << " sweeps");
    ConstrainedStepSolver solver(FrictionalContactOptions{sweeps, 1e-12});
    std::vector<int> active;
    const ConstrainedStep& step =
        solver.solve(metric, unconstrained, constraints, friction, active);
    CHECK(step.feasible);
    if (sweeps == 1) CHECK_FALSE(step.converged);
    for (const GaussConstraint& c : constraints)
      CHECK(constraint_row(c).dot(step.step) >= c.rhs - 1e-12);
    CHECK(step.step.head<2>().norm() > 1e-4);  // it slid: friction 0.8 cannot hold this pull
  }
}

}  // namespace
}  // namespace hb
