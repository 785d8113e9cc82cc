#include "algorithms/contact/proximity_certifier.h"

#include <algorithm>
#include <numeric>
#include <tuple>

namespace hb {

namespace {
// Below this distance (m) a pair's closest points give no direction; the
// pair's own normal is used instead.
constexpr double kDirectionFloor = 1e-12;
}  // namespace

void match_pairs(std::span<const ContactFeatures> from, std::span<const ContactFeatures> to,
                 std::vector<int>& index_in_from) {
  auto key = [](const ContactFeatures& f) {
    return std::tuple(f.kind, f.scene_object, f.tool_feature, f.scene_feature);
  };
  std::vector<int> sorted(from.size());
  std::iota(sorted.begin(), sorted.end(), 0);
  std::sort(sorted.begin(), sorted.end(),
            [&](int a, int b) { return key(from[a]) < key(from[b]); });
  index_in_from.assign(to.size(), -1);
  for (std::size_t k = 0; k < to.size(); ++k) {
    const auto at = std::lower_bound(sorted.begin(), sorted.end(), to[k],
                                     [&](int i, const auto& f) { return key(from[i]) < key(f); });
    if (at != sorted.end() && from[*at] == to[k]) index_in_from[k] = *at;
  }
}

void carry_impulses(std::span<const int> index_in_from, std::span<const Vec3> impulses,
                    std::vector<Vec3>& carried) {
  carried.assign(index_in_from.size(), Vec3::Zero());
  for (std::size_t k = 0; k < index_in_from.size(); ++k) {
    const int old = index_in_from[k];
    if (old >= 0 && static_cast<std::size_t>(old) < impulses.size()) carried[k] = impulses[old];
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
  const ProximityResult found = ccd_.proximity(
      certificate.anchor, band_m, static_cast<std::size_t>(settings_.haptic_max_pairs));
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
