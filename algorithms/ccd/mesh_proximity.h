// The search behind MeshCcd::proximity and MeshCcd::closest_points (see
// mesh_ccd.h): tool tree × scene trees at one pose, nearest pairs first.
#pragma once

#include <cstddef>
#include <span>

#include "algorithms/ccd/mesh_ccd.h"
#include "algorithms/ccd/mesh_features.h"

namespace hb::ccd_detail {

/// The feature pairs of the tool (its frame at `tool_pose`) and the scene
/// closer than max_distance, at most max_pairs of them (MeshCcd::proximity).
ProximityResult search_proximity(const MeshFeatures& tool, std::span<const MeshFeatures> scene,
                                 const Pose& tool_pose, double max_distance, std::size_t max_pairs);

/// Closest points of one feature pair (indices already checked), the tool's
/// pose given as the rotation of its normalised quaternion and its
/// translation (worked out once for many pairs at one pose).
PairClosestPoints pair_closest_points(const MeshFeatures& tool, const MeshFeatures& scene,
                                      const ContactFeatures& features, const Mat3& rotation,
                                      const Vec3& translation);

}  // namespace hb::ccd_detail
