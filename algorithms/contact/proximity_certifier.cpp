#include "algorithms/contact/proximity_certifier.h"

#include <algorithm>

namespace hb {

namespace {
// Below this distance (m) a pair's closest points give no direction; the
// pair's own normal is used instead.
constexpr double kDirectionFloor = 1e-12;
}  // namespace

void carry_impulses(std::span<const ContactFeatures> from, std::span<const Vec3> impulses,
                    std::span<const ContactFeatures> to, std::vector<Vec3>& carried) {
  carried.assign(to.size(), Vec3::Zero());
  for (std::size_t old = 0; old < impulses.size() && old < from.size(); ++old) {
    if (impulses[old].isZero()) continue;
    const auto found = std::find(to.begin(), to.end(), from[old]);
    if (found != to.end()) carried[found - to.begin()] = impulses[old];
  }
}

ProximityCertifier::ProximityCertifier(const MeshCcd& ccd, const ContactSettings& settings,
                                       const Vec3& centre_of_mass)
    : ccd_(ccd),
      settings_(settings),
      frames_{centre_of_mass},
      radius_(settings.point_tool ? 0.0 : ccd.tool_radius()) {}

ProximityCertificate ProximityCertifier::certify(const Pose& tool_pose, double band_m) const {
  ProximityCertificate certificate;
  certificate.anchor = frames_.com_frame(tool_pose);
  const auto most = static_cast<std::size_t>(settings_.haptic_max_pairs);
  const std::size_t first = std::min(kFirstListedPairs, most);
  constexpr double kReachPerBand = 1.0 / 3;
  const double reach_wanted = kReachPerBand * band_m;
  // A list cut short at `clearance` (< band_m) that leaves too little reach:
  // pairs crowd the standoff.
  const auto too_little_reach = [&](double clearance) {
    return clearance < band_m && clearance - settings_.standoff_m < reach_wanted;
  };
  ProximityResult found = ccd_.proximity(certificate.anchor, band_m, crowded_ ? most : first);
  if (!crowded_ && first < most && too_little_reach(found.clearance_m))
    found = ccd_.proximity(certificate.anchor, band_m, most);
  // Whether the first pairs alone would have left too little reach here
  // (their clearance: the distance of the next pair): then the next query,
  // a slow-loop interval away, lists the most at once.
  crowded_ = found.pairs.size() > first && too_little_reach(found.pairs[first].distance);
  certificate.clearance_m = found.clearance_m;
  certificate.pairs.reserve(found.pairs.size());
  certificate.distances.reserve(found.pairs.size());
  for (const ProximityPair& pair : found.pairs) {
    certificate.pairs.push_back(pair.features);
    certificate.distances.push_back(pair.distance);
  }
  return certificate;
}

double ProximityCertifier::band_for(const Pose& previous_target, const Pose& target) const {
  constexpr double kMargin = 6.0;  // two intervals until the next certificate, times three
  const double moved = point_reach(
      displacement(frames_.com_frame(previous_target), frames_.com_frame(target)), radius_);
  return std::clamp(kMargin * moved, settings_.haptic_band_min_m, settings_.haptic_band_m);
}

bool ProximityCertifier::within_reach(const ProximityCertificate& certificate,
                                      const Pose& tool_pose) const {
  return point_reach(displacement(certificate.anchor, frames_.com_frame(tool_pose)), radius_) <=
         reach(certificate);
}

PairContact ProximityCertifier::evaluate(const ContactFeatures& pair, const Pose& com_pose) const {
  const PairClosestPoints points = ccd_.closest_points(pair, com_pose);
  PairContact contact;
  contact.scene_point = points.scene_point;
  contact.tool_point = points.tool_point;
  contact.distance = points.distance;
  contact.normal = points.distance > kDirectionFloor
                       ? Vec3((points.tool_point - points.scene_point) / points.distance)
                       : ccd_.evaluate(pair, com_pose).normal;
  return contact;
}

}  // namespace hb
