#include "algorithms/god_object/haptic_proxy.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace hb {

HapticProxy::HapticProxy(const MeshCcd& ccd, const CouplingGains& gains,
                         const GodObjectSettings& settings, const Vec3& centre_of_mass,
                         std::vector<double> friction)
    : certifier_(ccd, settings, centre_of_mass),
      gains_(gains),
      settings_(settings),
      friction_(std::move(friction)) {}

void HapticProxy::reset(const Pose& start) {
  pose_ = start;
  certificate_ = certify(start, settings_.haptic_band_m);
  warm_active_.clear();
  warm_impulses_.clear();
  contacts_.clear();
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
    carry_impulses(previous.pairs, warm_impulses_, certificate_.pairs, carried_);
    warm_impulses_.swap(carried_);
    return true;
  }
  if (coupling_energy(slow_proxy, target) < coupling_energy(pose_, target)) {
    pose_ = slow_proxy;  // the anchor's own tool pose: within reach
    warm_active_.clear();
    warm_impulses_.clear();
    return true;
  }
  certificate_ = std::move(previous);
  return false;
}

HapticSolveStats HapticProxy::step(const Pose& target) {
  HapticSolveStats stats;
  const ProxyFrames& frames = certifier_.frames();
  const double radius = certifier_.radius();
  const Pose start = frames.com_frame(pose_);
  const Vec6 unconstrained = displacement(start, frames.com_frame(target));

  // The listed pairs at the current pose: one constraint each.
  constraints_.clear();
  constraint_friction_.clear();
  contacts_.clear();
  distances_.clear();
  for (const ContactFeatures& pair : certificate_.pairs) {
    const PairContact contact = certifier_.evaluate(pair, start);
    ++stats.pairs_evaluated;
    constraints_.push_back(
        GaussConstraint{contact.normal, contact.tool_point - start.p,
                        -std::max(0.0, contact.distance - settings_.standoff_m)});
    constraint_friction_.push_back(
        pair.scene_object < static_cast<int>(friction_.size()) ? friction_[pair.scene_object] : 0);
    distances_.push_back(contact.distance);
  }

  const ConstrainedStep& solved = solver_.solve(
      coupling_metric(gains_, frames.centre_of_mass, start.q, radius), unconstrained, constraints_,
      constraint_friction_, warm_active_,
      warm_impulses_.size() == constraints_.size() ? std::span<const Vec3>(warm_impulses_)
                                                   : std::span<const Vec3>());
  // The same pairs, in the same order, until the next certificate.
  warm_impulses_ = solved.impulses;
  stats.qp_iterations = solved.iterations;
  const Vec6 step = solved.converged ? solved.step : Vec6::Zero();  // else the proxy stays

  // Stay within the certificate's reach: the largest fraction of the step
  // that does (the reach bound is continuous in the fraction, and the
  // start lies within it).
  const double fraction = fraction_within_reach(certificate_.anchor, start, step, radius,
                                                certifier_.reach(certificate_));
  stats.bounded = fraction < 1;
  const Vec6 moved = fraction * step;
  if (fraction > 0) pose_ = frames.tool_frame(displaced(start, moved));

  // Contacts at the new pose: the pairs that may now be within the contact
  // distance (no pair came closer than the motion's reach).
  const double moved_reach = point_reach(moved, radius);
  const Pose end = frames.com_frame(pose_);
  for (std::size_t k = 0; k < certificate_.pairs.size(); ++k) {
    if (distances_[k] > settings_.contact_distance_m + moved_reach) continue;
    const PairContact contact = certifier_.evaluate(certificate_.pairs[k], end);
    if (contact.distance > settings_.contact_distance_m) continue;
    contacts_.push_back(Contact{contact.scene_point, contact.normal, -contact.distance});
  }
  return stats;
}

}  // namespace hb
