#include "algorithms/god_object/god_object_update.h"

#include <algorithm>
#include <cmath>

#include "algorithms/contact/proxy_motion.h"
#include "algorithms/god_object/coupling_metric.h"

namespace hb {

namespace {

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

// Below this largest point displacement (m) a motion counts as none.
constexpr double kNegligibleMotion = 1e-12;

}  // namespace

std::span<const ContactFeatures> pairs_within_move(const ProximityCertificate& certificate,
                                                   const Pose& start, const Vec6& move,
                                                   double radius) {
  // A pair at distance d at the anchor is at least d − (reach from the
  // anchor to the start) − (reach of the move) apart anywhere on the move:
  // no tool point moves farther (point_reach bounds the screw motion's
  // whole path by its end), and the distance between two features changes
  // no faster than their points move. The distances ascend, so the pairs
  // that may touch are the first ones.
  const double reach = point_reach(displacement(certificate.anchor, start), radius) +
                       point_reach(move, radius) + kPairCullMargin;
  return std::span<const ContactFeatures>(certificate.pairs)
      .first(pairs_within(certificate, reach));
}

GodObjectSolver::GodObjectSolver(const RenderContext& context, const GodObjectSettings& settings)
    : settings_(settings),
      gains_(context.coupling),
      geometry_(context.tool, context.scene, settings) {}

void GodObjectSolver::reset(const Pose& start) {
  proxy_ = start;
  contacts_.clear();
  contacts_pose_.reset();
  warm_active_.clear();
}

void GodObjectSolver::refresh_contacts() {
  // The geometry is a function of the pose: at the pose it was evaluated at
  // (the update's end, then the next update's start when the proxy stayed),
  // evaluating it again would give the same values.
  if (contacts_pose_ && contacts_pose_->p == proxy_.p &&
      contacts_pose_->q.coeffs() == proxy_.q.coeffs())
    return;
  refreshed_features_.clear();
  for (const KeptContact& contact : contacts_) refreshed_features_.push_back(contact.features);
  geometry_.ccd().evaluate(refreshed_features_, geometry_.frames().com_frame(proxy_),
                           refreshed_geometry_);
  for (std::size_t k = 0; k < contacts_.size(); ++k) contacts_[k].geometry = refreshed_geometry_[k];
  std::erase_if(contacts_, [&](const KeptContact& contact) {
    return !usable(contact.features, contact.geometry, settings_.contact_distance_m);
  });
  contacts_pose_ = proxy_;
}

GodObjectUpdateStats GodObjectSolver::update(const Pose& target,
                                             const ProximityCertificate* certificate) {
  GodObjectUpdateStats stats;
  const ProxyFrames& frames = geometry_.frames();
  for (int iteration = 0; iteration < settings_.max_iterations; ++iteration) {
    // Refresh: the kept contacts at the proxy's pose; stop at the device.
    refresh_contacts();
    const Pose start = frames.com_frame(proxy_);
    const Vec6 unconstrained = displacement(start, frames.com_frame(target));
    if (reach(unconstrained) <= kNegligibleMotion) {
      stats.reached_device = true;
      break;
    }
    // Solve: Gauss' least constraint (with friction) on the kept contacts.
    build_constraints(start);
    const ConstrainedStep& solved = solver_.solve(
        coupling_metric(gains_, frames.centre_of_mass, proxy_.q, geometry_.ccd().tool_radius()),
        unconstrained, constraints_, constraint_friction_, warm_active_);
    stats.qp_iterations += solved.iterations;
    stats.coulomb_violations += solved.coulomb_residual > kCoulombResidualTolerance;
    if (!solved.feasible) {
      stats.solver_failed = true;
      break;
    }
    if (reach(solved.step) <= kNegligibleMotion) break;
    // Move: along the step's screw motion as far as the CCD lets the proxy.
    if (!move(start, solved.step, certificate, stats)) break;
  }
  refresh_contacts();
  return stats;
}

double GodObjectSolver::radius() const {
  return settings_.point_tool ? 0.0 : geometry_.ccd().tool_radius();
}

double GodObjectSolver::reach(const Vec6& motion) const { return point_reach(motion, radius()); }

void GodObjectSolver::build_constraints(const Pose& start) {
  constraints_.clear();
  constraint_friction_.clear();
  for (const KeptContact& contact : contacts_) {
    const FeatureGeometry& g = contact.geometry;
    constraints_.push_back(
        GaussConstraint{g.normal, g.point - start.p, -std::max(0.0, g.gap - settings_.standoff_m)});
    constraint_friction_.push_back(geometry_.friction()[contact.features.scene_object]);
  }
}

bool GodObjectSolver::move(const Pose& start, Vec6 constrained,
                           const ProximityCertificate* certificate, GodObjectUpdateStats& stats) {
  const MeshCcd& ccd = geometry_.ccd();
  const ProxyFrames& frames = geometry_.frames();
  // Within the certificate's reach only its pairs can meet: a move that
  // would leave it is cut at its boundary and is the update's last (the
  // path's point displacement from the anchor is convex along the screw
  // motion, a line for the centre and a geodesic for the rotation, so a
  // path whose ends are within reach stays within it). Only a start with
  // no room left (a crowded contact whose 64 pairs end close to the
  // standoff) falls back to the whole mesh CCD.
  double fraction = 1.0;
  if (certificate != nullptr)
    fraction = fraction_within_reach(certificate->anchor, start, constrained, radius(),
                                     certificate->clearance_m - settings_.standoff_m);
  const bool certified = certificate != nullptr && fraction > 0;
  const bool last_move = certified && fraction < 1;
  if (certified) constrained *= fraction;
  const ScrewMotion motion(start, displaced(start, constrained));
  stats.certified_moves += certified;
  const MeshCcdResult hit =
      certified ? ccd.first_contact_among(
                      motion, pairs_within_move(*certificate, start, constrained, radius()),
                      settings_.ccd)
                : ccd.first_contact(motion, settings_.ccd);
  ++stats.iterations;
  stats.bv_tests += hit.bv_tests;
  stats.primitive_queries += hit.primitive_queries;
  stats.budget_hits += hit.budget_exhausted;
  if (!hit.contact) {
    proxy_ = frames.tool_frame(pose_on(motion, 1.0));
    return !last_move;
  }
  ++stats.ccd_hits;
  proxy_ = frames.tool_frame(pose_on(motion, stop_before(motion, constrained, hit)));
  add_new_contacts(hit);
  return true;
}

double GodObjectSolver::stop_before(const ScrewMotion& motion, const Vec6& constrained,
                                    const MeshCcdResult& hit) const {
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
  return std::max(0.0, hit.toi - settings_.standoff_m / approach_speed);
}

void GodObjectSolver::add_new_contacts(const MeshCcdResult& hit) {
  const Pose stopped = geometry_.frames().com_frame(proxy_);
  for (const MeshCcdContact& contact : hit.contacts) {
    const bool known =
        std::any_of(contacts_.begin(), contacts_.end(),
                    [&](const KeptContact& kept) { return kept.features == contact.features; });
    if (known) continue;
    const FeatureGeometry geometry = geometry_.ccd().evaluate(contact.features, stopped);
    if (usable(contact.features, geometry, settings_.contact_distance_m))
      contacts_.push_back({contact.features, geometry});
  }
}

}  // namespace hb
