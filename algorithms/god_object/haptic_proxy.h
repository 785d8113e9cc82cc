// The god-object's haptic-rate part (lecture notes: the constraint solve at
// the haptic rate, collision detection and contact discovery at a slower
// one). Every tick the proxy moves toward the device by Gauss' least
// constraint on the feature pairs the slow loop found near it, each
// re-evaluated at the current pose, without any collision detection.
//
// Why the proxy cannot pass a feature the slow loop has not seen: the slow
// loop hands over a proximity certificate, an anchor pose with every
// feature pair (tool vertex–scene face, scene vertex–tool face, edge–edge)
// closer than a clearance c listed (MeshCcd::proximity). Between
// certificates the proxy stays within reach ρ = c − standoff of the anchor:
// no point of the tool is farther than ρ from where it was at the anchor
// (bounded by |Δc| + |φ| r, r the tool's radius about its centre of mass),
// so every pair not listed stays at least `standoff` apart, along the
// straight path between any two poses too. The listed pairs are the
// constraints of the solve: n·(δc + φ × r_k) ≥ standoff − d_k, n the
// direction between the pair's closest points and d_k their distance: a pair
// closer than the standoff is pushed back out to it. The linearised
// constraint is exact for a vertex–face pair under translation; a rotation
// moves a contact point by a further ½ φ × (φ × r), toward the surface when
// the point lies beyond the centre of mass along the normal (a hook), and an
// edge–edge pair's closest points slide along nearly parallel edges by far
// more. So after the solve every listed pair's exact distance at the end
// pose is measured, signed by the side the pair started on (a pair whose
// direction between closest points turned over has crossed); a pair short
// of its floor, min(standoff − kStandoffSlackM, d_k) (never below where it
// started the tick, so no floor creeps down tick by tick), is asked for its
// shortfall more in a new solve (at most kCorrections times), and what
// still falls short is cut to the largest fraction of the step that keeps
// every pair above its floor. The floor holds at every tick.
//
// Only the listed pairs that can matter within the tick are solved and
// measured: a pair d apart at the anchor is at least d − (reach from the
// anchor to the tick's start) − (reach of the step) apart at its end, and
// its linearised constraint holds for any step of reach below d − standoff.
// The step is allowed twice the last tick's reach (kNearFloorM at least);
// the pairs nearer than max(standoff, contact distance) + those reaches are
// the solve's (a prefix: the certificate lists pairs by ascending
// distance), and a solve whose step reaches farther is done again with
// every listed pair (HapticSolveStats::widened).
#pragma once

#include <cstdint>
#include <vector>

#include "algorithms/ccd/mesh_ccd.h"
#include "algorithms/contact/constrained_step.h"
#include "algorithms/contact/feature_pair_index.h"
#include "algorithms/contact/proximity_certifier.h"
#include "algorithms/contact/proxy_motion.h"
#include "algorithms/god_object/god_object_update.h"
#include "hapticbench/pose.h"
#include "hapticbench/renderer.h"
#include "hapticbench/scene.h"

namespace hb {

/// What one haptic tick did.
struct HapticSolveStats {
  int64_t pairs_evaluated = 0;  ///< feature pairs re-evaluated at the proxy's pose
  int64_t qp_iterations = 0;
  bool bounded = false;  ///< the motion was shortened to stay within the certificate's reach
  int corrections = 0;   ///< solves repeated for pairs that fell short of their floor
  bool cut = false;      ///< the step was cut to keep every pair above its floor
  /// frictional solves off Coulomb's law by more than kCoulombResidualTolerance
  int coulomb_violations = 0;
  /// solves done again with every listed pair: the step reached farther
  /// than the pairs left out allowed (HapticProxy::step)
  int widened = 0;
  /// listed pairs the tick solved and checked (the others cannot matter)
  int64_t pairs_solved = 0;
};

class HapticProxy {
 public:
  /// How far below the standoff a listed pair may end a tick (m).
  static constexpr double kStandoffSlackM = 1e-7;
  /// Solves repeated with corrected right-hand sides before a cut.
  static constexpr int kCorrections = 2;
  /// The least reach (m) a tick's step is allowed before the pairs that
  /// cannot matter within it are left out of its solve (HapticProxy::step).
  static constexpr double kNearFloorM = 1e-6;
  /// Halvings of the fraction when a step is cut.
  static constexpr int kCutBisections = 20;

  /// `ccd` must outlive the proxy. Settings as for the slow loop's solver.
  /// friction: Coulomb μ per scene object (MeshCcd's indices); empty: none.
  HapticProxy(const MeshCcd& ccd, const CouplingGains& gains, const GodObjectSettings& settings,
              const Vec3& centre_of_mass, std::vector<double> friction = {});

  /// The proximity query, band and reach (proximity_certifier.h).
  ProximityCertificate certify(const Pose& tool_pose, double band_m) const {
    return certifier_.certify(tool_pose, band_m);
  }
  double band_for(const Pose& previous_target, const Pose& target) const {
    return certifier_.band_for(previous_target, target);
  }
  double widest_band() const { return certifier_.widest_band(); }
  bool within_reach(const ProximityCertificate& certificate, const Pose& tool_pose) const {
    return certifier_.within_reach(certificate, tool_pose);
  }

  /// Puts the proxy at the tool-frame pose `start` (free of the scene) with
  /// a certificate computed there.
  void reset(const Pose& start);

  /// A certificate from the slow loop, found at the tool-frame pose
  /// `slow_proxy` (where the slow update's CCD-limited moves ended). Taken
  /// when the proxy lies within its reach; otherwise, when the slow proxy
  /// is nearer the device `target` in the coupling's energy (the haptic
  /// proxy is held back), the proxy moves there and takes it; otherwise the
  /// current certificate stays. Returns whether the certificate was taken.
  bool offer(ProximityCertificate certificate, const Pose& slow_proxy, const Pose& target);

  /// One haptic tick toward the device's tool-frame pose `target`.
  HapticSolveStats step(const Pose& target);

  const Pose& pose() const { return pose_; }  ///< tool frame, world
  /// Listed pairs within the contact distance at the current pose.
  const std::vector<Contact>& contacts() const { return contacts_; }
  const ProximityCertificate& certificate() const { return certificate_; }
  /// The least distance (m) between the features of a listed pair at the
  /// current pose; infinity without listed pairs.
  double least_listed_distance() const;

 private:
  double coupling_energy(const Pose& tool_pose, const Pose& target) const;
  /// The least margin over the solved pairs at the centre-of-mass pose
  /// `com_pose`: signed distance (by the side the pair started the tick on)
  /// minus its floor; fills end_distances_ and end_contacts_.
  double worst_margin(const Pose& com_pose);
  /// The tick's solve on the first `near` listed pairs from the
  /// centre-of-mass pose `start`: fills `moved`; returns false, having
  /// moved nothing, when a solve's step reaches farther than `allowance`
  /// (m) and some pairs were left out.
  bool solve_near(std::size_t near, const Pose& start, const Vec6& unconstrained, double allowance,
                  Vec6& moved, HapticSolveStats& stats, bool carried);
  /// After a certificate taken at the same pose: the pairs both certificates
  /// list keep their measurement at com_pose_ (end_contacts_, measured_).
  void carry_measured_pairs(const std::vector<ContactFeatures>& previous);

  ProximityCertifier certifier_;
  CouplingGains gains_;
  GodObjectSettings settings_;
  std::vector<double> friction_;  ///< μ per scene object
  ConstrainedStepSolver solver_;
  std::vector<GaussConstraint> constraints_;
  std::vector<double> constraint_friction_;  ///< μ per constraint
  std::vector<int> warm_active_;
  std::vector<Vec3> warm_impulses_;  ///< the last frictional solve's, per listed pair
  /// warm_impulses_ and warm_active_ as the tick began (HapticProxy::step).
  std::vector<Vec3> tick_warm_impulses_;
  std::vector<int> tick_warm_active_;
  std::vector<Vec3> carried_;
  ProximityCertificate certificate_;
  Pose pose_;
  /// The centre-of-mass pose the last tick ended at, while pose_ is its
  /// tool frame: the next tick starts there (com_frame(pose_) would differ
  /// from it by rounding).
  Pose com_pose_;
  bool com_pose_current_ = false;
  /// Per listed pair: end_contacts_ holds it measured at com_pose_ (by the
  /// last tick's check, carried over a new certificate that lists it too),
  /// so the next tick need not measure it again at its start.
  std::vector<char> measured_;
  /// m: the largest reach of a solve's step in the last tick (HapticProxy::step).
  double last_step_reach_ = 0;
  std::vector<char> carried_measured_;  ///< measured_ of the next certificate, being filled
  std::vector<PairContact> carried_contacts_;
  FeaturePairIndex previous_index_;  ///< the last certificate's pairs, to match the next's
  std::vector<Contact> contacts_;
  std::vector<double> floors_;         ///< per solved pair: the least distance it may end at (m)
  std::vector<double> end_distances_;  ///< per solved pair at the end pose tried, signed (m)
  std::vector<PairContact> end_contacts_;  ///< per listed pair at the end pose tried
  std::vector<PairContact> evaluated_;     ///< scratch of worst_margin
};

}  // namespace hb
