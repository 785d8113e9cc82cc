// The god-object's haptic-rate part (lecture notes: the constraint solve at
// the haptic rate, collision detection and contact discovery at a slower
// one). Every tick the proxy moves toward the device by Gauss' least
// constraint on the feature pairs the slow loop's proximity certificate
// lists near it, each re-evaluated at the current pose, without any
// collision detection: it stays within the certificate's reach, so no pair
// left unlisted comes within the standoff, and every solved pair's exact
// distance at the end pose is kept above its floor, min(standoff −
// kStandoffSlackM, its distance at the tick's start) (m). Why this holds,
// and which pairs a tick solves: docs/algorithms/god-object.md.
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

  /// The proximity query, band and reach (proximity_certifier.h). The
  /// query's workspace is the querying thread's (the slow loop's).
  ProximityCertificate certify(ProximityCertifier::QueryWorkspace& queries, const Pose& tool_pose,
                               double band_m) const {
    return certifier_.certify(queries, tool_pose, band_m);
  }
  double band_for(const Pose& previous_target, const Pose& target) const {
    return certifier_.band_for(previous_target, target);
  }
  double widest_band() const { return certifier_.widest_band(); }
  bool within_reach(const ProximityCertificate& certificate, const Pose& tool_pose) const {
    return certifier_.within_reach(certificate, tool_pose);
  }

  /// Puts the proxy at the tool-frame pose `start` (free of the scene) with
  /// a certificate computed there, `queries` forgotten first (the slow
  /// loop's workspace, which no query uses meanwhile).
  void reset(const Pose& start, ProximityCertifier::QueryWorkspace& queries);

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
  /// constraints_, constraint_friction_ and floors_ of the first `near`
  /// listed pairs at the centre-of-mass pose `start` (measured there unless
  /// `carried` from the last tick's check).
  void build_near_constraints(std::size_t near, const Pose& start, bool carried,
                              HapticSolveStats& stats);
  /// The constrained step (Δ centre of mass m, rotation vector rad, world)
  /// on constraints_, warm-started from the last solve; zero when infeasible.
  Vec6 solve_step(std::size_t near, const Pose& start, const Vec6& unconstrained,
                  HapticSolveStats& stats);
  /// Cuts `moved` to the largest fraction (bisected) that keeps every solved
  /// pair above its floor, leaving end_contacts_ measured there.
  void cut_step(const Pose& start, Vec6& moved, HapticSolveStats& stats);
  /// Raises each pair short of its floor by its shortfall below the standoff.
  void ask_for_shortfalls();
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
  /// The haptic tick's scratch of the certifier's evaluations.
  ProximityCertifier::EvaluationWorkspace evaluation_;
};

}  // namespace hb
