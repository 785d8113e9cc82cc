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
// constraints of the solve: n·(δc + φ × r_k) ≥ −(d_k − standoff), n the
// direction between the pair's closest points and d_k their distance. For
// translations this is a sufficient condition (a feature pair's distance is
// convex in the translation); rotations add at most |φ|² r / 2 per tick.
#pragma once

#include <cstdint>
#include <vector>

#include "algorithms/ccd/mesh_ccd.h"
#include "algorithms/core/pose.h"
#include "algorithms/core/scene.h"
#include "algorithms/god_object/constrained_step.h"
#include "algorithms/god_object/god_object_update.h"
#include "algorithms/god_object/proximity_certifier.h"
#include "algorithms/god_object/proxy_motion.h"
#include "algorithms/proxy/renderer.h"

namespace hb {

/// What one haptic tick did.
struct HapticSolveStats {
  int64_t pairs_evaluated = 0;  ///< feature pairs re-evaluated at the proxy's pose
  int64_t qp_iterations = 0;
  bool bounded = false;  ///< the motion was shortened to stay within the certificate's reach
};

class HapticProxy {
 public:
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

 private:
  double coupling_energy(const Pose& tool_pose, const Pose& target) const;

  ProximityCertifier certifier_;
  CouplingGains gains_;
  GodObjectSettings settings_;
  std::vector<double> friction_;  ///< μ per scene object
  ConstrainedStepSolver solver_;
  std::vector<GaussConstraint> constraints_;
  std::vector<double> constraint_friction_;  ///< μ per constraint
  std::vector<int> warm_active_;
  std::vector<Vec3> warm_impulses_;  ///< the last frictional solve's, per listed pair
  std::vector<Vec3> carried_;
  ProximityCertificate certificate_;
  Pose pose_;
  std::vector<Contact> contacts_;
  std::vector<double> distances_;  ///< per listed pair at the start of the tick (m)
};

}  // namespace hb
