// Gauss' principle of least constraint for the 6-DOF god-object (lecture
// notes, "Gauss' Principle of Least Constraint" to "Constrained Motion";
// Ortega, Redon & Coquillart 2007). The constrained generalized acceleration
// of the proxy is the one closest to the unconstrained one in the kinetic
// metric:
//   a^c = argmin_a ½ (a − a^u)ᵀ M (a − a^u)   subject to   J_k · a ≥ b_k,
//   a = (a_cm, α),   J_k = (n_k, r_k × n_k),
// one row per contact (point, normal). With b = 0 (the notes' constraints)
// a = 0 is always feasible, so a solution always exists.
//
// Solved by the Goldfarb–Idnani dual active-set method, whose active rows
// stay linearly independent (docs/algorithms/constrained-step.md).
#pragma once

#include <span>
#include <vector>

#include "hapticbench/pose.h"

namespace hb {

/// One contact constraint J · a ≥ rhs on the generalized acceleration
/// a = (a_cm, α), with J = (normal, lever × normal).
struct GaussConstraint {
  Vec3 normal = Vec3::UnitZ();  ///< world frame, unit length, pushes the tool out of the scene
  Vec3 lever = Vec3::Zero();    ///< contact point minus the tool's centre of mass, world frame (m)
  /// Lower bound b_k on the normal acceleration of the contact point
  /// n · (a_cm + α × r) (m/s²); 0 for a resting contact.
  double rhs = 0;
};

/// The constraint's row J_k = (n_k, r_k × n_k) of the contact Jacobian: J_k · a
/// is the acceleration of the contact point along the normal (m/s²), and
/// J_kᵀ λ is the wrench (N, N·m about the centre of mass) of a normal force λ.
Vec6 constraint_row(const GaussConstraint& constraint);

/// Mass matrix M = diag(m I₃, I_world) of a rigid body for a = (a_cm, α):
/// mass in kg, inertia about the centre of mass in world axes (kg·m²).
Mat6 rigid_body_mass_matrix(double mass_kg, const Mat3& inertia_world);

struct GaussSettings {
  /// Upper bound on add/drop steps; reaching it returns converged = false.
  int max_iterations = 1000;
  /// A constraint counts as violated when it misses its bound by more than
  /// this fraction of the problem's scale (the largest M-norm distance from
  /// a^u to one constraint's boundary, or |a^u|_M).
  double feasibility_tolerance = 1e-12;
  /// A constraint whose M-metric unit normal lies within this distance of
  /// the span of the active ones is treated as linearly dependent on them.
  /// When all rhs ≤ 0 (a = 0 feasible), a dependent row that cannot be
  /// added can only be off by rounding, so it is left at its residual (of
  /// order this tolerance times the problem's scale) instead of reporting
  /// infeasibility.
  double dependence_tolerance = 1e-12;
};

struct GaussSolution {
  /// The constrained generalized acceleration a^c = (a_cm m/s², α rad/s²),
  /// world frame, centre of mass. When not converged: the last iterate,
  /// which may violate constraints.
  Vec6 acceleration = Vec6::Zero();
  /// Indices (into the constraints) of the active set, ascending: its rows
  /// are linearly independent (at most 6), each holds with equality, and
  /// together they determine the solution. A constraint that also holds
  /// with equality but depends on these rows (a fourth coplanar contact)
  /// is not listed; its multiplier is 0.
  std::vector<int> active;
  /// One multiplier per constraint, λ ≥ 0, zero outside the active set, with
  /// M (a^c − a^u) = Σ_k λ_k J_kᵀ: λ_k is the normal contact force (N) when
  /// M is in kg, kg·m² and accelerations in m/s², rad/s²; in other units it
  /// is the contact force up to the same scale. Not unique when the tight
  /// constraints are linearly dependent; this is one valid choice.
  std::vector<double> multipliers;
  int iterations = 0;       ///< add and drop steps taken (warm-start drops included)
  bool converged = false;   ///< KKT conditions met within the tolerances
  bool infeasible = false;  ///< no a satisfies all constraints (only possible with some rhs > 0)
};

/// Solves the least-constraint problem with reusable buffers, so a solve in
/// the haptic loop does not allocate once the buffers have grown.
class GaussLeastConstraintSolver {
 public:
  explicit GaussLeastConstraintSolver(const GaussSettings& settings = {});

  /// mass: symmetric positive definite 6×6 (kg, kg·m²; diagonal blocks as in
  /// rigid_body_mass_matrix, a general SPD matrix is accepted).
  /// unconstrained: a^u = (a_cm m/s², α rad/s²), world frame.
  /// warm_active: indices of constraints expected to be active (typically
  /// the previous solve's active set); wrong guesses cost iterations, never
  /// correctness. Throws InputError for a non-symmetric or non-positive-
  /// definite mass, non-finite input, a normal that is not unit length, or a
  /// warm-start index out of range. The result stays valid until the next solve.
  const GaussSolution& solve(const Mat6& mass, const Vec6& unconstrained,
                             std::span<const GaussConstraint> constraints,
                             std::span<const int> warm_active = {});

 private:
  GaussSettings settings_;
  // Per constraint, in the metric z = Lᵀ(a − a^u): unit row ĝ_k and bound ĥ_k
  // of ĝ_k · z ≥ ĥ_k, and the factor |L⁻¹ J_kᵀ| that scaled them.
  std::vector<Vec6> unit_rows_;
  std::vector<double> unit_rhs_;
  std::vector<double> row_scale_;
  std::vector<double> unit_multipliers_;
  std::vector<char> in_active_set_;
  std::vector<char> set_aside_;
  std::vector<int> working_set_;
  GaussSolution solution_;
  /// The Cholesky factor L of factored_mass_ and L⁻¹ (valid when factored_).
  Mat6 factored_mass_ = Mat6::Zero();
  Mat6 lower_ = Mat6::Zero();
  Mat6 lower_inverse_ = Mat6::Zero();
  bool factored_ = false;

  /// The dual iteration's state between its phases (gauss_least_constraint.cpp).
  struct DualIterate;

  /// Factors the mass (L, L⁻¹), unless it is the last one factored.
  void factor(const Mat6& mass);
  /// Puts the warm-start rows that are independent of each other in the working set.
  void warm_start(DualIterate& iterate, std::span<const int> warm_active);
  /// z at the least-norm point of the working set, dropping rows whose
  /// multipliers turn negative; false when the iteration budget ran out.
  bool drop_negative_multipliers(DualIterate& iterate);
  /// The constraint that misses its bound by the most beyond `tolerance`, or −1.
  int most_violated(const Vec6& z, int count, double tolerance) const;
  /// Raises the `added` constraint's multiplier until it holds (added) or
  /// another leaves; false when the solve stops (budget, infeasible).
  bool add_constraint(DualIterate& iterate, int added, bool known_feasible);
  /// The step at which the first active multiplier reaches zero and its
  /// working-set position `blocking` (unchanged: none falls).
  double blocking_step(const DualIterate& iterate, int& blocking) const;
  /// A row dependent on the active ones that cannot be added: set aside
  /// (true) when a = 0 is feasible, else the problem is infeasible (false).
  bool set_aside_dependent(int added, bool known_feasible);
  bool within_budget() const;  ///< add/drop steps left
  void remove_from_working_set(int position);
  /// Fills the per-constraint buffers for a solve; returns the problem's
  /// scale (the largest bound, or |Lᵀ a^u|) and clears known_feasible when
  /// some rhs > 0.
  double prepare_rows(const Mat6& lower, const Mat6& lower_inverse, const Vec6& unconstrained,
                      std::span<const GaussConstraint> constraints, bool& known_feasible);
  /// The solution from the final z and working set.
  void finish(const Vec6& unconstrained, const Mat6& lower_inverse, const Vec6& z, int count);
};

/// One-shot form of GaussLeastConstraintSolver::solve.
GaussSolution solve_least_constraint(const Mat6& mass, const Vec6& unconstrained,
                                     std::span<const GaussConstraint> constraints,
                                     std::span<const int> warm_active = {},
                                     const GaussSettings& settings = {});

}  // namespace hb
