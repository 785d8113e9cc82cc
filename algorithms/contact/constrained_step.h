// A proxy's constrained step with surface friction, shared by the
// god-object (Ortega, Redon & Coquillart 2007, "with surface properties")
// and constrained dynamics: the generalised vector a (a displacement for the
// massless god-object, a velocity for a proxy with mass) nearest the
// unconstrained one a^u in a metric M,
//   minimise ½ (a − a^u)ᵀ M (a − a^u)   subject to   J_k a ≥ b_k,
// with Coulomb friction on the contact multipliers λ (M (a − a^u) = Σ J_kᵀ λ_k):
// a contact sticks while the tangential force it must carry is at most μ
// times its normal force, and slides with exactly μ times it otherwise.
// For the god-object, M is the coupling's stiffness K and this is the
// quasi-static Coulomb law for a massless proxy (λ in N); for constrained
// dynamics M is the step's effective mass and λ are impulses (N·s).
//
// How it is solved (repeated constraints, the exact QP, the frictional
// sweeps, the cone passes, the Coulomb residual, non-symmetric systems):
// docs/algorithms/constrained-step.md.
#pragma once

#include <span>
#include <vector>

#include "algorithms/contact/distinct_constraints.h"
#include "algorithms/contact/frictional_contact_solver.h"
#include "algorithms/contact/gauss_least_constraint.h"
#include "algorithms/contact/key_window.h"
#include "hapticbench/pose.h"

namespace hb {

struct ConstrainedStep {
  /// The constrained a: (Δ centre of mass m, rotation vector rad) or (v m/s,
  /// ω rad/s), world. When not converged: the solver's last iterate.
  Vec6 step = Vec6::Zero();
  /// Per constraint (λ_n, λ_t1, λ_t2) in the tangent basis of
  /// perpendicular_unit(normal) (frictional_contact_solver.h); with
  /// friction, the Gauss–Seidel sweeps' own (the final QP's normal
  /// multipliers differ by what the sweeps had left).
  std::vector<Vec3> impulses;
  int iterations = 0;  ///< active-set steps, plus Gauss–Seidel sweeps with friction
  bool converged = false;
  /// The step satisfies every constraint (the last QP converged): usable
  /// even when the friction sweeps stopped at their limit (converged false),
  /// with friction as far as they got, never a reason to freeze the proxy.
  bool feasible = false;
  bool with_friction = false;  ///< some contact had μ > 0
  /// Distance of the returned step from Coulomb's law, a fraction of the
  /// total normal force (see above); 0 without friction.
  double coulomb_residual = 0;
  /// solve_system only: passes of the symmetric solve (1 for a symmetric
  /// system or a step that left a_u unchanged).
  int skew_passes = 0;
};

/// A frictional step whose Coulomb residual exceeds this fraction of the
/// normal force is counted as off the cone by the renderers that use it.
constexpr double kCoulombResidualTolerance = 1e-4;

class ConstrainedStepSolver {
 public:
  /// settings: the frictional solver's sweeps and tolerance (in a's units).
  explicit ConstrainedStepSolver(const FrictionalContactSettings& settings = {300, 1e-9});

  /// metric: M, symmetric positive definite. friction: one μ per constraint
  /// (empty: all frictionless). warm_active: the previous active set of the
  /// frictionless solve, updated. warm_impulses: one per constraint, or
  /// empty.
  const ConstrainedStep& solve(const Mat6& metric, const Vec6& unconstrained,
                               std::span<const GaussConstraint> constraints,
                               std::span<const double> friction, std::vector<int>& warm_active,
                               std::span<const Vec3> warm_impulses = {});

  /// The same for a system matrix A that need not be symmetric (an
  /// implicit step's gyroscopic and rotational-coupling terms): the step a
  /// with A (a − a_u) = Σ Jᵀλ, the constraints and Coulomb's law, as a
  /// fixed point of `solve` on A's symmetric part with its skew part as a
  /// given force, at most kSkewPasses passes
  /// (docs/algorithms/constrained-step.md).
  const ConstrainedStep& solve_system(const Mat6& system, const Vec6& unconstrained,
                                      std::span<const GaussConstraint> constraints,
                                      std::span<const double> friction,
                                      std::vector<int>& warm_active,
                                      std::span<const Vec3> warm_impulses = {});

  static constexpr int kSkewPasses = 6;

 private:
  GaussLeastConstraintSolver gauss_;
  DistinctConstraints distinct_;  ///< the constraints of a solve with their repeats merged
  std::vector<int> distinct_warm_active_;
  std::vector<Vec3> distinct_warm_impulses_;
  std::vector<Vec3> expanded_impulses_;
  FrictionalContactSolver frictional_;
  std::vector<FrictionalContactRow> rows_;
  std::vector<Vec3> seed_;
  /// `solve`, building the contact rows or, with `rows_built`, keeping those
  /// of the last call (solve_system's passes after the first: the same
  /// constraints and μ; a pass that built none reached no frictional solve,
  /// and neither do the passes after it).
  /// solve_system on constraints that are all distinct.
  const ConstrainedStep& solve_system_of(const Mat6& system, const Vec6& unconstrained,
                                         std::span<const GaussConstraint> constraints,
                                         std::span<const double> friction,
                                         std::vector<int>& warm_active,
                                         std::span<const Vec3> warm_impulses);
  /// solve(constraints, friction, warm_active, warm_impulses) (a `solve`
  /// or a `solve_system`) on the distinct constraints when some repeat
  /// (distinct_constraints.h), its result and active set given back in the
  /// numbering of `constraints`; on all of them otherwise, and when the
  /// reduced solve rejects its input (so the error names the constraint by
  /// its own index).
  template <class Solve>
  const ConstrainedStep& solve_merging_repeats(std::span<const GaussConstraint> constraints,
                                               std::span<const double> friction,
                                               std::vector<int>& warm_active,
                                               std::span<const Vec3> warm_impulses, Solve&& solve);
  /// The warm start of the constraints (`count` of them) in distinct_'s
  /// numbering: distinct_warm_active_, distinct_warm_impulses_.
  void to_distinct(std::span<const int> warm_active, std::span<const Vec3> warm_impulses,
                   std::size_t count);
  /// The result of a solve of distinct_'s constraints, and its active set
  /// (from distinct_warm_active_), in the numbering of the `count` constraints given.
  const ConstrainedStep& from_distinct(std::vector<int>& warm_active, std::size_t count);
  const ConstrainedStep& solve_pass(const Mat6& metric, const Vec6& unconstrained,
                                    std::span<const GaussConstraint> constraints,
                                    std::span<const double> friction, std::vector<int>& warm_active,
                                    std::span<const Vec3> warm_impulses, bool rows_built);
  /// result_ for a new pass: the unconstrained step, no impulses.
  void start_result(const Vec6& unconstrained, std::size_t count, std::span<const double> friction);
  /// The frictionless QP into result_ (step, normal multipliers, active set).
  void solve_frictionless(const Mat6& metric, const Vec6& unconstrained,
                          std::span<const GaussConstraint> constraints,
                          std::vector<int>& warm_active);
  /// seed_: per row, the sum of its constraints' impulses in `source`.
  void seed_rows(std::span<const Vec3> source, std::size_t count);
  /// M⁻¹ (response_), kept while the metric stays the same bit for bit.
  const Mat6& response_of(const Mat6& metric);
  /// The sweeps' impulses on each row's first constraint (result_), and
  /// each row's friction (friction_forces_).
  void keep_sweep_impulses(const FrictionalContactSolution& solution, std::size_t count);
  /// The cone passes: the QP with the rows' friction held as given forces,
  /// its normal forces shared within planar contacts, the friction scaled
  /// into the cone while the sweeps had not converged; false when a QP
  /// did not converge.
  bool project_friction(const Mat6& metric, const Vec6& unconstrained, const Mat6& response,
                        std::span<const GaussConstraint> constraints, std::vector<int>& warm_active,
                        const FrictionalContactSolution& solution);
  /// The wrench (N, N·m about the centre of mass; or their impulses) of
  /// the rows' friction forces.
  Vec6 row_friction_wrench(const FrictionalContactSolution& solution) const;
  /// normal_forces_ and row_normal_ from the QP's multipliers.
  void take_qp_normals(const GaussSolution& projected, std::size_t count);
  /// Scales the rows' friction into μ times the QP's normal force in total
  /// (true), unless it is within it already or `pass` is the last (false).
  bool scale_friction_into_cone(int pass);
  /// rows_ and row_of_ for the constraints: coincident contacts merged,
  /// then reduce_coplanar_rows.
  void build_rows(std::span<const GaussConstraint> constraints, std::span<const double> friction);
  void reduce_coplanar_rows();
  void keep_hull_vertices(const Vec3& normal);
  void share_planar_loads(const FrictionalContactSolution& solution);
  /// normal_forces_ of the constraints in rows: the row's on its first, 0 on the others.
  void spread_row_normals(std::size_t constraint_count);
  double coulomb_residual(const Mat6& response, const Vec6& step,
                          std::span<const GaussConstraint> constraints,
                          std::span<const double> friction, std::span<const double> normal_forces);

  double tolerance_;
  std::vector<int> row_of_;     ///< per constraint, its row of the frictional solve (−1: none)
  std::vector<int> row_first_;  ///< per row, the constraint that made it
  std::vector<int> all_rows_;   ///< 0, 1, … (share_planar_loads)
  std::vector<int> group_of_, group_first_, group_size_, members_, new_index_;
  KeyWindow window_;  ///< rows or groups by the key of a lever or normal (constrained_step.cpp)
  KeyWindow normal_window_;  ///< the rows by the key of their normal (many rows)
  std::vector<char> keep_;
  std::vector<char> taken_;
  std::vector<std::pair<Eigen::Vector2d, int>> plane_points_;
  std::vector<int> hull_;
  std::vector<Eigen::Vector2d> friction_forces_;  ///< per row, in its (t1, t2) basis
  std::vector<double> row_normal_;                ///< per row, the normal force of the last QP
  std::vector<double> shared_normal_;
  std::vector<double> normal_forces_;  ///< per constraint
  std::vector<Vec3> pass_impulses_;    ///< solve_system: the previous pass's
  ConstrainedStep result_;
  Mat6 inverted_metric_ = Mat6::Zero();  ///< the metric response_ inverts
  Mat6 response_ = Mat6::Zero();         ///< its inverse (valid when inverted_)
  bool inverted_ = false;
};

}  // namespace hb
