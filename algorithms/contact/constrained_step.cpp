#include "algorithms/contact/constrained_step.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

#include "hapticbench/input_error.h"

namespace hb {

ConstrainedStepSolver::ConstrainedStepSolver(const FrictionalContactSettings& settings)
    : frictional_(settings), tolerance_(settings.tolerance) {}

namespace {

// Bounded passes of the staggered QP that cut friction back into the cone.
constexpr int kConePasses = 4;

// Two contact normals this close (cosine) are one normal: one plane.
constexpr double kSameNormalCos = 1 - 1e-6;
// How far apart (m) two such unit normals can be, |a − b| = √(2 − 2 a·b),
// with room for their rounding: the KeyWindow radius of the search.
const double kSameNormalDistance = std::sqrt(2 * (1 - kSameNormalCos)) + 1e-9;

// Coincident contacts (ConstrainedStepSolver::solve): levers this close (m)
// with normals this close (cosine) and one μ.
constexpr double kCoincidentM = 1e-7;
constexpr double kCoincidentCos = 1 - 1e-9;
// Room for the rounding of a lever's key (m; levers up to kilometres).
constexpr double kLeverKeyMargin = 1e-12;

// Up to this many contacts a plain scan finds matches for less than
// sorting them by key and searching does.
constexpr std::size_t kFewContacts = 32;

// Visits, in ascending order and until visit returns false, the ids of
// `listed` when `few`, else the window's ids whose key is within `radius`
// of `point`'s (the candidates a "within distance" test can accept).
template <class Visit>
void visit_candidates(bool few, std::span<const int> listed, KeyWindow& window, const Vec3& point,
                      double radius, Visit&& visit) {
  if (few) {
    for (const int id : listed)
      if (!visit(id)) return;
    return;
  }
  window.visit_within(point.dot(KeyWindow::axis()), radius, visit);
}

// The least candidate (as visit_candidates has them) that accept(id)
// takes, −1 if none.
template <class Accept>
int least_candidate(bool few, std::span<const int> listed, const KeyWindow& window,
                    const Vec3& point, double radius, Accept&& accept) {
  if (few) {
    for (const int id : listed)
      if (accept(id)) return id;
    return -1;
  }
  return window.least_within(point.dot(KeyWindow::axis()), radius, accept);
}

// z-component of (b − a) × (c − a): > 0 when a, b, c turn left.
double turn(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

}  // namespace

void ConstrainedStepSolver::keep_hull_vertices(const Vec3& normal) {
  // Andrew's monotone chain on the members' levers in the contact plane;
  // points on a hull edge are convex combinations of its ends and dropped.
  const Vec3 t1 = perpendicular_unit(normal);
  const Vec3 t2 = normal.cross(t1);
  plane_points_.clear();
  for (int m : members_)
    plane_points_.emplace_back(Eigen::Vector2d(rows_[m].lever.dot(t1), rows_[m].lever.dot(t2)), m);
  std::sort(plane_points_.begin(), plane_points_.end(), [](const auto& a, const auto& b) {
    return a.first.x() < b.first.x() || (a.first.x() == b.first.x() && a.first.y() < b.first.y());
  });
  const std::size_t n = plane_points_.size();
  hull_.assign(2 * n, 0);
  std::size_t size = 0;
  for (std::size_t i = 0; i < n; ++i) {  // lower chain
    while (size >= 2 && turn(plane_points_[hull_[size - 2]].first,
                             plane_points_[hull_[size - 1]].first, plane_points_[i].first) <= 0)
      --size;
    hull_[size++] = static_cast<int>(i);
  }
  for (std::size_t i = n - 1, lower = size + 1; i-- > 0;) {  // upper chain
    while (size >= lower && turn(plane_points_[hull_[size - 2]].first,
                                 plane_points_[hull_[size - 1]].first, plane_points_[i].first) <= 0)
      --size;
    hull_[size++] = static_cast<int>(i);
  }
  for (int m : members_) keep_[m] = 0;
  for (std::size_t i = 0; i < size; ++i) keep_[plane_points_[hull_[i]].second] = 1;
}

void ConstrainedStepSolver::reduce_coplanar_rows() {
  // Rows with one normal, one μ and about the same bound (a face resting on
  // a face) are one planar contact; beyond kKept of them the sweeps only
  // trade load between them. The vertices of their convex hull in the
  // plane carry every wrench the others can; the others are left to the
  // final QP, which holds every constraint.
  constexpr std::size_t kKept = 8;
  const double bound_tolerance = 1000 * tolerance_;
  group_of_.assign(rows_.size(), -1);
  group_first_.clear();
  group_size_.clear();
  // The groups' first rows as they come (few rows), or by normal: a row can
  // join only a group made before it, so the window holds the groups' first
  // rows, added as the groups are made (rows on one face would otherwise
  // fill every row's window).
  const bool few = rows_.size() <= kFewContacts;
  window_.clear();
  for (std::size_t row = 0; row < rows_.size(); ++row) {
    // The first group (in order of creation, which is the order of their
    // first rows) whose first row matches: only rows with a normal near
    // this one's can.
    const int first = least_candidate(
        few, group_first_, window_, rows_[row].normal, kSameNormalDistance, [&](int other) {
          const FrictionalContactRow& candidate = rows_[other];
          return other < static_cast<int>(row) && group_first_[group_of_[other]] == other &&
                 candidate.friction == rows_[row].friction &&
                 candidate.normal.dot(rows_[row].normal) >= kSameNormalCos &&
                 std::abs(candidate.bound - rows_[row].bound) <= bound_tolerance;
        });
    if (first < 0) {
      group_of_[row] = static_cast<int>(group_first_.size());
      group_first_.push_back(static_cast<int>(row));
      group_size_.push_back(0);
      if (!few) window_.insert(rows_[row].normal.dot(KeyWindow::axis()), static_cast<int>(row));
    } else {
      group_of_[row] = group_of_[first];
    }
    ++group_size_[group_of_[row]];
  }
  keep_.assign(rows_.size(), 1);
  for (std::size_t g = 0; g < group_first_.size(); ++g) {
    if (group_size_[g] <= static_cast<int>(kKept)) continue;
    members_.clear();
    for (std::size_t row = 0; row < rows_.size(); ++row)
      if (group_of_[row] == static_cast<int>(g)) members_.push_back(static_cast<int>(row));
    keep_hull_vertices(rows_[group_first_[g]].normal);
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

void ConstrainedStepSolver::build_rows(std::span<const GaussConstraint> constraints,
                                       std::span<const double> friction) {
  // Coincident contacts (a vertex–face pair and the edge–edge pairs of that
  // vertex's edges meet at one point with one normal) would make the sweeps
  // trade load between them without end: each point is solved once, with
  // the tightest bound of the pairs there, its impulse kept by the first.
  // A constraint joins the first row (in order) that matches; only rows
  // whose lever lies near its own can.
  // (A row's lever, normal and μ are its first constraint's, and rows are
  // made in the order of their first constraints.)
  rows_.clear();
  row_of_.assign(constraints.size(), 0);
  row_first_.clear();
  // The rows' first constraints as they come (few constraints), or every
  // constraint by lever.
  const bool few = constraints.size() <= kFewContacts;
  if (!few)
    window_.assign(constraints.size(),
                   [&](int k) { return constraints[k].lever.dot(KeyWindow::axis()); });
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    const GaussConstraint& c = constraints[k];
    // The earliest constraint that made a row and matches.
    const int first = least_candidate(
        few, row_first_, window_, c.lever, kCoincidentM + kLeverKeyMargin, [&](int other) {
          const GaussConstraint& candidate = constraints[other];
          return other < static_cast<int>(k) && row_first_[row_of_[other]] == other &&
                 friction[other] == friction[k] &&
                 (candidate.lever - c.lever).norm() <= kCoincidentM &&
                 candidate.normal.dot(c.normal) >= kCoincidentCos;
        });
    if (first < 0) {
      row_of_[k] = static_cast<int>(rows_.size());
      rows_.push_back(FrictionalContactRow{c.normal, c.lever, c.rhs, friction[k]});
      row_first_.push_back(static_cast<int>(k));
    } else {
      row_of_[k] = row_of_[first];
      rows_[row_of_[k]].bound = std::max(rows_[row_of_[k]].bound, c.rhs);
    }
  }
  reduce_coplanar_rows();
  // The rows by normal, for share_planar_loads (every pass of the cone and
  // of solve_system visits them).
  if (rows_.size() > kFewContacts)
    normal_window_.assign(rows_.size(),
                          [&](int row) { return rows_[row].normal.dot(KeyWindow::axis()); });
}

const ConstrainedStep& ConstrainedStepSolver::solve(const Mat6& metric, const Vec6& unconstrained,
                                                    std::span<const GaussConstraint> constraints,
                                                    std::span<const double> friction,
                                                    std::vector<int>& warm_active,
                                                    std::span<const Vec3> warm_impulses) {
  return solve_merging_repeats(
      constraints, friction, warm_active, warm_impulses,
      [&](std::span<const GaussConstraint> c, std::span<const double> mu, std::vector<int>& active,
          std::span<const Vec3> impulses) -> const ConstrainedStep& {
        return solve_pass(metric, unconstrained, c, mu, active, impulses, false);
      });
}

template <class Solve>
const ConstrainedStep& ConstrainedStepSolver::solve_merging_repeats(
    std::span<const GaussConstraint> constraints, std::span<const double> friction,
    std::vector<int>& warm_active, std::span<const Vec3> warm_impulses, Solve&& solve) {
  if (!distinct_.reduce(constraints, friction))
    return solve(constraints, friction, warm_active, warm_impulses);
  to_distinct(warm_active, warm_impulses, constraints.size());
  try {
    solve(distinct_.constraints(), distinct_.friction(), distinct_warm_active_,
          distinct_warm_impulses_);
  } catch (const InputError&) {
    // A constraint the QP rejects is named by its index among those given:
    // the same solve of all of them throws for it.
    return solve(constraints, friction, warm_active, warm_impulses);
  }
  return from_distinct(warm_active, constraints.size());
}

void ConstrainedStepSolver::to_distinct(std::span<const int> warm_active,
                                        std::span<const Vec3> warm_impulses, std::size_t count) {
  // Equal constraints' warm impulses add up on their distinct one, as the
  // frictional solve's seed adds up those of the contacts of one row.
  // Indices past the constraints are dropped as solve_pass drops them; a
  // negative one goes on, for the QP to reject (and the solve of every
  // constraint to name).
  distinct_warm_active_.clear();
  for (const int k : warm_active)
    if (k < 0 || static_cast<std::size_t>(k) < count)
      distinct_warm_active_.push_back(k < 0 ? k : distinct_.distinct_of(k));
  distinct_warm_impulses_.clear();
  // Without friction the solve reads no impulses.
  const std::span<const double> friction = distinct_.friction();
  if (warm_impulses.size() != count ||
      std::none_of(friction.begin(), friction.end(), [](double mu) { return mu > 0; }))
    return;
  distinct_warm_impulses_.assign(distinct_.constraints().size(), Vec3::Zero());
  for (std::size_t k = 0; k < count; ++k)
    distinct_warm_impulses_[static_cast<std::size_t>(distinct_.distinct_of(static_cast<int>(k)))] +=
        warm_impulses[k];
}

const ConstrainedStep& ConstrainedStepSolver::from_distinct(std::vector<int>& warm_active,
                                                            std::size_t count) {
  // The first of equal constraints carries their impulse, the others none.
  ConstrainedStep& r = result_;
  expanded_impulses_.assign(count, Vec3::Zero());
  for (std::size_t d = 0; d < r.impulses.size(); ++d)
    expanded_impulses_[static_cast<std::size_t>(distinct_.first_of(static_cast<int>(d)))] =
        r.impulses[d];
  r.impulses.swap(expanded_impulses_);
  warm_active.clear();
  for (const int d : distinct_warm_active_) warm_active.push_back(distinct_.first_of(d));
  return r;
}

const ConstrainedStep& ConstrainedStepSolver::solve_pass(
    const Mat6& metric, const Vec6& unconstrained, std::span<const GaussConstraint> constraints,
    std::span<const double> friction, std::vector<int>& warm_active,
    std::span<const Vec3> warm_impulses, bool rows_built) {
  ConstrainedStep& r = result_;
  // Start: the unconstrained step, no impulses.
  start_result(unconstrained, constraints.size(), friction);
  if (constraints.empty()) return r;

  // Frictionless: the QP's answer, or the sweeps' seed without warm impulses.
  const bool seed_from_qp = !r.with_friction || warm_impulses.size() != constraints.size();
  if (seed_from_qp) {
    solve_frictionless(metric, unconstrained, constraints, warm_active);
    if (!r.with_friction) return r;
  }

  // Rows: they depend on the constraints and μ only, so a skew pass of
  // solve_system takes those of the pass before it.
  if (!rows_built) build_rows(constraints, friction);
  seed_rows(seed_from_qp ? std::span<const Vec3>(r.impulses) : warm_impulses, constraints.size());
  const Mat6& response = response_of(metric);

  // Sweeps: the frictional solve on the rows.
  const FrictionalContactSolution& solution =
      frictional_.solve(response, unconstrained, rows_, seed_);
  r.iterations += solution.sweeps;
  keep_sweep_impulses(solution, constraints.size());

  // Project: non-penetration exactly, the friction held as given forces.
  if (!project_friction(metric, unconstrained, response, constraints, warm_active, solution))
    return r;

  // Residual: of the forces the step was solved with, each row's normal
  // force and friction on its first constraint.
  spread_row_normals(constraints.size());
  r.coulomb_residual = coulomb_residual(response, r.step, constraints, friction, normal_forces_);
  return r;
}

void ConstrainedStepSolver::start_result(const Vec6& unconstrained, std::size_t count,
                                         std::span<const double> friction) {
  ConstrainedStep& r = result_;
  r.step = unconstrained;
  r.impulses.assign(count, Vec3::Zero());
  r.iterations = 0;
  r.converged = true;
  r.feasible = true;
  r.with_friction = std::any_of(friction.begin(), friction.end(), [](double mu) { return mu > 0; });
  r.coulomb_residual = 0;
  r.skew_passes = 0;
}

void ConstrainedStepSolver::solve_frictionless(const Mat6& metric, const Vec6& unconstrained,
                                               std::span<const GaussConstraint> constraints,
                                               std::vector<int>& warm_active) {
  ConstrainedStep& r = result_;
  std::erase_if(warm_active, [&](int k) { return k >= static_cast<int>(constraints.size()); });
  const GaussSolution& solution = gauss_.solve(metric, unconstrained, constraints, warm_active);
  r.iterations = solution.iterations;
  r.converged = solution.converged;
  r.feasible = solution.converged;
  warm_active = solution.converged ? solution.active : std::vector<int>{};
  r.step = solution.acceleration;
  for (std::size_t k = 0; k < constraints.size(); ++k) r.impulses[k].x() = solution.multipliers[k];
}

void ConstrainedStepSolver::seed_rows(std::span<const Vec3> source, std::size_t count) {
  seed_.assign(rows_.size(), Vec3::Zero());
  for (std::size_t k = 0; k < count; ++k)
    if (row_of_[k] >= 0) seed_[row_of_[k]] += source[k];
}

const Mat6& ConstrainedStepSolver::response_of(const Mat6& metric) {
  if (!inverted_ || std::memcmp(metric.data(), inverted_metric_.data(), sizeof(Mat6)) != 0) {
    response_ = metric.inverse();
    inverted_metric_ = metric;
    inverted_ = true;
  }
  return response_;
}

void ConstrainedStepSolver::keep_sweep_impulses(const FrictionalContactSolution& solution,
                                                std::size_t count) {
  // The sweeps' impulses are the next warm start: the QP below puts the load
  // of redundant contacts on an independent few, which they would spread again.
  ConstrainedStep& r = result_;
  std::fill(r.impulses.begin(), r.impulses.end(), Vec3::Zero());
  taken_.assign(rows_.size(), 0);
  for (std::size_t k = 0; k < count; ++k) {
    if (row_of_[k] < 0 || taken_[row_of_[k]]) continue;
    taken_[row_of_[k]] = 1;
    r.impulses[k] = solution.impulses[row_of_[k]];
  }
  normal_forces_.assign(count, 0.0);
  friction_forces_.resize(rows_.size());
  for (std::size_t row = 0; row < rows_.size(); ++row)
    friction_forces_[row] = solution.impulses[row].tail<2>();
}

bool ConstrainedStepSolver::project_friction(const Mat6& metric, const Vec6& unconstrained,
                                             const Mat6& response,
                                             std::span<const GaussConstraint> constraints,
                                             std::vector<int>& warm_active,
                                             const FrictionalContactSolution& solution) {
  // The frictionless QP again with the friction impulses held as given
  // forces (one step of staggered projections). Its normal forces are exact
  // for that friction, shared within each planar contact as the sweeps
  // shared them (share_planar_loads: the QP's own sharing of a planar
  // contact's load is one of many). When the sweeps stopped at their
  // limit, their friction is scaled into the QP's cone and the QP solved
  // again, at most kConePasses times.
  ConstrainedStep& r = result_;
  for (int pass = 0; pass < kConePasses; ++pass) {
    const Vec6 friction_wrench = row_friction_wrench(solution);
    std::erase_if(warm_active, [&](int k) { return k >= static_cast<int>(constraints.size()); });
    const GaussSolution& projected =
        gauss_.solve(metric, unconstrained + response * friction_wrench, constraints, warm_active);
    r.iterations += projected.iterations;
    r.converged = solution.converged && projected.converged;
    r.feasible = projected.converged;
    warm_active = projected.converged ? projected.active : std::vector<int>{};
    r.step = projected.acceleration;
    if (!projected.converged) return false;
    take_qp_normals(projected, constraints.size());
    share_planar_loads(solution);
    if (solution.converged || !scale_friction_into_cone(pass)) break;
    r.converged = false;  // friction had to be cut: not the sweeps' answer any more
  }
  return true;
}

Vec6 ConstrainedStepSolver::row_friction_wrench(const FrictionalContactSolution& solution) const {
  Vec6 friction_wrench = Vec6::Zero();
  for (std::size_t row = 0; row < rows_.size(); ++row) {
    const Vec3 t1 = solution.tangent1[row];
    const Vec3 t2 = rows_[row].normal.cross(t1);
    const Vec3 force = friction_forces_[row].x() * t1 + friction_forces_[row].y() * t2;
    friction_wrench.head<3>() += force;
    friction_wrench.tail<3>() += rows_[row].lever.cross(force);
  }
  return friction_wrench;
}

void ConstrainedStepSolver::take_qp_normals(const GaussSolution& projected, std::size_t count) {
  row_normal_.assign(rows_.size(), 0.0);
  for (std::size_t k = 0; k < count; ++k) {
    normal_forces_[k] = projected.multipliers[k];
    if (row_of_[k] >= 0) row_normal_[row_of_[k]] += projected.multipliers[k];
  }
}

bool ConstrainedStepSolver::scale_friction_into_cone(int pass) {
  // A converged solve's friction stands (the residual tells how well the
  // normal forces support it). An unconverged one's is scaled down, all
  // rows alike, until it is at most μ times the QP's normal force in all
  // (a per-row cut would follow the QP's sharing of load between nearly
  // coplanar contacts, which is arbitrary, and drop friction wholesale).
  double friction_total = 0, cone_total = 0;
  for (std::size_t row = 0; row < rows_.size(); ++row) {
    friction_total += friction_forces_[row].norm();
    cone_total += rows_[row].friction * row_normal_[row];
  }
  if (friction_total <= cone_total * (1 + 1e-9) || pass + 1 == kConePasses) return false;
  for (Eigen::Vector2d& force : friction_forces_) force *= cone_total / friction_total;
  return true;
}

void ConstrainedStepSolver::share_planar_loads(const FrictionalContactSolution& solution) {
  // Rows with one normal and one μ share their group's total normal force
  // (the QP's) in the sweeps' proportions; the rows with a normal near a
  // row's are found by key, and summed in row order. Rows with the same
  // normal and μ (contacts on one face) have the same near rows: visited in
  // order of key, where they follow one another, each takes the sums of the
  // one before it when they match.
  const bool few = rows_.size() <= kFewContacts;  // every row, or the rows by normal
  all_rows_.resize(rows_.size());
  std::iota(all_rows_.begin(), all_rows_.end(), 0);
  shared_normal_.resize(rows_.size());
  double qp_total = 0, sweeps_total = 0;
  int previous = -1;
  const auto share = [&](int row) {
    // A row the sweeps and the QP both left without load keeps none (its
    // share of the group's total is zero, and so is its own QP force).
    if (solution.impulses[row].x() == 0 && row_normal_[row] == 0) {
      shared_normal_[row] = 0;
      return;
    }
    const bool same = previous >= 0 && rows_[previous].normal == rows_[row].normal &&
                      rows_[previous].friction == rows_[row].friction;
    if (!same) {
      qp_total = 0;
      sweeps_total = 0;
      visit_candidates(few, all_rows_, normal_window_, rows_[row].normal, kSameNormalDistance,
                       [&](int other) {
                         if (rows_[other].friction == rows_[row].friction &&
                             rows_[other].normal.dot(rows_[row].normal) >= kSameNormalCos) {
                           qp_total += row_normal_[other];
                           sweeps_total += solution.impulses[other].x();
                         }
                         return true;
                       });
    }
    previous = row;
    shared_normal_[row] = sweeps_total > 0 ? solution.impulses[row].x() * (qp_total / sweeps_total)
                                           : row_normal_[row];
  };
  if (few) {
    for (const int row : all_rows_) share(row);
  } else {
    normal_window_.visit_in_key_order(share);
  }
  row_normal_.swap(shared_normal_);
}

const ConstrainedStep& ConstrainedStepSolver::solve_system(
    const Mat6& system, const Vec6& unconstrained, std::span<const GaussConstraint> constraints,
    std::span<const double> friction, std::vector<int>& warm_active,
    std::span<const Vec3> warm_impulses) {
  return solve_merging_repeats(
      constraints, friction, warm_active, warm_impulses,
      [&](std::span<const GaussConstraint> c, std::span<const double> mu, std::vector<int>& active,
          std::span<const Vec3> impulses) -> const ConstrainedStep& {
        return solve_system_of(system, unconstrained, c, mu, active, impulses);
      });
}

const ConstrainedStep& ConstrainedStepSolver::solve_system_of(
    const Mat6& system, const Vec6& unconstrained, std::span<const GaussConstraint> constraints,
    std::span<const double> friction, std::vector<int>& warm_active,
    std::span<const Vec3> warm_impulses) {
  const Mat6 symmetric = 0.5 * (system + system.transpose());
  const Mat6 skew = 0.5 * (system - system.transpose());
  Eigen::LDLT<Mat6> symmetric_inverse;  // factored when a skew force first appears
  Vec6 shifted = unconstrained;
  pass_impulses_.assign(warm_impulses.begin(), warm_impulses.end());
  for (int pass = 1;; ++pass) {
    // Passes after the first solve the same constraints: their rows stand.
    const ConstrainedStep& r = solve_pass(symmetric, shifted, constraints, friction, warm_active,
                                          pass_impulses_, pass > 1);
    result_.skew_passes = pass;
    const Vec6 deflection = r.step - unconstrained;
    const Vec6 skew_force = skew * deflection;
    if (skew_force.isZero(0)) return r;  // free, or a symmetric system
    if (pass == 1) symmetric_inverse.compute(symmetric);
    const Vec6 next = unconstrained - symmetric_inverse.solve(skew_force);
    const double change = (next - shifted).lpNorm<Eigen::Infinity>();
    if (change <= std::max(tolerance_, 1e-6 * deflection.lpNorm<Eigen::Infinity>()) ||
        pass == kSkewPasses)
      return r;
    shifted = next;
    if (r.with_friction) pass_impulses_.assign(r.impulses.begin(), r.impulses.end());
  }
}

void ConstrainedStepSolver::spread_row_normals(std::size_t constraint_count) {
  std::fill(taken_.begin(), taken_.end(), 0);
  for (std::size_t k = 0; k < constraint_count; ++k) {
    const int row = row_of_[k];
    if (row < 0) continue;
    normal_forces_[k] = taken_[row] ? 0.0 : row_normal_[row];
    taken_[row] = 1;
  }
}

double ConstrainedStepSolver::coulomb_residual(const Mat6& response, const Vec6& step,
                                               std::span<const GaussConstraint> constraints,
                                               std::span<const double> friction,
                                               std::span<const double> normal_forces) {
  // Friction per constraint: its row's (the first constraint of a row
  // carries it, as the normal force passed in); a constraint left out of
  // the sweeps carries none.
  double worst = 0, total_normal = 0;
  std::fill(taken_.begin(), taken_.end(), 0);
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    const GaussConstraint& c = constraints[k];
    const int row = row_of_[k];
    Eigen::Vector2d force = Eigen::Vector2d::Zero();
    if (row >= 0) {
      if (taken_[row]) continue;  // a coincident pair: its row is counted once
      taken_[row] = 1;
      force = friction_forces_[row];
    }
    // A contact with neither normal nor friction force has a cone of radius
    // 0 and no force to leave it: it adds exactly nothing, whatever its slip.
    if (!(normal_forces[k] > 0) && force.isZero(0)) continue;
    const Vec3 t1 = perpendicular_unit(c.normal);
    const Vec3 t2 = c.normal.cross(t1);
    Eigen::Matrix<double, 2, 6> tangential;
    tangential.row(0) << t1.transpose(), c.lever.cross(t1).transpose();
    tangential.row(1) << t2.transpose(), c.lever.cross(t2).transpose();
    const Eigen::Vector2d slip = tangential * step;
    const double mean_response = 0.5 * (tangential * response * tangential.transpose()).trace();
    const Eigen::Vector2d trial = force - slip / mean_response;
    const double radius = friction[k] * std::max(0.0, normal_forces[k]);
    const Eigen::Vector2d projected =
        trial.norm() > radius ? Eigen::Vector2d(trial * (radius / trial.norm())) : trial;
    worst = std::max(worst, (force - projected).norm());
    total_normal += std::max(0.0, normal_forces[k]);
  }
  return total_normal > 0 ? worst / total_normal : 0.0;
}

}  // namespace hb
