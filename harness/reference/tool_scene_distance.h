// The distance between the posed tool's surface and the scene's triangles,
// and whether they cross, for scenes without inside/outside (distance-only
// objects). Tool surface samples alone cannot tell: a tool passing through
// an open sheet has samples on both sides, none on it, and reads as close
// but apart. Here every tool triangle that can come within the current
// bound of the scene is paired with the scene triangles near it: whether
// they intersect is decided exactly (triangles_intersect(), exact
// predicates), their distance in double (triangle_pair_distance.h). The
// search starts from the samples' distances, which the oracle computes
// anyway: each sample stands for the tool triangles nearest it (its cluster,
// fixed in the tool frame), and a cluster is opened only when its sample's
// distance minus the cluster's radius is within the best distance found so
// far, so only the tool's part nearest the scene is paired.
// docs/ground-truth.md says what the numbers mean.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "hapticbench/pose.h"
#include "hapticbench/triangle_mesh.h"
#include "harness/reference/oracle.h"
#include "harness/reference/triangle_pair_distance.h"

namespace hb {

/// The posed tool against the scene at one pose.
struct ToolSceneDistance {
  /// Some tool triangle and some scene triangle share a point (exact
  /// predicates on the posed double coordinates): the tool crosses, or
  /// exactly touches, the scene's surface.
  bool crossing = false;
  /// m: the least distance between the tool's and the scene's triangles
  /// (0 when crossing; infinite for a scene without triangles).
  double distance_m = 0;
  /// m, world frame: the closest points of tool and scene (apart only).
  Vec3 on_tool = Vec3::Zero();
  Vec3 on_scene = Vec3::Zero();
  /// m, world frame: the first crossing pair found (crossing only).
  TriangleCorners crossing_tool_triangle = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  TriangleCorners crossing_scene_triangle = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  int64_t triangle_pairs = 0;  ///< tool–scene triangle pairs tested
};

/// Slack (m) on every bound of the search, over the rounding of distances
/// computed in double: a pair is examined when its lower bound is within
/// the best distance plus this.
inline constexpr double kToolSceneBoundSlackM = 1e-9;

class ToolSceneDistanceSearch {
 public:
  /// `tool`: the tool's mesh, tool frame (m); `samples`: the points (tool
  /// frame, m) whose distances evaluate() is given, each tool triangle
  /// assigned to the sample nearest its centroid; `spacing_m`: their
  /// spacing (surface_samples.h), > 0. Throws std::invalid_argument on an
  /// empty sample list or a non-positive spacing.
  ToolSceneDistanceSearch(const TriangleMesh& tool, std::span<const Vec3> samples,
                          double spacing_m);

  /// The tool at `tool_pose` (tool frame to world) against the oracle's
  /// scene. `sample_closest` is the oracle's closest-point answer for the
  /// samples so posed, in their order (distance and closest point of each).
  /// Null when the oracle does not list triangles near a point
  /// (Oracle::triangles_within). Throws std::invalid_argument when the
  /// answer's size is not the number of samples.
  std::optional<ToolSceneDistance> evaluate(const Oracle& oracle, const Pose& tool_pose,
                                            const PointQueryResult& sample_closest);

 private:
  // Tool triangles in the tool frame and, per sample, the triangles it
  // stands for (compressed rows: cluster_start_[s] .. cluster_start_[s + 1]
  // index cluster_triangles_).
  std::vector<TriangleCorners> triangles_;
  std::vector<Vec3> samples_;
  std::vector<std::size_t> cluster_start_;
  std::vector<uint32_t> cluster_triangles_;
  std::vector<Vec3> centroids_;  ///< m, tool frame, per triangle
  std::vector<double> radii_;    ///< m, per triangle: farthest corner from its centroid
  /// m, per cluster row: farthest corner of the row's triangle from its sample
  std::vector<double> reach_;
  std::vector<double> cluster_radius_;  ///< m, per sample: the largest reach_ of its cluster
  // Scratch of evaluate().
  std::vector<std::pair<double, uint32_t>> open_clusters_;  ///< (lower bound, sample)
  std::vector<NearTriangle> near_;
};

}  // namespace hb
