#include "algorithms/contact/gauss_least_constraint.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "algorithms/contact/small_inverse.h"
#include "hapticbench/input_error.h"

namespace hb {
namespace {

constexpr int kDof = 6;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// At most six independent rows can be active, so every active-set quantity
// fits in fixed-capacity storage and a solve never allocates inside the loop.
using ActiveVector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kDof, 1>;

// Factorisation Nᵀ = Q R of the active unit rows (as columns), Q with
// orthonormal columns, R upper triangular. It answers the two questions the
// dual method asks: the minimum-norm point on the active constraints'
// boundaries, and how a new row splits into a part in the span of the active
// rows (coefficients r) and a part orthogonal to it (d). Built by classical
// Gram–Schmidt applied twice, which keeps Q orthonormal to rounding (as
// Householder would) at a fraction of the cost for six columns.
class ActiveSetFactorisation {
 public:
  void compute(const std::vector<Vec6>& unit_rows, const std::vector<int>& working_set) {
    size_ = 0;
    for (const int index : working_set) append(unit_rows[index]);
  }

  // Appends a row that is independent of the current ones.
  void append(const Vec6& row) {
    ActiveVector in_span;
    Vec6 orthogonal;
    project(row, in_span, orthogonal);
    const double length = orthogonal.norm();
    q_.col(size_) = orthogonal / length;
    r_.col(size_).head(size_) = in_span;
    r_(size_, size_) = length;
    ++size_;
  }

  int size() const { return size_; }

  // row = Nᵀ coefficients + orthogonal.
  void split(const Vec6& row, ActiveVector& coefficients, Vec6& orthogonal) const {
    ActiveVector in_span;
    project(row, in_span, orthogonal);
    coefficients = solve_upper(in_span);
  }

  // The point z of least norm with N z = bounds, z = Nᵀ multipliers.
  void least_norm_point(const ActiveVector& bounds, Vec6& point, ActiveVector& multipliers) const {
    const ActiveVector y = solve_upper_transposed(bounds);
    point = q_.leftCols(size_) * y;
    multipliers = solve_upper(y);
  }

 private:
  // x = R⁻¹ b by back substitution.
  ActiveVector solve_upper(const ActiveVector& b) const {
    ActiveVector x(size_);
    for (int i = size_ - 1; i >= 0; --i) {
      double sum = b[i];
      for (int j = i + 1; j < size_; ++j) sum -= r_(i, j) * x[j];
      x[i] = sum / r_(i, i);
    }
    return x;
  }

  // y = R⁻ᵀ b by forward substitution.
  ActiveVector solve_upper_transposed(const ActiveVector& b) const {
    ActiveVector y(size_);
    for (int i = 0; i < size_; ++i) {
      double sum = b[i];
      for (int j = 0; j < i; ++j) sum -= r_(j, i) * y[j];
      y[i] = sum / r_(i, i);
    }
    return y;
  }

  // row = Q in_span + orthogonal, with orthogonal ⟂ Q's columns.
  void project(const Vec6& row, ActiveVector& in_span, Vec6& orthogonal) const {
    in_span.setZero(size_);
    orthogonal = row;
    for (int pass = 0; pass < 2; ++pass) {
      const ActiveVector correction = q_.leftCols(size_).transpose() * orthogonal;
      orthogonal -= q_.leftCols(size_) * correction;
      in_span += correction;
    }
  }

  int size_ = 0;
  Mat6 q_ = Mat6::Zero();
  Mat6 r_ = Mat6::Zero();
};

// The position of the most negative of the first `size` multipliers; −1
// when none is negative.
int most_negative_multiplier(const ActiveVector& multipliers, int size) {
  int most_negative = -1;
  for (int i = 0; i < size; ++i) {
    if (multipliers[i] < 0 && (most_negative < 0 || multipliers[i] < multipliers[most_negative]))
      most_negative = i;
  }
  return most_negative;
}

// Validation runs every solve, so it builds a message only when it fails.
std::string constraint_field(size_t index, const char* field) {
  return "constraints[" + std::to_string(index) + "]." + field;
}

void require_finite(bool finite, const std::string& location) {
  if (!finite) throw InputError("", location, "expected finite numbers");
}

void validate_problem(const Mat6& mass, const Vec6& unconstrained,
                      std::span<const GaussConstraint> constraints,
                      std::span<const int> warm_active) {
  require_finite(mass.allFinite(), "mass");
  const double mass_size = mass.cwiseAbs().maxCoeff();
  if ((mass - mass.transpose()).cwiseAbs().maxCoeff() > 1e-9 * mass_size) {
    throw InputError("", "mass", "expected a symmetric 6x6 mass matrix");
  }
  require_finite(unconstrained.allFinite(), "unconstrained");
  for (size_t k = 0; k < constraints.size(); ++k) {
    const GaussConstraint& constraint = constraints[k];
    if (!constraint.normal.allFinite()) require_finite(false, constraint_field(k, "normal"));
    if (!constraint.lever.allFinite()) require_finite(false, constraint_field(k, "lever"));
    if (!std::isfinite(constraint.rhs)) require_finite(false, constraint_field(k, "rhs"));
    // |n|² within 2e-6 of 1 is |n| within 1e-6 of 1, without a square root.
    if (std::abs(constraint.normal.squaredNorm() - 1) > 2e-6) {
      throw InputError(
          "", constraint_field(k, "normal"),
          "expected a unit vector, length is " + std::to_string(constraint.normal.norm()));
    }
  }
  for (size_t i = 0; i < warm_active.size(); ++i) {
    if (warm_active[i] < 0 || static_cast<size_t>(warm_active[i]) >= constraints.size()) {
      throw InputError("", "warm_active[" + std::to_string(i) + "]",
                       "expected a constraint index in [0, " + std::to_string(constraints.size()) +
                           "), got " + std::to_string(warm_active[i]));
    }
  }
}

}  // namespace

Vec6 constraint_row(const GaussConstraint& constraint) {
  Vec6 row;
  row << constraint.normal, constraint.lever.cross(constraint.normal);
  return row;
}

Mat6 rigid_body_mass_matrix(double mass_kg, const Mat3& inertia_world) {
  Mat6 mass = Mat6::Zero();
  mass.topLeftCorner<3, 3>() = mass_kg * Mat3::Identity();
  mass.bottomRightCorner<3, 3>() = inertia_world;
  return mass;
}

GaussLeastConstraintSolver::GaussLeastConstraintSolver(const GaussSettings& settings)
    : settings_(settings) {}

// The dual iteration's state between its phases: the active rows'
// factorisation, the point z = Lᵀ(a − a^u) and the scratch of its steps.
struct GaussLeastConstraintSolver::DualIterate {
  ActiveSetFactorisation factorisation;
  Vec6 z = Vec6::Zero();
  ActiveVector coefficients;  ///< a row's coefficients on the active rows (split)
  Vec6 orthogonal;            ///< a row's part orthogonal to the active rows (split)
  ActiveVector bounds;        ///< the active rows' ĥ
  ActiveVector multipliers;   ///< the active rows' λ̂ at the least-norm point
};

const GaussSolution& GaussLeastConstraintSolver::solve(const Mat6& mass, const Vec6& unconstrained,
                                                       std::span<const GaussConstraint> constraints,
                                                       std::span<const int> warm_active) {
  validate_problem(mass, unconstrained, constraints, warm_active);
  // Factor: M = L Lᵀ and L⁻¹, unless M is the last solve's.
  factor(mass);
  const int count = static_cast<int>(constraints.size());

  // Rows: each constraint as a unit row and bound in the metric z = Lᵀ(a − a^u).
  bool known_feasible = true;  // a = 0 satisfies every constraint when all rhs ≤ 0
  const double scale =
      prepare_rows(lower_, lower_inverse_, unconstrained, constraints, known_feasible);
  const double violation_tolerance = settings_.feasibility_tolerance * scale;

  GaussSolution& solution = solution_;
  solution.iterations = 0;
  solution.converged = false;
  solution.infeasible = false;

  // Warm start: the suggested rows that are independent of each other.
  DualIterate iterate;
  warm_start(iterate, warm_active);
  while (true) {
    // Drop: the least-norm point of the working set, its negative multipliers dropped.
    if (!drop_negative_multipliers(iterate)) break;
    // Converged when no constraint is violated beyond the tolerance.
    const int added = most_violated(iterate.z, count, violation_tolerance);
    if (added < 0) {
      solution.converged = true;
      break;
    }
    // Add: the most violated constraint, dropping the rows that block it.
    if (!add_constraint(iterate, added, known_feasible)) break;
  }

  // Finish: a = a^u + L⁻ᵀ z and the multipliers in the constraints' units.
  finish(unconstrained, lower_inverse_, iterate.z, count);
  return solution;
}

// The factors of the last mass, kept while the mass stays the same bit for
// bit (a solve repeated with other bounds or a shifted a^u).
[[gnu::always_inline]] inline void GaussLeastConstraintSolver::factor(const Mat6& mass) {
  if (factored_ && std::memcmp(mass.data(), factored_mass_.data(), sizeof(Mat6)) == 0) return;
  factored_ = false;
  const Eigen::LLT<Mat6> cholesky(mass);
  if (cholesky.info() != Eigen::Success) {
    throw InputError("", "mass", "expected a positive definite mass matrix");
  }
  lower_ = cholesky.matrixL();
  // L⁻¹ once, so each row costs one 6×6 product instead of a triangular solve.
  lower_inverse_ = lower_triangular_inverse(lower_);
  factored_mass_ = mass;
  factored_ = true;
}

// Warm start: takes the suggested rows that are independent of each other.
[[gnu::always_inline]] inline void GaussLeastConstraintSolver::warm_start(
    DualIterate& iterate, std::span<const int> warm_active) {
  iterate.factorisation.compute(unit_rows_, working_set_);
  for (const int index : warm_active) {
    if (in_active_set_[index]) continue;
    iterate.factorisation.split(unit_rows_[index], iterate.coefficients, iterate.orthogonal);
    if (iterate.orthogonal.norm() <= settings_.dependence_tolerance) continue;
    iterate.factorisation.append(unit_rows_[index]);
    working_set_.push_back(index);
    in_active_set_[index] = 1;
  }
}

// The exact minimum-norm point on the working set's boundaries. Its
// multipliers are non-negative after every full step in exact arithmetic;
// a negative one (a poor warm-start guess, or rounding) is dropped, which
// keeps the pair (z, working set) dual feasible. False when the iteration
// budget ran out first.
[[gnu::always_inline]] inline bool GaussLeastConstraintSolver::drop_negative_multipliers(
    DualIterate& iterate) {
  ActiveSetFactorisation& factorisation = iterate.factorisation;
  while (true) {
    factorisation.compute(unit_rows_, working_set_);
    iterate.bounds.resize(factorisation.size());
    for (int i = 0; i < factorisation.size(); ++i) iterate.bounds[i] = unit_rhs_[working_set_[i]];
    factorisation.least_norm_point(iterate.bounds, iterate.z, iterate.multipliers);
    const int most_negative = most_negative_multiplier(iterate.multipliers, factorisation.size());
    if (most_negative < 0) break;
    if (!within_budget()) return false;
    ++solution_.iterations;
    remove_from_working_set(most_negative);
  }
  for (int i = 0; i < factorisation.size(); ++i)
    unit_multipliers_[working_set_[i]] = iterate.multipliers[i];
  return true;
}

// The most violated constraint at z, as a distance in the kinetic metric;
// −1 when none misses its bound by more than the tolerance.
[[gnu::always_inline]] inline int GaussLeastConstraintSolver::most_violated(
    const Vec6& z, int count, double tolerance) const {
  int added = -1;
  double worst = tolerance;
  for (int k = 0; k < count; ++k) {
    if (in_active_set_[k] || set_aside_[k]) continue;
    const double violation = unit_rhs_[k] - unit_rows_[k].dot(z);
    if (violation > worst) {
      worst = violation;
      added = k;
    }
  }
  return added;
}

// Raises the new constraint's multiplier t from 0, keeping the active
// constraints on their boundaries: z moves along d (the part of ĝ_p
// orthogonal to the active rows) and the active multipliers change by −t r.
// Ends with the constraint added or set aside; false when the solve stops
// (budget spent, or infeasible).
[[gnu::always_inline]] inline bool GaussLeastConstraintSolver::add_constraint(DualIterate& iterate,
                                                                              int added,
                                                                              bool known_feasible) {
  ActiveSetFactorisation& factorisation = iterate.factorisation;
  double added_multiplier = 0;
  while (true) {
    if (!within_budget()) return false;
    ++solution_.iterations;
    factorisation.split(unit_rows_[added], iterate.coefficients, iterate.orthogonal);
    const bool dependent = iterate.orthogonal.norm() <= settings_.dependence_tolerance;
    if (dependent) iterate.orthogonal.setZero();

    int blocking = -1;  // the first active multiplier to reach zero
    const double partial_step = blocking_step(iterate, blocking);
    const double violation = unit_rhs_[added] - unit_rows_[added].dot(iterate.z);
    const double full_step =
        dependent ? kInfinity : std::max(violation, 0.0) / iterate.orthogonal.squaredNorm();

    if (blocking < 0 && dependent) return set_aside_dependent(added, known_feasible);
    const double step = std::min(full_step, partial_step);
    iterate.z += step * iterate.orthogonal;
    for (int i = 0; i < factorisation.size(); ++i)
      unit_multipliers_[working_set_[i]] -= step * iterate.coefficients[i];
    added_multiplier += step;
    if (full_step <= partial_step) {
      working_set_.push_back(added);
      in_active_set_[added] = 1;
      unit_multipliers_[added] = added_multiplier;
      return true;
    }
    remove_from_working_set(blocking);
    factorisation.compute(unit_rows_, working_set_);
  }
}

// The step t at which the first active multiplier reaches zero as the
// added one rises (infinity when none falls), and its position `blocking`
// in the working set (−1 for none).
[[gnu::always_inline]] inline double GaussLeastConstraintSolver::blocking_step(
    const DualIterate& iterate, int& blocking) const {
  const ActiveVector& coefficients = iterate.coefficients;
  double partial_step = kInfinity;
  for (int i = 0; i < iterate.factorisation.size(); ++i) {
    if (coefficients[i] <= 0) continue;
    const double step = unit_multipliers_[working_set_[i]] / coefficients[i];
    if (step < partial_step) {
      partial_step = step;
      blocking = i;
    }
  }
  return partial_step;
}

// ĝ_p is a non-positive combination of active rows that hold with equality:
// no point satisfies them and p. When a = 0 is known to be feasible this
// can only be a row within rounding of dependence, whose violation is then
// of rounding size too (bounded by the dependence tolerance times the
// scale): it is left out of this solve (true: the solve goes on). Otherwise
// the problem is infeasible (false).
[[gnu::always_inline]] inline bool GaussLeastConstraintSolver::set_aside_dependent(
    int added, bool known_feasible) {
  if (known_feasible) {
    set_aside_[added] = 1;
    return true;
  }
  solution_.infeasible = true;
  return false;
}

[[gnu::always_inline]] inline bool GaussLeastConstraintSolver::within_budget() const {
  return solution_.iterations < settings_.max_iterations;
}

[[gnu::always_inline]] inline void GaussLeastConstraintSolver::remove_from_working_set(
    int position) {
  const int index = working_set_[position];
  in_active_set_[index] = 0;
  unit_multipliers_[index] = 0;
  working_set_.erase(working_set_.begin() + position);
}

// z = Lᵀ(a − a^u) turns the kinetic metric into the Euclidean one: the
// problem becomes the projection of z = 0 onto {z : ĝ_k · z ≥ ĥ_k}. Unit
// rows make every violation a distance, so one tolerance fits all rows
// whatever their lever arms.
[[gnu::always_inline]] inline double GaussLeastConstraintSolver::prepare_rows(
    const Mat6& lower, const Mat6& lower_inverse, const Vec6& unconstrained,
    std::span<const GaussConstraint> constraints, bool& known_feasible) {
  const int count = static_cast<int>(constraints.size());
  unit_rows_.resize(count);
  unit_rhs_.resize(count);
  row_scale_.resize(count);
  unit_multipliers_.assign(count, 0.0);
  in_active_set_.assign(count, 0);
  set_aside_.assign(count, 0);
  working_set_.clear();
  double scale = (lower.transpose() * unconstrained).norm();
  for (int k = 0; k < count; ++k) {
    const Vec6 row = constraint_row(constraints[k]);
    const Vec6 metric_row = lower_inverse * row;
    row_scale_[k] = metric_row.norm();
    const double inverse_scale = 1 / row_scale_[k];
    unit_rows_[k] = inverse_scale * metric_row;
    unit_rhs_[k] = inverse_scale * (constraints[k].rhs - row.dot(unconstrained));
    scale = std::max(scale, std::abs(unit_rhs_[k]));
    known_feasible = known_feasible && constraints[k].rhs <= 0;
  }
  return scale;
}

// Back to accelerations: a = a^u + L⁻ᵀ z, λ_k = λ̂_k / |L⁻¹ J_kᵀ|.
[[gnu::always_inline]] inline void GaussLeastConstraintSolver::finish(const Vec6& unconstrained,
                                                                      const Mat6& lower_inverse,
                                                                      const Vec6& z, int count) {
  GaussSolution& solution = solution_;
  solution.acceleration = unconstrained + lower_inverse.transpose() * z;
  solution.active.assign(working_set_.begin(), working_set_.end());
  std::sort(solution.active.begin(), solution.active.end());
  solution.multipliers.assign(count, 0.0);
  for (const int index : solution.active) {
    solution.multipliers[index] = std::max(unit_multipliers_[index], 0.0) / row_scale_[index];
  }
}

GaussSolution solve_least_constraint(const Mat6& mass, const Vec6& unconstrained,
                                     std::span<const GaussConstraint> constraints,
                                     std::span<const int> warm_active,
                                     const GaussSettings& settings) {
  GaussLeastConstraintSolver solver(settings);
  return solver.solve(mass, unconstrained, constraints, warm_active);
}

}  // namespace hb
