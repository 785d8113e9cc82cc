#include "algorithms/god_object/haptic_proxy.h"

#include <algorithm>
#include <cmath>

namespace hb {

namespace {
// Below this distance (m) a pair's closest points give no direction; the
// pair's own normal is used instead.
constexpr double kDirectionFloor = 1e-12;
}  // namespace

HapticProxy::HapticProxy(const MeshCcd& ccd, const CouplingGains& gains,
                         const GodObjectSettings& settings, const Vec3& centre_of_mass)
    : ccd_(ccd),
      gains_(gains),
      settings_(settings),
      frames_{centre_of_mass},
      radius_(settings.point_tool ? 0.0 : ccd.tool_radius()) {}

ProximityCertificate HapticProxy::certify(const Pose& tool_pose, double band_m) const {
  ProximityCertificate certificate;
  certificate.anchor = frames_.com_frame(tool_pose);
  const ProximityResult found = ccd_.proximity(
      certificate.anchor, band_m, static_cast<std::size_t>(settings_.haptic_max_pairs));
  certificate.clearance_m = found.clearance_m;
  certificate.pairs.reserve(found.pairs.size());
  for (const ProximityPair& pair : found.pairs) certificate.pairs.push_back(pair.features);
  return certificate;
}

double HapticProxy::band_for(const Pose& previous_target, const Pose& target) const {
  constexpr double kMargin = 6.0;  // two intervals until the next certificate, times three
  const double moved = point_reach(
      displacement(frames_.com_frame(previous_target), frames_.com_frame(target)), radius_);
  return std::clamp(kMargin * moved, settings_.haptic_band_min_m, settings_.haptic_band_m);
}

void HapticProxy::reset(const Pose& start) {
  pose_ = start;
  certificate_ = certify(start, settings_.haptic_band_m);
  warm_active_.clear();
  contacts_.clear();
}

bool HapticProxy::within_reach(const ProximityCertificate& certificate,
                               const Pose& tool_pose) const {
  return point_reach(displacement(certificate.anchor, frames_.com_frame(tool_pose)), radius_) <=
         certificate.clearance_m - settings_.standoff_m;
}

double HapticProxy::coupling_energy(const Pose& tool_pose, const Pose& target) const {
  const Vec3 dx = target.p - tool_pose.p;
  const Vec3 dphi = rotation_vector(target.q * tool_pose.q.conjugate());
  return 0.5 * (gains_.k_t * dx.squaredNorm() + gains_.k_r * dphi.squaredNorm());
}

bool HapticProxy::offer(ProximityCertificate certificate, const Pose& slow_proxy,
                        const Pose& target) {
  ProximityCertificate previous = std::move(certificate_);
  certificate_ = std::move(certificate);
  if (within_reach(certificate_, pose_)) {
    warm_active_.clear();
    return true;
  }
  if (coupling_energy(slow_proxy, target) < coupling_energy(pose_, target)) {
    pose_ = slow_proxy;  // the anchor's own tool pose: within reach
    warm_active_.clear();
    return true;
  }
  certificate_ = std::move(previous);
  return false;
}

HapticSolveStats HapticProxy::step(const Pose& target) {
  HapticSolveStats stats;
  const Pose start = frames_.com_frame(pose_);
  const Vec6 unconstrained = displacement(start, frames_.com_frame(target));

  // The listed pairs at the current pose: one constraint each.
  constraints_.clear();
  contacts_.clear();
  distances_.clear();
  for (const ContactFeatures& pair : certificate_.pairs) {
    const PairClosestPoints points = ccd_.closest_points(pair, start);
    ++stats.pairs_evaluated;
    Vec3 normal = points.tool_point - points.scene_point;
    if (points.distance > kDirectionFloor)
      normal /= points.distance;
    else
      normal = ccd_.evaluate(pair, start).normal;
    constraints_.push_back(GaussConstraint{normal, points.tool_point - start.p,
                                           -std::max(0.0, points.distance - settings_.standoff_m)});
    distances_.push_back(points.distance);
  }

  Vec6 step = unconstrained;
  if (!constraints_.empty()) {
    std::erase_if(warm_active_, [&](int k) { return k >= static_cast<int>(constraints_.size()); });
    const GaussSolution& solution =
        gauss_.solve(coupling_metric(gains_, frames_.centre_of_mass, start.q, radius_),
                     unconstrained, constraints_, warm_active_);
    stats.qp_iterations = solution.iterations;
    if (!solution.converged) {
      warm_active_.clear();
      step.setZero();  // the proxy stays where it is free
    } else {
      warm_active_ = solution.active;
      step = solution.acceleration;
    }
  }

  // Stay within the certificate's reach: the largest fraction of the step
  // that does (the reach bound is continuous in the fraction, and the
  // start lies within it).
  const double fraction = fraction_within_reach(certificate_.anchor, start, step, radius_,
                                                certificate_.clearance_m - settings_.standoff_m);
  stats.bounded = fraction < 1;
  const Vec6 moved = fraction * step;
  if (fraction > 0) pose_ = frames_.tool_frame(displaced(start, moved));

  // Contacts at the new pose: the pairs that may now be within the contact
  // distance (no pair came closer than the motion's reach).
  const double moved_reach = point_reach(moved, radius_);
  const Pose end = frames_.com_frame(pose_);
  for (std::size_t k = 0; k < certificate_.pairs.size(); ++k) {
    if (distances_[k] > settings_.contact_distance_m + moved_reach) continue;
    const PairClosestPoints points = ccd_.closest_points(certificate_.pairs[k], end);
    if (points.distance > settings_.contact_distance_m) continue;
    const Vec3 normal = points.distance > kDirectionFloor
                            ? Vec3((points.tool_point - points.scene_point) / points.distance)
                            : ccd_.evaluate(certificate_.pairs[k], end).normal;
    contacts_.push_back(Contact{points.scene_point, normal, -points.distance});
  }
  return stats;
}

}  // namespace hb
