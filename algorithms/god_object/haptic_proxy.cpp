#include "algorithms/god_object/haptic_proxy.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "algorithms/god_object/coupling_metric.h"

namespace hb {

HapticProxy::HapticProxy(const MeshCcd& ccd, const CouplingGains& gains,
                         const GodObjectSettings& settings, const Vec3& centre_of_mass,
                         std::vector<double> friction)
    : certifier_(ccd, settings, centre_of_mass),
      gains_(gains),
      settings_(settings),
      friction_(std::move(friction)) {}

void HapticProxy::reset(const Pose& start, ProximityCertifier::QueryWorkspace& queries) {
  pose_ = start;
  queries.forget();
  certificate_ = certify(queries, start, settings_.haptic_band_m);
  com_pose_current_ = false;
  measured_.clear();
  warm_active_.clear();
  warm_impulses_.clear();
  contacts_.clear();
  last_step_reach_ = 0;
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
    carry_measured_pairs(previous.pairs);  // the pose stays
    return true;
  }
  if (coupling_energy(slow_proxy, target) < coupling_energy(pose_, target)) {
    pose_ = slow_proxy;  // the anchor's own tool pose: within reach
    com_pose_current_ = false;
    measured_.clear();
    warm_active_.clear();
    warm_impulses_.clear();
    return true;
  }
  certificate_ = std::move(previous);
  return false;
}

void HapticProxy::carry_measured_pairs(const std::vector<ContactFeatures>& previous) {
  const std::vector<ContactFeatures>& pairs = certificate_.pairs;
  std::vector<char>& measured = carried_measured_;
  measured.assign(pairs.size(), 0);
  carried_contacts_.resize(pairs.size());
  if (measured_.size() == previous.size()) {
    previous_index_.build(previous);
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const int old = previous_index_.find(pairs[k]);
      if (old < 0 || !measured_[static_cast<std::size_t>(old)]) continue;
      carried_contacts_[k] = end_contacts_[static_cast<std::size_t>(old)];
      measured[k] = 1;
    }
  }
  measured_.swap(measured);
  end_contacts_.swap(carried_contacts_);
}

double HapticProxy::least_listed_distance() const {
  const Pose com_pose = certifier_.frames().com_frame(pose_);
  double least = std::numeric_limits<double>::infinity();
  for (const ContactFeatures& pair : certificate_.pairs)
    least = std::min(least, certifier_.evaluate(pair, com_pose).distance);
  return least;
}

double HapticProxy::worst_margin(const Pose& com_pose) {
  certifier_.evaluate_listed(evaluation_, certificate_, constraints_.size(), com_pose, evaluated_);
  double worst = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < constraints_.size(); ++k) {
    const PairContact& contact = evaluated_[k];
    end_contacts_[k] = contact;
    // The side each pair started the tick on: a pair whose direction
    // between closest points turned over has crossed.
    const double side = contact.normal.dot(constraints_[k].normal) >= 0 ? 1.0 : -1.0;
    end_distances_[k] = side * contact.distance;
    worst = std::min(worst, end_distances_[k] - floors_[k]);
  }
  return worst;
}

HapticSolveStats HapticProxy::step(const Pose& target) {
  HapticSolveStats stats;
  const ProxyFrames& frames = certifier_.frames();
  const double radius = certifier_.radius();
  const Pose start = com_pose_current_ ? com_pose_ : frames.com_frame(pose_);
  const Vec6 unconstrained = displacement(start, frames.com_frame(target));
  const std::size_t listed = certificate_.pairs.size();
  bool carried = com_pose_current_ && measured_.size() == listed;
  end_contacts_.resize(listed);

  // The pairs that can matter this tick: a pair d apart at the anchor is at
  // least d − (reach from the anchor to the start) − (reach of the step)
  // apart at the end, and its linearised constraint holds for any step of
  // less reach than d − standoff; the certificate lists the pairs by
  // ascending distance. The step's reach is allowed twice the last tick's
  // (kNearFloorM at least); a solve whose step reaches farther is done
  // again with every listed pair.
  const double from_anchor = point_reach(displacement(certificate_.anchor, start), radius);
  const double matters = std::max(settings_.standoff_m, settings_.contact_distance_m);
  const double allowance = std::max(2 * last_step_reach_, kNearFloorM);
  std::size_t near =
      settings_.haptic_all_pairs
          ? listed
          : pairs_within(certificate_, matters + from_anchor + allowance + kPairCullMargin);
  Vec6 moved = Vec6::Zero();
  // An attempt that has to be done again starts from the warm start the
  // tick began with, as a solve of every pair would have.
  if (near < listed) {
    tick_warm_impulses_ = warm_impulses_;
    tick_warm_active_ = warm_active_;
  }
  for (;;) {
    if (solve_near(near, start, unconstrained, allowance, moved, stats, carried) || near == listed)
      break;
    near = listed;    // the step reached farther than the pairs left out allow
    carried = false;  // the near pairs' measurements are the attempt's now
    warm_impulses_.swap(tick_warm_impulses_);
    warm_active_.swap(tick_warm_active_);
    ++stats.widened;
  }
  stats.pairs_solved = static_cast<int64_t>(near);
  // The last check measured the near pairs at this pose; the next tick starts here.
  com_pose_ = displaced(start, moved);
  com_pose_current_ = true;
  measured_.assign(listed, 0);
  std::fill(measured_.begin(), measured_.begin() + static_cast<std::ptrdiff_t>(near), 1);
  if (moved.squaredNorm() > 0) pose_ = frames.tool_frame(com_pose_);

  // Contacts at the new pose: the pairs within the contact distance, as
  // measured there by the last check (the others are beyond it).
  contacts_.clear();
  for (std::size_t k = 0; k < near; ++k) {
    const PairContact& contact = end_contacts_[k];
    if (contact.distance > settings_.contact_distance_m) continue;
    contacts_.push_back(Contact{contact.scene_point, contact.normal, -contact.distance});
  }
  return stats;
}

bool HapticProxy::solve_near(std::size_t near, const Pose& start, const Vec6& unconstrained,
                             double allowance, Vec6& moved, HapticSolveStats& stats, bool carried) {
  const double radius = certifier_.radius();
  const bool all = near == certificate_.pairs.size();
  // Constraints: one per near pair at the start, asking for the standoff.
  build_near_constraints(near, start, carried, stats);
  // Solve, move, and check every near pair's exact distance at the end
  // pose; a pair that fell short of its floor (the linearised constraint
  // missed a rotation's second-order motion, or an edge pair's sliding
  // closest points) is asked for its shortfall more in a new solve. What
  // still falls short after kCorrections solves is cut to the largest
  // fraction of the step that keeps every pair above its floor.
  double reached = 0;  // the largest reach of a solve's step
  for (int pass = 0;; ++pass) {
    // Solve: the constrained step, warm-started from the last solve.
    const Vec6 step = solve_step(near, start, unconstrained, stats);
    reached = std::max(reached, point_reach(step, radius));
    if (!all && reached > allowance) return false;
    // Stay within the certificate's reach: the largest fraction of the step
    // that does (the reach bound is continuous in the fraction, and the
    // start lies within it).
    const double fraction = fraction_within_reach(certificate_.anchor, start, step, radius,
                                                  certifier_.reach(certificate_));
    stats.bounded = fraction < 1;
    moved = fraction * step;
    // Check: every solved pair's exact distance at the end pose.
    stats.pairs_evaluated += static_cast<int64_t>(constraints_.size());
    if (worst_margin(displaced(start, moved)) >= 0) break;
    // Cut: after kCorrections solves, the step keeps every pair above its floor.
    if (pass == kCorrections) {
      cut_step(start, moved, stats);
      break;
    }
    // Correct: the pairs that fell short ask for their shortfall more.
    ask_for_shortfalls();
    ++stats.corrections;
  }
  std::fill(warm_impulses_.begin() + static_cast<std::ptrdiff_t>(near), warm_impulses_.end(),
            Vec3::Zero());
  last_step_reach_ = reached;
  return true;
}

[[gnu::always_inline]] inline void HapticProxy::build_near_constraints(std::size_t near,
                                                                       const Pose& start,
                                                                       bool carried,
                                                                       HapticSolveStats& stats) {
  // One constraint per near pair at the current pose, asking for the
  // standoff (a pair found closer is pushed back out: the gap a rotation's
  // second-order motion took is recovered). The last tick's final check
  // measured them there already, unless a certificate came since.
  constraints_.clear();
  constraint_friction_.clear();
  floors_.clear();
  for (std::size_t k = 0; k < near; ++k) {
    const ContactFeatures& pair = certificate_.pairs[k];
    const bool measured = carried && measured_[k];
    const PairContact contact = measured ? end_contacts_[k] : certifier_.evaluate(pair, start);
    stats.pairs_evaluated += measured ? 0 : 1;
    constraints_.push_back(GaussConstraint{contact.normal, contact.tool_point - start.p,
                                           settings_.standoff_m - contact.distance});
    constraint_friction_.push_back(
        pair.scene_object < static_cast<int>(friction_.size()) ? friction_[pair.scene_object] : 0);
    floors_.push_back(std::min(settings_.standoff_m - kStandoffSlackM, contact.distance));
  }
  end_distances_.assign(constraints_.size(), 0);
}

[[gnu::always_inline]] inline Vec6 HapticProxy::solve_step(std::size_t near, const Pose& start,
                                                           const Vec6& unconstrained,
                                                           HapticSolveStats& stats) {
  // The warm start: the last solve's impulses per listed pair, the pairs
  // left out at zero (none after a jump).
  const std::size_t listed = certificate_.pairs.size();
  const bool warm = warm_impulses_.size() == listed;
  const ConstrainedStep& solved = solver_.solve(
      coupling_metric(gains_, certifier_.frames().centre_of_mass, start.q, certifier_.radius()),
      unconstrained, constraints_, constraint_friction_, warm_active_,
      warm ? std::span<const Vec3>(warm_impulses_).first(near) : std::span<const Vec3>());
  // The same pairs, in the same order, until the next certificate.
  warm_impulses_.resize(listed, Vec3::Zero());
  std::copy(solved.impulses.begin(), solved.impulses.end(), warm_impulses_.begin());
  stats.qp_iterations += solved.iterations;
  stats.coulomb_violations += solved.coulomb_residual > kCoulombResidualTolerance;
  // A step the friction sweeps did not finish is still feasible: taken
  // (the proxy only stays when the last QP failed, which it does not for
  // a consistent set of constraints).
  return solved.feasible ? solved.step : Vec6::Zero();
}

[[gnu::always_inline]] inline void HapticProxy::cut_step(const Pose& start, Vec6& moved,
                                                         HapticSolveStats& stats) {
  // The start keeps every pair above its floor: bisect the fraction.
  double safe = 0, unsafe = 1;
  for (int i = 0; i < kCutBisections; ++i) {
    const double middle = 0.5 * (safe + unsafe);
    stats.pairs_evaluated += static_cast<int64_t>(constraints_.size());
    (worst_margin(displaced(start, middle * moved)) >= 0 ? safe : unsafe) = middle;
  }
  moved *= safe;
  worst_margin(displaced(start, moved));  // the pairs at the pose kept
  stats.cut = true;
}

void HapticProxy::ask_for_shortfalls() {
  for (std::size_t k = 0; k < constraints_.size(); ++k)
    if (end_distances_[k] < floors_[k])
      constraints_[k].rhs += settings_.standoff_m - end_distances_[k];
}

}  // namespace hb
