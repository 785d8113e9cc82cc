#include "algorithms/god_object/god_object_update.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "algorithms/contact/proxy_motion.h"
#include "algorithms/god_object/coupling_metric.h"

namespace hb {

namespace {

// The tool as the CCD sees it: its mesh in a frame at its centre of mass,
// or the single point at its frame's origin.
TriangleMesh ccd_tool_mesh(const Tool& tool, bool point_tool) {
  TriangleMesh mesh;
  if (point_tool) {
    mesh.vertices = {Vec3::Zero()};
    mesh.triangles = {{0, 0, 0}};
    return mesh;
  }
  mesh = tool.mesh;
  for (Vec3& vertex : mesh.vertices) vertex -= tool.mass.centre_of_mass;
  return mesh;
}

Pose pose_on(const ScrewMotion& motion, double t) {
  return Pose{motion.point_at(Vec3::Zero(), t), Quat(motion.rotation_at(t)).normalized()};
}

// Whether a feature pair's geometry is a constraint worth keeping. An
// edge–edge pair whose closest points are not inside both segments (a
// vertex of one edge is nearest) has a normal from the lines, not from the
// contact: that contact is held by the vertex's own vertex–face pairs.
bool usable(const ContactFeatures& features, const FeatureGeometry& geometry,
            double contact_distance) {
  if (!(geometry.distance <= contact_distance)) return false;
  if (features.kind != ContactFeatureKind::kEdgeEdge) return true;
  return geometry.distance - std::abs(geometry.gap) <= 1e-9 * geometry.distance + 1e-15;
}

}  // namespace

StartEscape GodObjectSolver::escape(const Pose& start) const {
  StartEscape result{start, 0.0, false};
  const auto [scene_centre, scene_radius] = ccd_.scene_bounding_sphere();
  if (scene_radius < 0) return result;
  const Pose com = frames_.com_frame(start);
  const double radius = settings_.point_tool ? 0.0 : ccd_.tool_radius();
  // From this far along any direction the tool is outside the scene's sphere.
  const double length =
      (com.p - scene_centre).norm() + scene_radius + radius + 2 * settings_.standoff_m;
  double shortest = std::numeric_limits<double>::infinity();
  Pose shortest_pose = com;
  // Straight up first: a free start above the scene is proven so at once.
  for (int z : {1, -1, 0})
    for (int x = -1; x <= 1; ++x)
      for (int y = -1; y <= 1; ++y) {
        if (x == 0 && y == 0 && z == 0) continue;
        const Vec3 direction = Vec3(x, y, z).normalized();
        const ScrewMotion motion(Pose{com.p + length * direction, com.q}, com);
        const MeshCcdResult hit = ccd_.first_contact(motion, settings_.ccd);
        if (!hit.contact) return result;
        const double stop = std::max(0.0, hit.toi - settings_.standoff_m / length);
        if (length * (1 - stop) < shortest) {
          shortest = length * (1 - stop);
          shortest_pose = pose_on(motion, stop);
        }
      }
  result.pose = frames_.tool_frame(shortest_pose);
  result.distance_m = shortest;
  result.escaped = true;
  return result;
}

GodObjectSolver::GodObjectSolver(const RenderContext& context, const GodObjectSettings& settings)
    : settings_(settings),
      gains_(context.coupling),
      frames_{settings.point_tool ? Vec3::Zero() : context.tool.mass.centre_of_mass},
      ccd_(ccd_tool_mesh(context.tool, settings.point_tool), context.scene) {
  for (const SceneObject& object : context.scene) friction_.push_back(object.friction);
}

void GodObjectSolver::reset(const Pose& start) {
  proxy_ = start;
  contacts_.clear();
  warm_active_.clear();
}

void GodObjectSolver::refresh_contacts() {
  const Pose frame = frames_.com_frame(proxy_);
  std::erase_if(contacts_, [&](KeptContact& contact) {
    contact.geometry = ccd_.evaluate(contact.features, frame);
    return !usable(contact.features, contact.geometry, settings_.contact_distance_m);
  });
}

GodObjectUpdateStats GodObjectSolver::update(const Pose& target,
                                             const ProximityCertificate* certificate) {
  GodObjectUpdateStats stats;
  const double radius = settings_.point_tool ? 0.0 : ccd_.tool_radius();
  // Below this largest point displacement (m) a motion counts as none.
  constexpr double kNegligibleMotion = 1e-12;
  auto reach = [&](const Vec6& d) { return point_reach(d, radius); };

  for (int iteration = 0; iteration < settings_.max_iterations; ++iteration) {
    refresh_contacts();
    const Pose start = frames_.com_frame(proxy_);
    const Vec6 unconstrained = displacement(start, frames_.com_frame(target));
    if (reach(unconstrained) <= kNegligibleMotion) {
      stats.reached_device = true;
      break;
    }

    constraints_.clear();
    constraint_friction_.clear();
    for (const KeptContact& contact : contacts_) {
      const FeatureGeometry& g = contact.geometry;
      constraints_.push_back(GaussConstraint{g.normal, g.point - start.p,
                                             -std::max(0.0, g.gap - settings_.standoff_m)});
      constraint_friction_.push_back(friction_[contact.features.scene_object]);
    }
    const ConstrainedStep& solved =
        solver_.solve(coupling_metric(gains_, frames_.centre_of_mass, proxy_.q, ccd_.tool_radius()),
                      unconstrained, constraints_, constraint_friction_, warm_active_);
    stats.qp_iterations += solved.iterations;
    stats.coulomb_violations += solved.coulomb_residual > kCoulombResidualTolerance;
    if (!solved.feasible) {
      stats.solver_failed = true;
      break;
    }
    Vec6 constrained = solved.step;
    if (reach(constrained) <= kNegligibleMotion) break;

    // Within the certificate's reach only its pairs can meet: a move that
    // would leave it is cut at its boundary and is the update's last (the
    // path's point displacement from the anchor is convex along the screw
    // motion, a line for the centre and a geodesic for the rotation, so a
    // path whose ends are within reach stays within it). Only a start with
    // no room left (a crowded contact whose 64 pairs end close to the
    // standoff) falls back to the whole mesh CCD.
    double fraction = 1.0;
    if (certificate != nullptr)
      fraction = fraction_within_reach(certificate->anchor, start, constrained, radius,
                                       certificate->clearance_m - settings_.standoff_m);
    const bool certified = certificate != nullptr && fraction > 0;
    const bool last_move = certified && fraction < 1;
    if (certified) constrained *= fraction;
    const ScrewMotion motion(start, displaced(start, constrained));
    stats.certified_moves += certified;
    const MeshCcdResult hit =
        certified ? ccd_.first_contact_among(motion, certificate->pairs, settings_.ccd)
                  : ccd_.first_contact(motion, settings_.ccd);
    ++stats.iterations;
    stats.bv_tests += hit.bv_tests;
    stats.primitive_queries += hit.primitive_queries;
    stats.budget_hits += hit.budget_exhausted;
    if (!hit.contact) {
      proxy_ = frames_.tool_frame(pose_on(motion, 1.0));
      if (last_move) break;
      continue;
    }
    ++stats.ccd_hits;

    // Back off from the first contact so the fastest-approaching contact
    // keeps about `standoff` of separation (never less than a tenth of the
    // path's speed is assumed, so a grazing hit still makes progress).
    const Vec3 com_at_hit = motion.point_at(Vec3::Zero(), hit.toi);
    double approach_speed = 0.1 * reach(constrained);  // m per unit t
    for (const MeshCcdContact& contact : hit.contacts) {
      const Vec3 lever = contact.geometry.point - com_at_hit;
      const Vec3 velocity = constrained.head<3>() + constrained.tail<3>().cross(lever);
      approach_speed = std::max(approach_speed, -contact.geometry.normal.dot(velocity));
    }
    const double stop = std::max(0.0, hit.toi - settings_.standoff_m / approach_speed);
    proxy_ = frames_.tool_frame(pose_on(motion, stop));

    const Pose stopped = frames_.com_frame(proxy_);
    for (const MeshCcdContact& contact : hit.contacts) {
      const bool known =
          std::any_of(contacts_.begin(), contacts_.end(),
                      [&](const KeptContact& kept) { return kept.features == contact.features; });
      if (known) continue;
      const FeatureGeometry geometry = ccd_.evaluate(contact.features, stopped);
      if (usable(contact.features, geometry, settings_.contact_distance_m))
        contacts_.push_back({contact.features, geometry});
    }
  }
  refresh_contacts();
  return stats;
}

}  // namespace hb
