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
// Frictionless contacts go to Gauss' least constraint, an exact active-set
// QP (gauss_least_constraint.h), which converges in a few steps however
// stiff or redundant the contacts; with friction the frictional contact
// solver (frictional_contact_solver.h, projected Gauss–Seidel with the exact
// circular cone) runs, warm-started from the given impulses or, without
// them, from the frictionless QP's normal multipliers (contacts at one point
// with one normal are solved once, and a planar contact of more than eight
// keeps its extreme points, reduce_coplanar_rows), and the QP then runs
// once more with its friction impulses held as given forces, so that
// non-penetration holds exactly however far the Gauss–Seidel sweeps got
// (one step of staggered projections: friction to the sweeps' accuracy,
// the normal constraints exact).
#pragma once

#include <span>
#include <vector>

#include "algorithms/core/pose.h"
#include "algorithms/god_object/gauss_least_constraint.h"
#include "algorithms/proxy/frictional_contact_solver.h"

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
};

class ConstrainedStepSolver {
 public:
  /// options: the frictional solver's sweeps and tolerance (in a's units).
  explicit ConstrainedStepSolver(const FrictionalContactOptions& options = {300, 1e-9});

  /// metric: M, symmetric positive definite. friction: one μ per constraint
  /// (empty: all frictionless). warm_active: the previous active set of the
  /// frictionless solve, updated. warm_impulses: one per constraint, or
  /// empty.
  const ConstrainedStep& solve(const Mat6& metric, const Vec6& unconstrained,
                               std::span<const GaussConstraint> constraints,
                               std::span<const double> friction, std::vector<int>& warm_active,
                               std::span<const Vec3> warm_impulses = {});

 private:
  GaussLeastConstraintSolver gauss_;
  FrictionalContactSolver frictional_;
  std::vector<FrictionalContactRow> rows_;
  std::vector<Vec3> seed_;
  void reduce_coplanar_rows();

  double tolerance_;
  std::vector<int> row_of_;  ///< per constraint, its row of the frictional solve (−1: none)
  std::vector<int> group_of_, group_first_, members_, new_index_;
  std::vector<char> keep_;
  std::vector<char> taken_;
  ConstrainedStep result_;
};

}  // namespace hb
