// One update of the 6-DOF god-object (lecture notes, "Constraint-Based Proxy
// Solver" to "CCD Summary"; Ortega, Redon & Coquillart 2007): a massless
// proxy that follows the device as far as the scene lets it and never
// penetrates it. Each iteration refreshes the kept contacts, solves Gauss'
// least constraint in the coupling's stiffness metric for the step toward
// the device (Δ centre of mass m, rotation vector rad, world), and moves
// along it until the mesh CCD's first contact, backed off to keep
// `standoff` (m); it stops at the device, when the step vanishes, or after
// `max_iterations` (docs/algorithms/god-object.md). The proxy's frame for
// CCD is the tool's centre of mass with the tool frame's axes.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "algorithms/ccd/mesh_ccd.h"
#include "algorithms/contact/constrained_step.h"
#include "algorithms/contact/contact_geometry.h"
#include "algorithms/contact/contact_settings.h"
#include "algorithms/contact/proximity_certifier.h"
#include "algorithms/contact/proxy_motion.h"
#include "hapticbench/pose.h"
#include "hapticbench/scene.h"

namespace hb {

/// The god-object's settings: its contact handling, as for constrained
/// dynamics (contact_settings.h), and its slow loop's moves.
struct GodObjectSettings : ContactSettings {
  /// Most CCD-limited moves per update, ≥ 1.
  int max_iterations = 8;
  /// The haptic tick solves every listed pair, not only those that can
  /// matter within it (HapticProxy::step): what the culling is compared to.
  bool haptic_all_pairs = false;
};

/// A contact the proxy keeps between iterations and updates.
struct KeptContact {
  ContactFeatures features;
  FeatureGeometry geometry;  ///< at the proxy's current pose
};

/// Added (m) to the reach within which a listed pair may touch during a
/// move: room for the rounding of the distances and displacements.
inline constexpr double kPairCullMargin = 1e-9;

/// The certificate's pairs that may touch while the tool's centre-of-mass
/// frame moves by `move` (a screw displacement, world) from `start`: those
/// whose distance at the anchor is within the largest displacement of a
/// tool point (within `radius`, m, of the centre of mass) from the anchor
/// to anywhere on the move, plus kPairCullMargin. A prefix of
/// certificate.pairs (their distances ascend); the others cannot meet on
/// the move, so its continuous collision check leaves them out.
std::span<const ContactFeatures> pairs_within_move(const ProximityCertificate& certificate,
                                                   const Pose& start, const Vec6& move,
                                                   double radius);

/// What one update did.
struct GodObjectUpdateStats {
  int iterations = 0;          ///< CCD-limited moves made
  int ccd_hits = 0;            ///< moves the CCD stopped short
  int certified_moves = 0;     ///< moves checked on a certificate's pairs only
  int budget_hits = 0;         ///< moves whose CCD had a kernel answer by its budget fallback
  int certificates = 0;        ///< proximity queries made for the update (by its caller)
  int proximity_searches = 0;  ///< tree searches those queries took (the rest reused pairs)
  /// Searches ahead those queries took, worked in slices by the queries before.
  int proximity_searches_ahead = 0;
  int64_t bv_tests = 0;
  int64_t primitive_queries = 0;
  int64_t qp_iterations = 0;
  int coulomb_violations = 0;   ///< frictional solves off Coulomb's law (constrained_step.h)
  bool reached_device = false;  ///< the proxy ended on the device's pose
  bool solver_failed = false;   ///< the least-constraint solve did not converge (the proxy stayed)
};

/// The god-object's proxy and contacts, and the update that moves them.
class GodObjectSolver {
 public:
  /// Settings as read by read_god_object_settings (god_object.h).
  GodObjectSolver(const RenderContext& context, const GodObjectSettings& settings);

  /// Puts the proxy at the tool-frame pose `start` with no contacts.
  void reset(const Pose& start);

  /// Moves the proxy toward the device's tool-frame pose `target`. With a
  /// certificate, a move that stays within its reach is checked by the
  /// kernels of its listed pairs only (MeshCcd::first_contact_among), a
  /// move beyond it by the whole mesh CCD.
  GodObjectUpdateStats update(const Pose& target,
                              const ProximityCertificate* certificate = nullptr);

  /// The proxy's tool-frame pose (world) and its contacts at that pose.
  const Pose& proxy_pose() const { return proxy_; }
  const std::vector<KeptContact>& contacts() const { return contacts_; }

  /// Moves the proxy to the tool-frame pose `pose` (known to be free), keeping
  /// its contacts, which the next update refreshes there.
  void move_proxy(const Pose& pose) { proxy_ = pose; }
  /// The CCD structures, the tool's frames, the scene's friction and the
  /// start escape (contact_geometry.h), which the haptic proxy uses too.
  const ContactGeometry& geometry() const { return geometry_; }

 private:
  void refresh_contacts();
  /// The tool's radius about its centre of mass (m; 0 for a point tool).
  double radius() const;
  /// The largest displacement (m) of a tool point under `motion` (point_reach).
  double reach(const Vec6& motion) const;
  /// constraints_ and constraint_friction_ from the kept contacts, levers
  /// from the centre-of-mass pose `start`.
  void build_constraints(const Pose& start);
  /// Moves the proxy from the centre-of-mass pose `start` along the step
  /// `constrained` (cut at the certificate's reach) until the CCD's first
  /// contact, backed off; adds the contacts found. False when the update
  /// ends with it (the move was cut at the certificate's reach).
  bool move(const Pose& start, Vec6 constrained, const ProximityCertificate* certificate,
            GodObjectUpdateStats& stats);
  /// The time on `motion` (the step `constrained`) to stop at before the
  /// CCD's hit, so that the fastest-approaching contact keeps about the standoff.
  double stop_before(const ScrewMotion& motion, const Vec6& constrained,
                     const MeshCcdResult& hit) const;
  /// The hit's contacts not yet kept, usable at the proxy's pose.
  void add_new_contacts(const MeshCcdResult& hit);

  GodObjectSettings settings_;
  CouplingGains gains_;
  ContactGeometry geometry_;
  ConstrainedStepSolver solver_;
  std::vector<GaussConstraint> constraints_;
  std::vector<double> constraint_friction_;  ///< μ per constraint
  std::vector<int> warm_active_;
  Pose proxy_;
  std::vector<KeptContact> contacts_;
  /// The proxy pose at which every kept contact's geometry was last
  /// evaluated (refresh_contacts); none after a reset or a new contact.
  std::optional<Pose> contacts_pose_;
  std::vector<ContactFeatures> refreshed_features_;  ///< refresh_contacts' scratch
  std::vector<FeatureGeometry> refreshed_geometry_;
};

}  // namespace hb
