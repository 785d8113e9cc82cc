// Distance-only scenes: the tool's distance to an open sheet and whether it
// crosses it, per tick by the OracleEvaluator, against closed forms. The
// sheet is two triangles in the plane z = 0 (marked distance_only), the
// tool a 3 × 2 × 1 cm box. Units m; quaternions (qw,qx,qy,qz).
#include "harness/reference/tool_scene_distance.h"

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "hapticbench/shapes.h"
#include "harness/reference/oracle.h"
#include "harness/reference/oracle_evaluation.h"
#include "harness/reference/triangle_pair_distance.h"
#include "tests/support/shape_fixtures.h"

namespace hb {
namespace tool_scene_distance_test {

using test::box_shape;
using test::kPi;

const Vec3 kBoxSize(0.03, 0.02, 0.01);
constexpr double kHalfHeight = 0.005;

// The open square sheet x in [x_min, x_max], y in [-0.05, 0.05], z = 0.
SceneObject sheet(double x_min, double x_max) {
  SceneObject object;
  object.name = "sheet";
  object.mesh.vertices = {Vec3(x_min, -0.05, 0), Vec3(x_max, -0.05, 0), Vec3(x_max, 0.05, 0),
                          Vec3(x_min, 0.05, 0)};
  object.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  object.distance_only = true;
  return object;
}

RenderContext box_over(const SceneObject& scene_object) {
  RenderContext context;
  context.scene = {scene_object};
  context.tool.shape = box_shape(kBoxSize);
  context.tool.mesh = shape_mesh(*context.tool.shape);
  return context;
}

OracleTickEvaluation evaluate_at(OracleEvaluator& evaluator, const Pose& pose) {
  return evaluator.evaluate(0, pose, {});
}

TEST_CASE("a box moved through an open sheet crosses it exactly while it straddles the plane") {
  const RenderContext context = box_over(sheet(-0.05, 0.05));
  for (const char* backend : {"embree", "cgal"}) {
    INFO(backend);
    OracleEvaluator evaluator(context, {{backend}, 1, 0});
    REQUIRE_FALSE(evaluator.measures_penetration());
    // Straddling (|z| <= half height, touching included): crossing, distance 0.
    for (const double z : {-0.00499, -0.0031, 0.0, 0.00137, 0.00437, 0.004999, kHalfHeight}) {
      INFO("centre z = " << z);
      const OracleTickEvaluation out = evaluate_at(evaluator, test::at(Vec3(0.003, -0.002, z)));
      REQUIRE(out.crossing);
      CHECK(*out.crossing);
      REQUIRE(out.min_distance_m);
      CHECK(*out.min_distance_m == 0.0);
    }
    // Clear of the plane: no crossing, the gap between the parallel faces.
    for (const double z : {-0.0063, 0.0051, 0.0123}) {
      INFO("centre z = " << z);
      const OracleTickEvaluation out = evaluate_at(evaluator, test::at(Vec3(0.003, -0.002, z)));
      REQUIRE(out.crossing);
      CHECK_FALSE(*out.crossing);
      REQUIRE(out.min_distance_m);
      CHECK(*out.min_distance_m == Approx(std::abs(z) - kHalfHeight).margin(1e-15));
    }
    // Straddling the plane but 1 mm beside the sheet's edge x = 0.05: no
    // crossing, the gap to the edge.
    const OracleTickEvaluation beside =
        evaluate_at(evaluator, test::at(Vec3(0.05 + 0.015 + 0.001, 0, 0.0017)));
    REQUIRE(beside.crossing);
    CHECK_FALSE(*beside.crossing);
    CHECK(*beside.min_distance_m == Approx(0.001).margin(1e-15));
  }
}

TEST_CASE("a tilted box whose lowest corner dips 1 nm through the sheet crosses it") {
  const RenderContext context = box_over(sheet(-0.05, 0.05));
  // A generic orientation; the lowest corner is c_z − Σ_j |R_zj| h_j below
  // the centre (h the half sizes).
  const Quat q(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
  const Eigen::Matrix3d r = q.toRotationMatrix();
  const double drop =
      std::abs(r(2, 0)) * 0.015 + std::abs(r(2, 1)) * 0.01 + std::abs(r(2, 2)) * kHalfHeight;
  for (const char* backend : {"embree", "cgal"}) {
    INFO(backend);
    OracleEvaluator evaluator(context, {{backend}, 1, 0});
    for (const double gap : {-1e-9, 1e-9, 1e-6}) {
      INFO("lowest corner at z = " << gap);
      const OracleTickEvaluation out =
          evaluate_at(evaluator, test::at(Vec3(0.002, 0.001, drop + gap), q));
      REQUIRE(out.crossing);
      CHECK(*out.crossing == (gap < 0));
      REQUIRE(out.min_distance_m);
      if (gap > 0)
        CHECK(*out.min_distance_m == Approx(gap).margin(1e-15));
      else
        CHECK(*out.min_distance_m == 0.0);
    }
  }
}

// The box turned 45° about x (its lowest edge runs along x), then tilted by
// α about y (the edge descends toward +x), over a sheet that ends at x = 0.
// The edge passes the sheet's boundary edge (the y axis) at height h at
// x = 0: the two are skew lines h cos α apart, nearest at an interior point
// of each, and the sheet's interior and every corner of the box are
// farther. Surface samples meet that edge point only by chance.
TEST_CASE("a box edge skew to the sheet's boundary edge: the distance is h cos α") {
  const RenderContext context = box_over(sheet(-0.05, 0.0));
  for (const double alpha : {0.35, 0.6}) {
    for (const double h : {0.002, 0.0007}) {
      const Quat q = Quat(Eigen::AngleAxisd(alpha, Vec3::UnitY())) *
                     Quat(Eigen::AngleAxisd(kPi / 4, Vec3::UnitX()));
      // The edge's point x = 0 of the tool frame, (0, −1 cm, −0.5 cm), goes to (0, y0, h).
      const Vec3 edge_middle = q * Vec3(0, -0.01, -kHalfHeight);
      const Pose pose = test::at(Vec3(0, 0, h) - Vec3(edge_middle.x(), 0, edge_middle.z()), q);
      const double expected = h * std::cos(alpha);
      for (const char* backend : {"embree", "cgal"}) {
        INFO(backend << ", alpha " << alpha << ", h " << h);
        OracleEvaluator evaluator(context, {{backend}, 1, 0});
        const OracleTickEvaluation out = evaluate_at(evaluator, pose);
        REQUIRE(out.crossing);
        CHECK_FALSE(*out.crossing);
        REQUIRE(out.min_distance_m);
        CHECK(*out.min_distance_m == Approx(expected).margin(1e-12));
      }
    }
  }
}

TEST_CASE("ToolSceneDistanceSearch: the closest points of the skew edges are the closed form's") {
  const RenderContext context = box_over(sheet(-0.05, 0.0));
  const auto oracle = make_embree_oracle(context.scene);
  const double alpha = 0.35, h = 0.002;
  const Quat q = Quat(Eigen::AngleAxisd(alpha, Vec3::UnitY())) *
                 Quat(Eigen::AngleAxisd(kPi / 4, Vec3::UnitX()));
  const Vec3 edge_middle = q * Vec3(0, -0.01, -kHalfHeight);
  const Pose pose = test::at(Vec3(0, 0, h) - Vec3(edge_middle.x(), 0, edge_middle.z()), q);
  // Only the eight corners as samples: the search still finds the edge point.
  std::vector<Vec3> corners = context.tool.mesh.vertices;
  ToolSceneDistanceSearch search(context.tool.mesh, corners, 0.01);
  std::vector<Vec3> world;
  for (const Vec3& c : corners) world.push_back(pose.transform_point(c));
  PointQueryResult closest;
  oracle->query_points({.points = world, .want_inside = false, .want_closest = true}, closest);
  const std::optional<ToolSceneDistance> result = search.evaluate(*oracle, pose, closest);
  REQUIRE(result);
  CHECK_FALSE(result->crossing);
  CHECK(result->distance_m == Approx(h * std::cos(alpha)).margin(1e-12));
  // On the sheet: the boundary edge's point (0, y0, 0); on the box: the
  // foot h sin α cos α along x, at height h cos² α.
  CHECK((result->on_scene - Vec3(0, edge_middle.y(), 0)).norm() < 1e-12);
  CHECK((result->on_tool - Vec3(h * std::sin(alpha) * std::cos(alpha), edge_middle.y(),
                                h * std::cos(alpha) * std::cos(alpha)))
            .norm() < 1e-12);
  CHECK(result->triangle_pairs > 0);
}

TEST_CASE("closest points of disjoint triangles agree with a dense search, crossings are exact") {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  const auto random_triangle = [&](const Vec3& offset) {
    return TriangleCorners{
        offset + Vec3(coordinate(random), coordinate(random), 0.3 * coordinate(random)),
        offset + Vec3(coordinate(random), coordinate(random), 0.3 * coordinate(random)),
        offset + Vec3(coordinate(random), coordinate(random), 0.3 * coordinate(random))};
  };
  // Points of a triangle on a barycentric grid.
  const auto grid = [](const TriangleCorners& t) {
    std::vector<Vec3> points;
    constexpr int n = 60;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j)
        points.push_back(t[0] + (static_cast<double>(i) / n) * (t[1] - t[0]) +
                         (static_cast<double>(j) / n) * (t[2] - t[0]));
    return points;
  };
  int disjoint = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const TriangleCorners a = random_triangle(Vec3::Zero());
    const TriangleCorners b = random_triangle(Vec3(0, 0, 0.5 * coordinate(random) + 0.6));
    if (triangles_intersect(a, b)) continue;
    ++disjoint;
    const TrianglePairClosest pair = closest_points_of_disjoint_triangles(a, b);
    CHECK(pair.distance == Approx((pair.on_a - pair.on_b).norm()).margin(1e-15));
    double dense = std::numeric_limits<double>::infinity();
    const std::vector<Vec3> points_b = grid(b);
    for (const Vec3& p : grid(a))
      for (const Vec3& r : points_b) dense = std::min(dense, (p - r).norm());
    // Never above any pair of points, and the grid gets within its pitch.
    CHECK(pair.distance <= dense + 1e-12);
    CHECK(dense - pair.distance < 0.1);
  }
  CHECK(disjoint >= 10);

  // Closed cases: crossing, touching at a vertex, apart by 1e-12.
  const TriangleCorners floor{Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(0, 1, 0)};
  CHECK(triangles_intersect(floor, {Vec3(0, 0, -0.5), Vec3(0.2, 0, 0.5), Vec3(0, 0.2, 0.5)}));
  CHECK(triangles_intersect(floor, {Vec3(0, 0, 0), Vec3(0.2, 0, 0.5), Vec3(0, 0.2, 0.5)}));
  CHECK_FALSE(
      triangles_intersect(floor, {Vec3(0, 0, 1e-12), Vec3(0.2, 0, 0.5), Vec3(0, 0.2, 0.5)}));
}

TEST_CASE("the CGAL oracle lists the same triangles near a point as Embree") {
  // A 12-triangle box and the open sheet: every triangle within a radius.
  SceneObject box;
  box.name = "box";
  box.shape = box_shape(Vec3(0.04, 0.02, 0.03));
  box.mesh = shape_mesh(*box.shape);
  box.pose = test::pose(Vec3(0.01, 0.0, 0.03), 0.4, Vec3(1, 1, 0));
  const std::vector<SceneObject> scene = {box, sheet(-0.05, 0.05)};
  const auto embree = make_embree_oracle(scene);
  const auto cgal = make_cgal_oracle(scene);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> coordinate(-0.06, 0.06);
  std::vector<NearTriangle> from_embree, from_cgal;
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 point(coordinate(random), coordinate(random), coordinate(random));
    const double radius = 0.5 * std::abs(coordinate(random));
    REQUIRE(embree->triangles_within(point, radius, from_embree));
    REQUIRE(cgal->triangles_within(point, radius, from_cgal));
    REQUIRE(from_embree.size() == from_cgal.size());
    const auto key = [](const NearTriangle& t) {
      return std::array<double, 4>{
          t.distance, t.corners[0].x() + t.corners[1].x() + t.corners[2].x(),
          t.corners[0].y() + t.corners[1].y() + t.corners[2].y(), static_cast<double>(t.object)};
    };
    std::vector<std::array<double, 4>> a, b;
    for (const NearTriangle& t : from_embree) a.push_back(key(t));
    for (const NearTriangle& t : from_cgal) b.push_back(key(t));
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    for (std::size_t i = 0; i < a.size(); ++i)
      for (int k = 0; k < 4; ++k) CHECK(a[i][k] == Approx(b[i][k]).margin(1e-15));
  }
}

}  // namespace tool_scene_distance_test
}  // namespace hb
