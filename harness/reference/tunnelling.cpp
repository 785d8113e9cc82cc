#include "harness/reference/tunnelling.h"

#include <algorithm>
#include <array>

namespace hb {

std::vector<Vec3> tunnelling_points(const TriangleMesh& tool_mesh) {
  std::vector<Vec3> points = {Vec3::Zero()};
  if (tool_mesh.vertices.empty()) return points;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z) {
        if (x == 0 && y == 0 && z == 0) continue;
        const Vec3 direction(x, y, z);
        const Vec3* extreme = &tool_mesh.vertices.front();
        for (const Vec3& vertex : tool_mesh.vertices)
          if (vertex.dot(direction) > extreme->dot(direction)) extreme = &vertex;
        if (std::find(points.begin(), points.end(), *extreme) == points.end())
          points.push_back(*extreme);
      }
  return points;
}

ToolTunnelling::ToolTunnelling(std::vector<Vec3> points_tool,
                               const std::function<std::unique_ptr<TunnellingDetector>()>& make)
    : points_(std::move(points_tool)) {
  for (std::size_t i = 0; i < points_.size(); ++i) detectors_.push_back(make());
}

bool ToolTunnelling::update(const Pose& tool_pose) {
  bool passed = false;
  for (std::size_t i = 0; i < points_.size(); ++i)
    passed |= detectors_[i]->update(tool_pose.transform_point(points_[i]));
  return passed;
}

bool path_meets_surface(const Oracle& oracle, const Vec3& a, const Vec3& b, double touch_m) {
  // Each step goes as far as the distance to the surface, so no surface can
  // lie between two steps. A path grazing a face crawls along it; past the
  // step limit it is taken as meeting the surface.
  constexpr int kMaxSteps = 100000;
  const double length = (b - a).norm();
  if (!(length > 0)) return false;
  const Vec3 direction = (b - a) / length;
  PointQueryRequest request;
  request.want_inside = false;
  request.want_closest = true;
  PointQueryResult result;
  double travelled = 0;
  for (int step = 0; step < kMaxSteps; ++step) {
    const std::array<Vec3, 1> point = {a + travelled * direction};
    request.points = point;
    oracle.query_points(request, result);
    const double distance = result.distance[0];
    if (!(distance > touch_m)) return true;
    travelled += distance;
    if (travelled >= length) return false;
  }
  return true;
}

bool path_enters_solid(const Oracle& oracle, const Vec3& a, const Vec3& b, double depth_m) {
  constexpr int kMaxSteps = 100000;
  const double length = (b - a).norm();
  if (!(length > 0)) return false;
  const Vec3 direction = (b - a) / length;
  PointQueryRequest request;
  request.want_closest = true;
  request.want_inside = true;
  PointQueryResult result;
  double travelled = 0;
  for (int step = 0; step < kMaxSteps && travelled < length; ++step) {
    const std::array<Vec3, 1> point = {a + std::min(travelled + depth_m, length) * direction};
    request.points = point;
    oracle.query_points(request, result);
    if (result.inside[0]) return true;  // depth_m past a point on the path: inside
    const double distance = result.distance[0];
    // No surface within `distance` of the probe: the path up to there is clear.
    travelled += std::max(distance, depth_m);
  }
  return false;
}

bool OracleTunnellingDetector::update(const Vec3& origin_world) {
  if (!origin_world.allFinite()) return false;
  const std::array<Vec3, 1> point = {origin_world};
  oracle_.query_points({.points = point, .want_inside = true, .want_closest = true}, query_);
  const double distance = query_.distance[0];
  if (query_.inside[0] || !(distance > 0)) {  // wait for it to come out
    last_tick_outside_ = false;
    return false;
  }
  const Vec3 side = (origin_world - query_.closest[0]) / distance;
  bool passed = false;
  if (last_point_) {
    // Consecutive ticks outside: any path through the solid counts; and, as
    // after ticks inside, a crossing to the other side (an open sheet has
    // no inside to go through).
    passed = (last_tick_outside_ &&
              path_enters_solid(oracle_, *last_point_, origin_world, kTunnellingDepthM)) ||
             (last_side_.dot(side) < 0 && path_meets_surface(oracle_, *last_point_, origin_world));
  }
  last_point_ = origin_world;
  last_side_ = side;
  last_tick_outside_ = true;
  return passed;
}

}  // namespace hb
