#include "algorithms/god_object/constrained_step.h"

#include <algorithm>

namespace hb {

const ConstrainedStep& ConstrainedStepSolver::solve(const Mat6& metric, const Vec6& unconstrained,
                                                    std::span<const GaussConstraint> constraints,
                                                    std::span<const double> friction,
                                                    std::vector<int>& warm_active) {
  ConstrainedStep& r = result_;
  r = ConstrainedStep{unconstrained, 0, true};
  if (constraints.empty()) return r;
  const bool frictionless =
      std::all_of(friction.begin(), friction.end(), [](double mu) { return mu <= 0; });
  if (frictionless) {
    std::erase_if(warm_active, [&](int k) { return k >= static_cast<int>(constraints.size()); });
    const GaussSolution& solution = gauss_.solve(metric, unconstrained, constraints, warm_active);
    r.iterations = solution.iterations;
    r.converged = solution.converged;
    warm_active = solution.converged ? solution.active : std::vector<int>{};
    r.step = solution.converged ? solution.acceleration : Vec6::Zero();
    return r;
  }
  warm_active.clear();
  rows_.clear();
  for (std::size_t k = 0; k < constraints.size(); ++k)
    rows_.push_back(FrictionalContactRow{constraints[k].normal, constraints[k].lever,
                                         constraints[k].rhs, friction[k]});
  const FrictionalContactSolution& solution =
      frictional_.solve(metric.inverse(), unconstrained, rows_);
  r.iterations = solution.sweeps;
  r.converged = solution.converged;
  r.step = solution.converged ? solution.velocity : Vec6::Zero();
  return r;
}

}  // namespace hb
