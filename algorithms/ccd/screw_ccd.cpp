#include "algorithms/ccd/screw_ccd.h"

#include <cmath>
#include <initializer_list>

#include "algorithms/ccd/ccd_bisection.h"

namespace hb {

namespace {

IntervalVec3 point_interval(const Vec3& v) {
  return {Interval(v.x()), Interval(v.y()), Interval(v.z())};
}

bool within_range(const ScrewMotion& motion, std::initializer_list<Vec3> points) {
  if (!motion.within(kMaxCcdCoordinate)) return false;
  for (const Vec3& p : points)
    for (int k = 0; k < 3; ++k)
      if (!(std::abs(p[k]) <= kMaxCcdCoordinate)) return false;
  return true;
}

CcdResult out_of_range() {
  CcdResult result;
  result.contact = true;
  result.toi = 0;
  result.input_out_of_range = true;
  return result;
}

}  // namespace

CcdResult screw_vertex_face_ccd(const ScrewMotion& motion, const Vec3& body_vertex,
                                const std::array<Vec3, 3>& world_triangle,
                                const CcdSettings& settings) {
  if (!within_range(motion, {body_vertex, world_triangle[0], world_triangle[1], world_triangle[2]}))
    return out_of_range();
  const ScrewVectorPath vertex = motion.path(body_vertex);
  const IntervalVec3 x1 = point_interval(world_triangle[0]), x2 = point_interval(world_triangle[1]),
                     x3 = point_interval(world_triangle[2]);
  return ccd_detail::first_contact_by_bisection(
      [&](const Interval& t) {
        const IntervalVec3 x0 = vertex.position(motion.sample(t));
        return ccd_detail::vertex_face_may_touch(x1 - x0, x2 - x0, x3 - x0);
      },
      settings);
}

CcdResult screw_face_vertex_ccd(const ScrewMotion& motion, const std::array<Vec3, 3>& body_triangle,
                                const Vec3& world_vertex, const CcdSettings& settings) {
  if (!within_range(motion, {world_vertex, body_triangle[0], body_triangle[1], body_triangle[2]}))
    return out_of_range();
  // In the body frame the triangle stands still and only the vertex moves;
  // the tests are invariant under the rigid change of frame.
  const IntervalVec3 x1 = point_interval(body_triangle[0]), x2 = point_interval(body_triangle[1]),
                     x3 = point_interval(body_triangle[2]);
  return ccd_detail::first_contact_by_bisection(
      [&](const Interval& t) {
        const IntervalVec3 x0 = motion.body_coordinates(world_vertex, motion.sample(t));
        return ccd_detail::vertex_face_may_touch(x1 - x0, x2 - x0, x3 - x0);
      },
      settings);
}

CcdResult screw_edge_edge_ccd(const ScrewMotion& motion, const std::array<Vec3, 2>& body_edge,
                              const std::array<Vec3, 2>& world_edge, const CcdSettings& settings) {
  if (!within_range(motion, {body_edge[0], body_edge[1], world_edge[0], world_edge[1]}))
    return out_of_range();
  // The moving edge's direction only turns: enclose R(t)(r1 − r0) directly
  // rather than the difference of two enclosed positions.
  const ScrewVectorPath start = motion.path(body_edge[0]);
  const IntervalVec3 r0 = point_interval(body_edge[0]);
  const ScrewVectorPath direction = motion.path(point_interval(body_edge[1]) - r0);
  const IntervalVec3 x2 = point_interval(world_edge[0]), x3 = point_interval(world_edge[1]);
  return ccd_detail::first_contact_by_bisection(
      [&](const Interval& t) {
        const ScrewMotionSample s = motion.sample(t);
        const IntervalVec3 x0 = start.position(s);
        return ccd_detail::edge_edge_may_touch(direction.rotated(s), x2 - x0, x3 - x0);
      },
      settings);
}

}  // namespace hb
