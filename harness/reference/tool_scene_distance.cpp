#include "harness/reference/tool_scene_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>

#include "hapticbench/closest_points.h"

namespace hb {

namespace {

// Integer cell of a point on a grid of side `cell`.
Eigen::Vector3i cell_of(const Vec3& p, double cell) {
  return (p / cell).array().floor().cast<int>().matrix();
}

uint64_t cell_key(const Eigen::Vector3i& c) {
  auto axis = [](int x) { return static_cast<uint64_t>(static_cast<uint32_t>(x) & 0x1fffff); };
  return axis(c.x()) | (axis(c.y()) << 21) | (axis(c.z()) << 42);
}

// The sample nearest each point: a grid of the samples at their spacing,
// searched in the point's cell and its 26 neighbours, else all samples.
class NearestSample {
 public:
  NearestSample(std::span<const Vec3> samples, double cell) : samples_(samples), cell_(cell) {
    for (std::size_t i = 0; i < samples.size(); ++i)
      grid_[cell_key(cell_of(samples[i], cell))].push_back(static_cast<uint32_t>(i));
  }

  uint32_t operator()(const Vec3& p) const {
    const Eigen::Vector3i centre = cell_of(p, cell_);
    double best_sq = std::numeric_limits<double>::infinity();
    uint32_t best = 0;
    const auto offer = [&](uint32_t i) {
      const double d_sq = (samples_[i] - p).squaredNorm();
      if (d_sq < best_sq) best_sq = d_sq, best = i;
    };
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = grid_.find(cell_key(centre + Eigen::Vector3i(dx, dy, dz)));
          if (it == grid_.end()) continue;
          for (uint32_t i : it->second) offer(i);
        }
    if (std::isinf(best_sq))
      for (std::size_t i = 0; i < samples_.size(); ++i) offer(static_cast<uint32_t>(i));
    return best;
  }

 private:
  std::span<const Vec3> samples_;
  double cell_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> grid_;
};

}  // namespace

ToolSceneDistanceSearch::ToolSceneDistanceSearch(const TriangleMesh& tool,
                                                 std::span<const Vec3> samples, double spacing_m)
    : samples_(samples.begin(), samples.end()) {
  if (samples.empty()) throw std::invalid_argument("tool-scene distance: no tool samples");
  if (!(spacing_m > 0))
    throw std::invalid_argument("tool-scene distance: sample spacing must be > 0 m");
  triangles_.reserve(tool.triangles.size());
  for (const auto& [a, b, c] : tool.triangles) {
    const TriangleCorners& corners = triangles_.emplace_back(
        TriangleCorners{tool.vertices[a], tool.vertices[b], tool.vertices[c]});
    const Vec3 centroid = (corners[0] + corners[1] + corners[2]) / 3;
    centroids_.push_back(centroid);
    radii_.push_back(std::max({(corners[0] - centroid).norm(), (corners[1] - centroid).norm(),
                               (corners[2] - centroid).norm()}));
  }

  // Each triangle to the sample nearest its centroid, then grouped by sample.
  const NearestSample nearest(samples_, spacing_m);
  std::vector<uint32_t> owner(triangles_.size());
  cluster_start_.assign(samples_.size() + 1, 0);
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    owner[t] = nearest(centroids_[t]);
    ++cluster_start_[owner[t] + 1];
  }
  for (std::size_t s = 0; s < samples_.size(); ++s) cluster_start_[s + 1] += cluster_start_[s];
  cluster_triangles_.resize(triangles_.size());
  reach_.resize(triangles_.size());
  cluster_radius_.assign(samples_.size(), 0.0);
  std::vector<std::size_t> fill(cluster_start_.begin(), cluster_start_.end() - 1);
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const uint32_t s = owner[t];
    const std::size_t row = fill[s]++;
    cluster_triangles_[row] = static_cast<uint32_t>(t);
    // Every point of the triangle is within this of the sample (the
    // distance from a point is convex, so largest at a corner).
    double reach = 0;
    for (const Vec3& corner : triangles_[t]) reach = std::max(reach, (corner - samples_[s]).norm());
    reach_[row] = reach;
    cluster_radius_[s] = std::max(cluster_radius_[s], reach);
  }
}

std::optional<ToolSceneDistance> ToolSceneDistanceSearch::evaluate(
    const Oracle& oracle, const Pose& tool_pose, const PointQueryResult& sample_closest) {
  const std::vector<double>& sample_distance = sample_closest.distance;
  if (sample_distance.size() != samples_.size() || sample_closest.closest.size() != samples_.size())
    throw std::invalid_argument("tool-scene distance: one closest point per sample expected");
  ToolSceneDistance result;
  // The nearest sample is a point of the tool: its distance bounds the
  // tool's from above.
  const auto nearest =
      std::min_element(sample_distance.begin(), sample_distance.end()) - sample_distance.begin();
  double bound = sample_distance[static_cast<std::size_t>(nearest)];
  result.distance_m = bound;
  result.on_tool = tool_pose.transform_point(samples_[static_cast<std::size_t>(nearest)]);
  result.on_scene = sample_closest.closest[static_cast<std::size_t>(nearest)];
  if (!std::isfinite(bound)) return result;  // no scene triangle (or no finite distance)

  // Distance is 1-Lipschitz: no point of cluster s is nearer the scene than
  // d(s) − radius(s). Clusters by that lower bound, most promising first.
  open_clusters_.clear();
  for (std::size_t s = 0; s < samples_.size(); ++s) {
    if (cluster_start_[s] == cluster_start_[s + 1]) continue;
    const double lower = sample_distance[s] - cluster_radius_[s];
    if (lower <= bound + kToolSceneBoundSlackM)
      open_clusters_.emplace_back(lower, static_cast<uint32_t>(s));
  }
  std::sort(open_clusters_.begin(), open_clusters_.end());

  for (const auto& [lower, s] : open_clusters_) {
    if (lower > bound + kToolSceneBoundSlackM) break;  // bound only shrinks: so do all after
    const Vec3 sample_world = tool_pose.transform_point(samples_[s]);
    // Every scene triangle within `bound` of a point of the cluster is
    // within radius + bound of its sample.
    if (!oracle.triangles_within(sample_world, cluster_radius_[s] + bound + kToolSceneBoundSlackM,
                                 near_))
      return std::nullopt;
    if (near_.empty()) continue;
    for (std::size_t row = cluster_start_[s]; row < cluster_start_[s + 1]; ++row) {
      // No point of the row's triangle is nearer the scene than this.
      if (sample_distance[s] - reach_[row] > bound + kToolSceneBoundSlackM) continue;
      const uint32_t t = cluster_triangles_[row];
      const Vec3 centroid = tool_pose.transform_point(centroids_[t]);
      std::optional<TriangleCorners> tool_triangle;  // posed on first use
      for (const NearTriangle& scene_triangle : near_) {
        // The scene triangle is at least its distance to the sample minus
        // the row's reach away from the tool triangle.
        if (scene_triangle.distance - reach_[row] > bound + kToolSceneBoundSlackM) continue;
        // Every point of the tool triangle is within radii_[t] of its
        // centroid: the pair is at least `lower` apart. Beyond the bound it
        // cannot be nearer; above 0 the triangles cannot intersect.
        const TriangleCorners& scene_corners = scene_triangle.corners;
        const Vec3 foot = closest_point_on_triangle(centroid, scene_corners[0], scene_corners[1],
                                                    scene_corners[2]);
        const double lower = (foot - centroid).norm() - radii_[t];
        if (lower > bound + kToolSceneBoundSlackM) continue;
        if (!tool_triangle) {
          const TriangleCorners& local = triangles_[t];
          tool_triangle = TriangleCorners{tool_pose.transform_point(local[0]),
                                          tool_pose.transform_point(local[1]),
                                          tool_pose.transform_point(local[2])};
        }
        ++result.triangle_pairs;
        if (!(lower > kToolSceneBoundSlackM) &&
            triangles_intersect(*tool_triangle, scene_corners)) {
          // A shared point: the distance is 0, nothing can be nearer.
          result.crossing = true;
          result.distance_m = 0;
          result.crossing_tool_triangle = *tool_triangle;
          result.crossing_scene_triangle = scene_corners;
          return result;
        }
        const TrianglePairClosest pair =
            closest_points_of_disjoint_triangles(*tool_triangle, scene_corners);
        if (pair.distance < result.distance_m) {
          bound = pair.distance;
          result.distance_m = pair.distance;
          result.on_tool = pair.on_a;
          result.on_scene = pair.on_b;
        }
      }
    }
  }
  return result;
}

}  // namespace hb
