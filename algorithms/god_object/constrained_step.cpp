#include "algorithms/god_object/constrained_step.h"

#include <algorithm>

namespace hb {

ConstrainedStepSolver::ConstrainedStepSolver(const FrictionalContactOptions& options)
    : frictional_(options) {}

const ConstrainedStep& ConstrainedStepSolver::solve(const Mat6& metric, const Vec6& unconstrained,
                                                    std::span<const GaussConstraint> constraints,
                                                    std::span<const double> friction,
                                                    std::vector<int>& warm_active,
                                                    std::span<const Vec3> warm_impulses) {
  ConstrainedStep& r = result_;
  r.step = unconstrained;
  r.impulses.assign(constraints.size(), Vec3::Zero());
  r.iterations = 0;
  r.converged = true;
  r.with_friction = std::any_of(friction.begin(), friction.end(), [](double mu) { return mu > 0; });
  if (constraints.empty()) return r;

  const bool seed_from_qp = !r.with_friction || warm_impulses.size() != constraints.size();
  if (seed_from_qp) {
    std::erase_if(warm_active, [&](int k) { return k >= static_cast<int>(constraints.size()); });
    const GaussSolution& solution = gauss_.solve(metric, unconstrained, constraints, warm_active);
    r.iterations = solution.iterations;
    r.converged = solution.converged;
    warm_active = solution.converged ? solution.active : std::vector<int>{};
    r.step = solution.acceleration;
    for (std::size_t k = 0; k < constraints.size(); ++k)
      r.impulses[k].x() = solution.multipliers[k];
    if (!r.with_friction) return r;
  }

  rows_.clear();
  for (std::size_t k = 0; k < constraints.size(); ++k)
    rows_.push_back(FrictionalContactRow{constraints[k].normal, constraints[k].lever,
                                         constraints[k].rhs, friction[k]});
  if (seed_from_qp)
    seed_ = r.impulses;
  else
    seed_.assign(warm_impulses.begin(), warm_impulses.end());
  const Mat6 response = metric.inverse();
  const FrictionalContactSolution& solution =
      frictional_.solve(response, unconstrained, rows_, seed_);
  r.iterations += solution.sweeps;
  r.impulses = solution.impulses;

  // Non-penetration exactly: the frictionless QP again with the friction
  // impulses held as given forces (one step of staggered projections).
  Vec6 friction_wrench = Vec6::Zero();
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    const Vec3 t1 = solution.tangent1[k];
    const Vec3 t2 = constraints[k].normal.cross(t1);
    const Vec3 force = solution.impulses[k].y() * t1 + solution.impulses[k].z() * t2;
    friction_wrench.head<3>() += force;
    friction_wrench.tail<3>() += constraints[k].lever.cross(force);
  }
  std::erase_if(warm_active, [&](int k) { return k >= static_cast<int>(constraints.size()); });
  const GaussSolution& projected =
      gauss_.solve(metric, unconstrained + response * friction_wrench, constraints, warm_active);
  r.iterations += projected.iterations;
  r.converged = solution.converged && projected.converged;
  warm_active = projected.converged ? projected.active : std::vector<int>{};
  r.step = projected.acceleration;
  for (std::size_t k = 0; k < constraints.size(); ++k) r.impulses[k].x() = projected.multipliers[k];
  return r;
}

}  // namespace hb
