// Closed-form ground truth for the scenes it covers: exactly one box in the
// scene and a tool that is a sphere or a box. It answers two questions about
// a pose: what a perfectly rigid, frictionless, quasi-static rendering would
// display for a device pose (the ideal rendering every algorithm's force and
// torque are compared against), and how deep a posed tool penetrates the box.
// Units: m, N, N·m, rad, J. Poses: translation + unit quaternion, written in
// the order qw,qx,qy,qz. All vectors are in the world frame unless a comment
// says otherwise.
#pragma once

#include <optional>
#include <string>

#include "hapticbench/pose.h"
#include "hapticbench/scene.h"
#include "hapticbench/shapes.h"
#include "harness/reference/tunnelling.h"

namespace hb {

/// A scene the closed forms cover: one scene object that is a primitive box,
/// a tool that is a primitive sphere or box (each centred on its own frame),
/// and no gravity.
struct AnalyticScene {
  Pose box_pose;                            ///< scene box frame (centred on the box) -> world
  Vec3 box_half_extents = Vec3::Zero();     ///< m, along the box frame's axes
  Shape tool_shape;                         ///< ShapeType::kSphere or ShapeType::kBox
  Vec3 tool_centre_of_mass = Vec3::Zero();  ///< m, tool frame. Kept for callers that need
                                            ///< torques about it; the frictionless
                                            ///< quasi-static rendering without gravity
                                            ///< does not depend on it.
  CouplingGains coupling;  ///< k_t (N/m) and k_r (N·m/rad) here; b_t, b_r in IdealCouplingDamper
  double friction = 0;     ///< Coulomb μ of the box (its scene object's "friction")
};

/// The analytic scene of a render context, or nullopt when the closed forms do
/// not cover it: not exactly one scene object, a scene object that is not a
/// primitive box, a tool that is a mesh or a capsule/box_with_hole, a
/// non-positive size, non-zero gravity (the quasi-static rendering would then
/// depend on each algorithm's own proxy mass), or a non-positive coupling
/// stiffness. When nullopt is returned and reason_not_covered is given, it
/// receives one sentence saying why.
std::optional<AnalyticScene> make_analytic_scene(const RenderContext& context,
                                                 std::string* reason_not_covered = nullptr);

/// The ideal rigid-contact rendering of one device pose.
struct IdealRendering {
  /// Tool-frame pose of the ideal proxy: the pose minimising the coupling
  /// spring energy ½ k_T |x_h − x_p|² + ½ k_R |θ(q_h q_p⁻¹)|² over poses where
  /// the tool does not penetrate the box (see ideal_rigid_contact for the
  /// exact feasible set).
  Pose proxy;
  /// What the device displays: −(spring part of the coupling) at the proxy,
  /// force k_T (x_p − x_h) in N, torque −k_R θ(q_h q_p⁻¹) in N·m about the tool
  /// frame's origin, world frame. The spring part only: the coupling's
  /// damper on the proxy's path is IdealCouplingDamper's
  /// (coupling_damper.h), which the run's evaluation adds. No device
  /// saturation: a caller comparing with a saturated output applies the limits.
  Wrench display;
  /// True when the device pose penetrates the box, i.e. the constraint is active.
  bool in_contact = false;
  /// World frame, unit length, out of the box: for the sphere the direction
  /// from the device's centre to the proxy's, for the box tool the normal of
  /// the box face the proxy rests on. Zero when not in contact.
  Vec3 contact_normal = Vec3::Zero();
  /// exact_penetration_depth of the tool at the device pose (m, ≥ 0).
  double device_penetration_m = 0;
};

/// The ideal rigid-contact rendering for a device pose (frictionless,
/// quasi-static, massless proxy).
///
/// Sphere tool: exact. The proxy's centre is the device's sphere centre (the
/// tool frame's origin) projected onto the closed region at distance ≥ r from
/// the box (the outside of the box grown by the radius); its orientation is
/// the device's, so the torque is zero. A centre inside the box leaves
/// through the nearest face (the nearest point of the grown box's surface);
/// near an edge or corner the proxy lies on the rounded part.
///
/// Box tool: the feasible set is restricted to poses where the tool lies
/// wholly on the outer side of one of the box's six face planes (each face
/// taken as a half-space boundary). The returned pose is the global minimiser
/// of the energy over that set, computed exactly (to rounding): for each face,
/// the optimal translation for a given orientation is closed-form, the
/// orientation reduces to the face normal's direction u in tool coordinates
/// (the nearest orientation with a given u is the minimal swing), and the
/// minimum over u on the sphere is found among its stationary points on a
/// great circle and on the three octant edges, each bracketed by sampling and
/// narrowed by bisection to machine precision; the face with the lowest
/// energy wins. This is the true rigid-contact optimum whenever the optimal
/// proxy rests against one face of the box (vertex, edge or face of the tool
/// on the face, anywhere over its plane); a tool resting on a box edge or
/// corner, or touching two faces at once, is not covered, and the proxy
/// returned then is feasible but may have a higher energy than the true
/// optimum. Where the energy has several local minima (a tall tool pressed
/// hard enough to tip over), the global one is returned, which a
/// path-following proxy may not reach.
IdealRendering ideal_rigid_contact(const AnalyticScene& scene, const Pose& device);

/// The ideal rendering with Coulomb friction μ = scene.friction at the box,
/// followed tick by tick, since with friction the ideal proxy depends on the
/// path. Quasi-static: while the frictionless ideal proxy
/// (ideal_rigid_contact) rests on one face of the box, with outward normal n
/// and normal force F_n (its display force along n), the frictional proxy
/// sits at p = p₀ + d with d ⟂ n. A box tool keeps its place on the face
/// while the tangential coupling force k_T |d| ≤ μ F_n (stick; the face
/// carries the tipping moment, so it does not turn). A sphere tool sticking
/// may still roll and pivot about its contact point (no point of it
/// slides): its pose is the one of least coupling energy among those rolled
/// from the last (rolled_sphere), held while its tangential force is at
/// most μ F_n; the rotational coupling is then in series with the
/// translational one, (1/k_T + r²/k_R)⁻¹ along the face. Otherwise the
/// proxy slides, staying behind the device in the same direction with
/// k_T |d| = μ F_n (slip); the display adds k_T d to the frictionless force,
/// and a sphere's the friction's moment about its centre, (−r n) × k_T d,
/// its proxy turned so that the rotational coupling balances it. Out of
/// contact, when the face changes, and where the sphere's ideal proxy lies
/// on a rounded edge or corner rather than on one face, d is dropped. Not
/// modelled: a box tool's friction against a twist (it depends on how the
/// load spreads over its face), a proxy kept by friction beyond the face's
/// edge. With μ = 0 it returns ideal_rigid_contact unchanged.
class FrictionalContactReference {
 public:
  explicit FrictionalContactReference(const AnalyticScene& scene) : scene_(scene) {}
  /// The ideal rendering for the next device pose.
  IdealRendering update(const Pose& device);
  /// The last update was in contact on one face and no point of the tool slid (a sphere may roll).
  bool sticking() const { return sticking_; }

 private:
  Pose rolled_sphere(const Vec3& p, const Quat& q, const Vec3& n, const Pose& device) const;

  const AnalyticScene& scene_;
  std::optional<Vec3> last_proxy_p_;  ///< m, world: the proxy's position at the last face contact
  Quat last_proxy_q_ = Quat::Identity();  ///< the proxy's orientation then
  Vec3 last_normal_ = Vec3::Zero();       ///< unit, world: that contact's face normal
  bool sticking_ = false;
};

/// Exact penetration depth (m, ≥ 0) of the tool placed at tool_pose into the
/// box: the length of the shortest translation that separates the tool from
/// the box's interior (zero when they do not overlap).
///
/// Sphere: radius − signed distance of the centre to the box, clamped at 0.
/// Box: the smallest overlap of the two boxes' projections over the 15
/// separating-axis candidates (3 face normals of each box and the 9 edge-edge
/// cross products); every facet normal of the boxes' Minkowski difference is
/// among them, so this minimum is exactly the distance from the origin to that
/// difference's boundary. Edge pairs closer than 1e-9 rad to parallel are
/// skipped (their facets are then bounded by the face axes to within
/// 1e-9 × size).
///
/// It is an upper bound on the depth of every tool point inside the box (a
/// point at depth d needs a translation of at least d to leave), and equals
/// the largest depth of a tool vertex below a face when the tool enters
/// through that face alone and the vertex is nearer that face than any other.
double exact_penetration_depth(const AnalyticScene& scene, const Pose& tool_pose);

/// Tunnelling through the scene box (tunnelling.h gives the definition), in
/// closed form: the box's nearest point and a segment–box test.
class BoxTunnellingDetector final : public TunnellingDetector {
 public:
  explicit BoxTunnellingDetector(const AnalyticScene& scene) : scene_(scene) {}
  bool update(const Vec3& origin_world) override;

 private:
  const AnalyticScene& scene_;
  std::optional<Vec3> last_point_;  ///< box frame, m: the last position outside
  Vec3 last_side_ = Vec3::Zero();   ///< unit, box frame: its side then
  bool last_tick_outside_ = false;  ///< the previous tick's position was outside
};

}  // namespace hb
