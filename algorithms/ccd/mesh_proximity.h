// The search behind MeshCcd::proximity and MeshCcd::closest_points (see
// mesh_ccd.h): tool tree × scene trees at one pose, nearest pairs first.
#pragma once

#include <array>
#include <cstddef>
#include <span>

#include "algorithms/ccd/mesh_ccd.h"
#include "algorithms/ccd/mesh_features.h"
#include "hapticbench/closest_points.h"

namespace hb::ccd_detail {

/// MeshCcd::start_proximity's search (ProximityInSlices).
ProximityInSlices::Search start_proximity_search(const MeshFeatures& tool,
                                                 std::span<const MeshFeatures> scene,
                                                 const Pose& tool_pose, double max_distance,
                                                 std::size_t max_pairs);

/// The feature pairs of the tool (its frame at `tool_pose`) and the scene
/// closer than max_distance, at most max_pairs of them (MeshCcd::proximity).
ProximityResult search_proximity(const MeshFeatures& tool, std::span<const MeshFeatures> scene,
                                 const Pose& tool_pose, double max_distance, std::size_t max_pairs);

/// Tool vertex v in the world (m), the tool's pose given as the rotation of
/// its normalised quaternion and its translation.
inline Vec3 placed_vertex(const MeshFeatures& tool, const Mat3& rotation, const Vec3& translation,
                          int v) {
  return translation + rotation * tool.vertex(v);
}

/// The tool's vertices in the world at one pose, each worked out once while
/// it keeps its slot: the pairs listed near a contact share a few vertices
/// (a box resting on tiles: its bottom face's, in every pair). The values
/// are placed_vertex's, bit for bit.
class PlacedToolVertices {
 public:
  /// Below this many pairs, placing each vertex where it is used costs less
  /// than clearing the slots.
  static constexpr std::size_t kFewPairs = 8;

  PlacedToolVertices(const MeshFeatures& tool, const Mat3& rotation, const Vec3& translation);
  Vec3 operator()(int v) {
    const std::size_t slot = static_cast<std::size_t>(v) & (kSlots - 1);
    if (vertex_[slot] != v) {
      vertex_[slot] = v;
      world_[slot] = placed_vertex(tool_, rotation_, translation_, v);
    }
    return world_[slot];
  }

 private:
  static constexpr std::size_t kSlots = 64;  // a power of two
  const MeshFeatures& tool_;
  const Mat3& rotation_;
  const Vec3& translation_;
  std::array<int, kSlots> vertex_;  // the vertex in each slot, −1 for none
  std::array<Vec3, kSlots> world_;
};

/// Closest points of one feature pair (indices already checked), the tool's
/// vertex v placed in the world by place(v).
template <class Place>
PairClosestPoints pair_closest_points_placed(const MeshFeatures& tool, const MeshFeatures& scene,
                                             const ContactFeatures& features, Place&& place) {
  PairClosestPoints out;
  switch (features.kind) {
    case ContactFeatureKind::kToolVertexSceneFace: {
      const auto& tri = scene.triangle(features.scene_feature);
      out.tool_point = place(features.tool_feature);
      out.scene_point = closest_point_on_triangle(out.tool_point, scene.vertex(tri[0]),
                                                  scene.vertex(tri[1]), scene.vertex(tri[2]));
      break;
    }
    case ContactFeatureKind::kSceneVertexToolFace: {
      const auto& tri = tool.triangle(features.tool_feature);
      out.scene_point = scene.vertex(features.scene_feature);
      out.tool_point =
          closest_point_on_triangle(out.scene_point, place(tri[0]), place(tri[1]), place(tri[2]));
      break;
    }
    case ContactFeatureKind::kEdgeEdge: {
      const auto& te = tool.edge(features.tool_feature);
      const auto& se = scene.edge(features.scene_feature);
      const SegmentClosestPoints points = closest_points_of_segments(
          place(te[0]), place(te[1]), scene.vertex(se[0]), scene.vertex(se[1]));
      out.tool_point = points.on_p;
      out.scene_point = points.on_q;
      break;
    }
  }
  out.distance = (out.tool_point - out.scene_point).norm();
  return out;
}

/// The same, the tool's pose given as the rotation of its normalised
/// quaternion and its translation.
PairClosestPoints pair_closest_points(const MeshFeatures& tool, const MeshFeatures& scene,
                                      const ContactFeatures& features, const Mat3& rotation,
                                      const Vec3& translation);

}  // namespace hb::ccd_detail
