// The god-object's constrained displacement with surface friction (Ortega,
// Redon & Coquillart 2007, "with surface properties"): the displacement a of
// the massless proxy nearest the unconstrained one a^u in the coupling's
// metric K, subject to the contacts' non-penetration, with Coulomb friction
// on the contact forces λ = K (a − a^u) projected on the contacts: a contact
// sticks (no tangential displacement) while the tangential force it must
// carry is at most μ times its normal force, and slides with exactly μ
// times it otherwise. This is the quasi-static Coulomb law for a massless
// proxy, solved as the frictional contact problem with response K⁻¹
// (frictional_contact_solver.h). Contacts that are all frictionless go to
// Gauss' least constraint (gauss_least_constraint.h) as before.
#pragma once

#include <span>
#include <vector>

#include "algorithms/core/pose.h"
#include "algorithms/god_object/gauss_least_constraint.h"
#include "algorithms/proxy/frictional_contact_solver.h"

namespace hb {

struct ConstrainedStep {
  Vec6 step = Vec6::Zero();  ///< (Δ centre of mass m, rotation vector rad), world
  int iterations = 0;        ///< active-set steps, or Gauss–Seidel sweeps with friction
  bool converged = false;    ///< when false, `step` is zero (the proxy stays)
};

class ConstrainedStepSolver {
 public:
  /// metric: the coupling's stiffness K (coupling_metric). friction: one μ
  /// per constraint (empty: all frictionless). warm_active: the previous
  /// active set of the frictionless solve, updated.
  const ConstrainedStep& solve(const Mat6& metric, const Vec6& unconstrained,
                               std::span<const GaussConstraint> constraints,
                               std::span<const double> friction, std::vector<int>& warm_active);

 private:
  GaussLeastConstraintSolver gauss_;
  FrictionalContactSolver frictional_{FrictionalContactOptions{1000, 1e-10}};
  std::vector<FrictionalContactRow> rows_;
  ConstrainedStep result_;
};

}  // namespace hb
