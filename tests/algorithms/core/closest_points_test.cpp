// Tests for algorithms/core/closest_points.cpp against closed forms and
// against brute force (the minimum over a dense grid of the triangle or of
// both segments), including the degenerate cases the module fixes a rule for.
#include "hapticbench/closest_points.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

namespace hb {
namespace {

Vec3 random_point(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return Vec3(u(rng), u(rng), u(rng));
}

// Smallest distance from p to a grid of points spread over the triangle.
double grid_distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  constexpr int kSteps = 300;
  double best = INFINITY;
  for (int i = 0; i <= kSteps; ++i)
    for (int j = 0; i + j <= kSteps; ++j) {
      const double u = double(i) / kSteps, v = double(j) / kSteps;
      best = std::min(best, (p - (a + u * (b - a) + v * (c - a))).norm());
    }
  return best;
}

double grid_distance_of_segments(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  constexpr int kSteps = 400;
  double best = INFINITY;
  for (int i = 0; i <= kSteps; ++i)
    for (int j = 0; j <= kSteps; ++j)
      best = std::min(
          best, ((p0 + (double(i) / kSteps) * (p1 - p0)) - (q0 + (double(j) / kSteps) * (q1 - q0)))
                    .norm());
  return best;
}

// Is q in the closed triangle (within a relative tolerance)?
bool in_triangle(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double area2 = n.squaredNorm();
  const double off_plane = std::abs((q - a).dot(n)) / std::sqrt(area2);
  const double u = (c - b).cross(q - b).dot(n) / area2;
  const double v = (a - c).cross(q - c).dot(n) / area2;
  const double w = (b - a).cross(q - a).dot(n) / area2;
  return off_plane < 1e-12 && u > -1e-12 && v > -1e-12 && w > -1e-12;
}

TEST_CASE("closest point on a triangle: each Voronoi region by hand") {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  CHECK((closest_point_on_triangle(Vec3(0.2, 0.3, 0.7), a, b, c) - Vec3(0.2, 0.3, 0)).norm() <
        1e-15);
  CHECK((closest_point_on_triangle(Vec3(-1, -1, 1), a, b, c) - a).norm() == 0);
  CHECK((closest_point_on_triangle(Vec3(2, -0.5, 0), a, b, c) - b).norm() == 0);
  CHECK((closest_point_on_triangle(Vec3(-0.5, 3, 0), a, b, c) - c).norm() == 0);
  CHECK((closest_point_on_triangle(Vec3(0.4, -2, 1), a, b, c) - Vec3(0.4, 0, 0)).norm() < 1e-15);
  CHECK((closest_point_on_triangle(Vec3(-2, 0.6, -1), a, b, c) - Vec3(0, 0.6, 0)).norm() < 1e-15);
  CHECK((closest_point_on_triangle(Vec3(1, 1, 0), a, b, c) - Vec3(0.5, 0.5, 0)).norm() < 1e-15);
}

TEST_CASE("closest point on a triangle agrees with a dense grid for random triangles") {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 a = random_point(rng, 1), b = random_point(rng, 1), c = random_point(rng, 1);
    const Vec3 p = random_point(rng, 2);
    const Vec3 q = closest_point_on_triangle(p, a, b, c);
    INFO("trial " << trial);
    REQUIRE(in_triangle(q, a, b, c));
    // The grid's best is never better than the exact closest point, and the
    // closest point is within the grid's spacing of the grid's best.
    const double grid = grid_distance_to_triangle(p, a, b, c);
    CHECK((p - q).norm() <= grid + 1e-12);
    CHECK((p - q).norm() >= grid - 2 * ((b - a).norm() + (c - a).norm()) / 300);
  }
}

TEST_CASE("a degenerate triangle is the union of its edges") {
  // Collinear corners: the nearest point of segment [a, c] (the longest).
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(3, 0, 0);
  CHECK((closest_point_on_triangle(Vec3(2, 1, 0), a, b, c) - Vec3(2, 0, 0)).norm() < 1e-15);
  CHECK((closest_point_on_triangle(Vec3(5, 1, 0), a, b, c) - c).norm() == 0);
  // All three corners equal: that point.
  CHECK((closest_point_on_triangle(Vec3(1, 2, 3), b, b, b) - b).norm() == 0);
  // Nearly collinear (sin of the angle 1e-13) counts as degenerate, and the
  // answer is still the nearest point of the (almost) flat triangle.
  const Vec3 flat(3, 1e-13, 0);
  const Vec3 q = closest_point_on_triangle(Vec3(2, 1, 0), a, b, flat);
  CHECK(std::abs(q.x() - 2) < 1e-12);
  CHECK(std::abs(q.y()) < 1e-12);
}

TEST_CASE("closest points of segments agree with a dense grid for random segments") {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 100; ++trial) {
    const Vec3 p0 = random_point(rng, 1), p1 = random_point(rng, 1);
    const Vec3 q0 = random_point(rng, 1), q1 = random_point(rng, 1);
    const SegmentParameters st = closest_segment_parameters(p0, p1, q0, q1);
    INFO("trial " << trial);
    REQUIRE(st.s >= 0);
    REQUIRE(st.s <= 1);
    REQUIRE(st.t >= 0);
    REQUIRE(st.t <= 1);
    const double distance = closest_points_of_segments(p0, p1, q0, q1).distance();
    const double grid = grid_distance_of_segments(p0, p1, q0, q1);
    CHECK(distance <= grid + 1e-12);
    CHECK(distance >= grid - ((p1 - p0).norm() + (q1 - q0).norm()) / 400);
  }
}

TEST_CASE("segments: zero length, parallel and crossing cases follow the stated rule") {
  // A zero-length first segment is its point: closest point on the other.
  auto r =
      closest_points_of_segments(Vec3(0.5, 1, 0), Vec3(0.5, 1, 0), Vec3(0, 0, 0), Vec3(1, 0, 0));
  CHECK((r.on_q - Vec3(0.5, 0, 0)).norm() < 1e-15);
  CHECK(r.distance() == Approx(1.0));
  // Both zero length: the two points.
  r = closest_points_of_segments(Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(0, 0, 0), Vec3(0, 0, 0));
  CHECK(r.distance() == Approx(std::sqrt(14.0)));
  // Parallel and overlapping: s = 0 on the first, its projection on the second.
  const SegmentParameters parallel =
      closest_segment_parameters(Vec3(0.2, 1, 0), Vec3(2, 1, 0), Vec3(0, 0, 0), Vec3(1, 0, 0));
  CHECK(parallel.s == 0);
  CHECK(parallel.t == Approx(0.2));
  // Parallel and disjoint along the line: the facing end points.
  r = closest_points_of_segments(Vec3(3, 1, 0), Vec3(4, 1, 0), Vec3(0, 0, 0), Vec3(1, 0, 0));
  CHECK((r.on_p - Vec3(3, 1, 0)).norm() < 1e-15);
  CHECK((r.on_q - Vec3(1, 0, 0)).norm() < 1e-15);
  // Crossing at right angles, 0.5 apart.
  r = closest_points_of_segments(Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0.3, -1, 0.5),
                                 Vec3(0.3, 1, 0.5));
  CHECK((r.on_p - Vec3(0.3, 0, 0)).norm() < 1e-15);
  CHECK(r.distance() == Approx(0.5));
}

TEST_CASE("the 2-D form gives the same parameters as the 3-D one in a plane") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Vector2d p0(u(rng), u(rng)), p1(u(rng), u(rng)), q0(u(rng), u(rng)),
        q1(u(rng), u(rng));
    const SegmentParameters flat = closest_segment_parameters(p0, p1, q0, q1);
    auto lift = [](const Eigen::Vector2d& v) { return Vec3(v.x(), v.y(), 0); };
    const SegmentParameters space =
        closest_segment_parameters(lift(p0), lift(p1), lift(q0), lift(q1));
    CHECK(flat.s == Approx(space.s).margin(1e-12));
    CHECK(flat.t == Approx(space.t).margin(1e-12));
  }
}

TEST_CASE("closest point on a segment clamps to its ends") {
  const Vec3 a(0, 0, 0), b(2, 0, 0);
  CHECK((closest_point_on_segment(Vec3(1, 1, 0), a, b) - Vec3(1, 0, 0)).norm() == 0);
  CHECK((closest_point_on_segment(Vec3(-1, 1, 0), a, b) - a).norm() == 0);
  CHECK((closest_point_on_segment(Vec3(3, 1, 0), a, b) - b).norm() == 0);
  CHECK((closest_point_on_segment(Vec3(3, 1, 0), a, a) - a).norm() == 0);
}

}  // namespace
}  // namespace hb
