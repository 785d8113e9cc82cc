#include "harness/reference/trace_clearance.h"

#include <algorithm>

#include "harness/reference/oracle.h"

namespace hb {

TraceClearance trace_clearance(const std::vector<SceneObject>& scene, const TriangleMesh& tool,
                               std::span<const Pose> poses, std::size_t max_vertices) {
  TraceClearance clearance;
  if (poses.empty() || tool.vertices.empty()) return clearance;
  const std::unique_ptr<Oracle> oracle = make_embree_oracle(scene);
  // Every stride-th vertex, so that a large mesh costs max_vertices queries.
  const std::size_t stride = (tool.vertices.size() + max_vertices - 1) / max_vertices;
  std::vector<Vec3> local;
  for (std::size_t i = 0; i < tool.vertices.size(); i += stride) local.push_back(tool.vertices[i]);
  clearance.vertices = local.size();
  clearance.poses = poses.size();

  std::vector<Vec3> world(local.size());
  PointQueryRequest request;
  request.want_inside = true;
  request.want_closest = true;
  PointQueryResult result;
  for (std::size_t p = 0; p < poses.size(); ++p) {
    for (std::size_t i = 0; i < local.size(); ++i) world[i] = poses[p].transform_point(local[i]);
    request.points = world;
    oracle->query_points(request, result);
    double gap = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < world.size(); ++i)
      gap = std::min(gap, result.inside[i] ? -result.distance[i] : result.distance[i]);
    const ClearanceSample sample{p, gap};
    if (p == 0) clearance.first = clearance.closest = sample;
    if (gap < clearance.closest.gap_m) clearance.closest = sample;
    clearance.last = sample;
  }
  return clearance;
}

}  // namespace hb
