#include "algorithms/god_object/constrained_step.h"

#include <algorithm>
#include <cmath>

namespace hb {

ConstrainedStepSolver::ConstrainedStepSolver(const FrictionalContactOptions& options)
    : frictional_(options), tolerance_(options.tolerance) {}

void ConstrainedStepSolver::reduce_coplanar_rows() {
  // Rows with one normal, one μ and about the same bound (a face resting on
  // a face) are one planar contact; beyond kKept of them the sweeps only
  // trade load between them. The extreme points along four directions of
  // the plane carry its normal load, friction and torque; the others are
  // left to the final QP, which holds every constraint.
  constexpr std::size_t kKept = 8;
  constexpr double kSameNormalCos = 1 - 1e-6;
  const double bound_tolerance = 1000 * tolerance_;
  group_of_.assign(rows_.size(), -1);
  group_first_.clear();
  for (std::size_t row = 0; row < rows_.size(); ++row) {
    std::size_t g = 0;
    for (; g < group_first_.size(); ++g) {
      const FrictionalContactRow& first = rows_[group_first_[g]];
      if (first.friction == rows_[row].friction &&
          first.normal.dot(rows_[row].normal) >= kSameNormalCos &&
          std::abs(first.bound - rows_[row].bound) <= bound_tolerance)
        break;
    }
    if (g == group_first_.size()) group_first_.push_back(static_cast<int>(row));
    group_of_[row] = static_cast<int>(g);
  }
  keep_.assign(rows_.size(), 1);
  for (std::size_t g = 0; g < group_first_.size(); ++g) {
    members_.clear();
    for (std::size_t row = 0; row < rows_.size(); ++row)
      if (group_of_[row] == static_cast<int>(g)) members_.push_back(static_cast<int>(row));
    if (members_.size() <= kKept) continue;
    const Vec3 normal = rows_[group_first_[g]].normal;
    const Vec3 t1 = perpendicular_unit(normal);
    const Vec3 t2 = normal.cross(t1);
    for (int m : members_) keep_[m] = 0;
    for (const Vec3& direction : {t1, t2, Vec3(t1 + t2), Vec3(t1 - t2)})
      for (double sign : {1.0, -1.0}) {
        const auto extreme = std::max_element(members_.begin(), members_.end(), [&](int a, int b) {
          return sign * rows_[a].lever.dot(direction) < sign * rows_[b].lever.dot(direction);
        });
        keep_[*extreme] = 1;
      }
  }
  // Compact the rows and re-point the constraints (−1: left to the QP).
  new_index_.assign(rows_.size(), -1);
  std::size_t kept = 0;
  for (std::size_t row = 0; row < rows_.size(); ++row) {
    if (!keep_[row]) continue;
    new_index_[row] = static_cast<int>(kept);
    rows_[kept++] = rows_[row];
  }
  rows_.resize(kept);
  for (int& row : row_of_) row = new_index_[row];
}

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
  r.feasible = true;
  r.with_friction = std::any_of(friction.begin(), friction.end(), [](double mu) { return mu > 0; });
  if (constraints.empty()) return r;

  const bool seed_from_qp = !r.with_friction || warm_impulses.size() != constraints.size();
  if (seed_from_qp) {
    std::erase_if(warm_active, [&](int k) { return k >= static_cast<int>(constraints.size()); });
    const GaussSolution& solution = gauss_.solve(metric, unconstrained, constraints, warm_active);
    r.iterations = solution.iterations;
    r.converged = solution.converged;
    r.feasible = solution.converged;
    warm_active = solution.converged ? solution.active : std::vector<int>{};
    r.step = solution.acceleration;
    for (std::size_t k = 0; k < constraints.size(); ++k)
      r.impulses[k].x() = solution.multipliers[k];
    if (!r.with_friction) return r;
  }

  // Coincident contacts (a vertex–face pair and the edge–edge pairs of that
  // vertex's edges meet at one point with one normal) would make the sweeps
  // trade load between them without end: each point is solved once, with
  // the tightest bound of the pairs there, its impulse kept by the first.
  constexpr double kCoincidentM = 1e-7;
  constexpr double kCoincidentCos = 1 - 1e-9;
  rows_.clear();
  row_of_.assign(constraints.size(), 0);
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    const GaussConstraint& c = constraints[k];
    std::size_t row = 0;
    while (row < rows_.size() && !(rows_[row].friction == friction[k] &&
                                   (rows_[row].lever - c.lever).norm() <= kCoincidentM &&
                                   rows_[row].normal.dot(c.normal) >= kCoincidentCos))
      ++row;
    if (row == rows_.size())
      rows_.push_back(FrictionalContactRow{c.normal, c.lever, c.rhs, friction[k]});
    else
      rows_[row].bound = std::max(rows_[row].bound, c.rhs);
    row_of_[k] = static_cast<int>(row);
  }
  reduce_coplanar_rows();
  const std::span<const Vec3> source =
      seed_from_qp ? std::span<const Vec3>(r.impulses) : warm_impulses;
  seed_.assign(rows_.size(), Vec3::Zero());
  for (std::size_t k = 0; k < constraints.size(); ++k)
    if (row_of_[k] >= 0) seed_[row_of_[k]] += source[k];
  const Mat6 response = metric.inverse();
  const FrictionalContactSolution& solution =
      frictional_.solve(response, unconstrained, rows_, seed_);
  r.iterations += solution.sweeps;
  // The sweeps' impulses are the next warm start: the QP below puts the load
  // of redundant contacts on an independent few, which they would spread again.
  std::fill(r.impulses.begin(), r.impulses.end(), Vec3::Zero());
  taken_.assign(rows_.size(), 0);
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    if (row_of_[k] < 0 || taken_[row_of_[k]]) continue;
    taken_[row_of_[k]] = 1;
    r.impulses[k] = solution.impulses[row_of_[k]];
  }

  // Non-penetration exactly: the frictionless QP again with the friction
  // impulses held as given forces (one step of staggered projections).
  Vec6 friction_wrench = Vec6::Zero();
  for (std::size_t row = 0; row < rows_.size(); ++row) {
    const Vec3 t1 = solution.tangent1[row];
    const Vec3 t2 = rows_[row].normal.cross(t1);
    const Vec3 force = solution.impulses[row].y() * t1 + solution.impulses[row].z() * t2;
    friction_wrench.head<3>() += force;
    friction_wrench.tail<3>() += rows_[row].lever.cross(force);
  }
  std::erase_if(warm_active, [&](int k) { return k >= static_cast<int>(constraints.size()); });
  const GaussSolution& projected =
      gauss_.solve(metric, unconstrained + response * friction_wrench, constraints, warm_active);
  r.iterations += projected.iterations;
  r.converged = solution.converged && projected.converged;
  r.feasible = projected.converged;
  warm_active = projected.converged ? projected.active : std::vector<int>{};
  r.step = projected.acceleration;
  return r;
}

}  // namespace hb
