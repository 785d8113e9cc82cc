// Proximity queries against brute force: at random poses of a tool near a
// scene, the pairs listed are exactly those within the distance asked for
// (or the nearest max_pairs), and no pair left out is nearer than the
// clearance. Distances are recomputed from the meshes with the closest-
// point functions, pair by pair.
#include <algorithm>
#include <catch2/catch.hpp>
#include <limits>
#include <random>
#include <vector>

#include "algorithms/ccd/mesh_ccd.h"
#include "hapticbench/closest_points.h"
#include "hapticbench/shapes.h"
#include "tests/support/proxy_fixtures.h"

namespace hb {
namespace {

struct BruteForcePair {
  ContactFeatures features;
  double distance;
};

// Every feature pair of the tool (mesh in its own frame, placed at `pose`)
// and the one scene object, with its distance.
std::vector<BruteForcePair> all_pairs(const MeshCcd& ccd, const TriangleMesh& tool,
                                      const TriangleMesh& scene, const Pose& pose) {
  std::vector<Vec3> world;
  for (const Vec3& v : tool.vertices) world.push_back(pose.transform_point(v));
  std::vector<BruteForcePair> pairs;
  for (std::size_t v = 0; v < world.size(); ++v)
    for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
      const auto& tri = scene.triangles[t];
      const Vec3 on = closest_point_on_triangle(world[v], scene.vertices[tri[0]],
                                                scene.vertices[tri[1]], scene.vertices[tri[2]]);
      pairs.push_back(
          {{ContactFeatureKind::kToolVertexSceneFace, 0, int(v), int(t)}, (world[v] - on).norm()});
    }
  for (std::size_t t = 0; t < tool.triangles.size(); ++t)
    for (std::size_t v = 0; v < scene.vertices.size(); ++v) {
      const auto& tri = tool.triangles[t];
      const Vec3 on =
          closest_point_on_triangle(scene.vertices[v], world[tri[0]], world[tri[1]], world[tri[2]]);
      pairs.push_back({{ContactFeatureKind::kSceneVertexToolFace, 0, int(t), int(v)},
                       (scene.vertices[v] - on).norm()});
    }
  const auto tool_edges = ccd.tool_edges();
  const auto scene_edges = ccd.scene_edges(0);
  for (std::size_t a = 0; a < tool_edges.size(); ++a)
    for (std::size_t b = 0; b < scene_edges.size(); ++b) {
      const double d = closest_points_of_segments(world[tool_edges[a][0]], world[tool_edges[a][1]],
                                                  scene.vertices[scene_edges[b][0]],
                                                  scene.vertices[scene_edges[b][1]])
                           .distance();
      pairs.push_back({{ContactFeatureKind::kEdgeEdge, 0, int(a), int(b)}, d});
    }
  return pairs;
}

bool listed(const ProximityResult& result, const ContactFeatures& features) {
  return std::any_of(result.pairs.begin(), result.pairs.end(),
                     [&](const ProximityPair& p) { return p.features == features; });
}

// A 2 cm icosphere and a 4 cm box (12 triangles, each larger than the
// sphere), one the tool and the other the scene object, at random poses
// from touching distance to 1 cm apart: small triangles against large ones
// from both sides of the search.
TEST_CASE("proximity lists exactly the pairs within the distance, or the nearest ones") {
  const bool sphere_tool = GENERATE(true, false);
  INFO((sphere_tool ? "sphere tool, box scene" : "box tool, sphere scene"));
  const TriangleMesh sphere = shape_mesh(test::sphere_tool(0.01).shape.value());
  const TriangleMesh box = shape_mesh(*test::box_object(Vec3(0.04, 0.04, 0.04), Pose{}).shape);
  const TriangleMesh& tool = sphere_tool ? sphere : box;
  SceneObject object;
  object.name = "scene";
  object.mesh = sphere_tool ? box : sphere;
  const std::vector<SceneObject> scene = {object};
  const MeshCcd ccd(tool, scene);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> lateral(-0.03, 0.03), gap(0.0001, 0.01), angle(-3, 3);
  int crowded = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const Pose pose{Vec3(lateral(rng), lateral(rng), 0.02 + 0.01 + gap(rng)),
                    quat_from_rotation_vector(Vec3(angle(rng), angle(rng), angle(rng)))};
    const std::vector<BruteForcePair> pairs = all_pairs(ccd, tool, object.mesh, pose);
    for (std::size_t max_pairs : {std::size_t{100000}, std::size_t{8}}) {
      const double max_distance = 0.005;
      const ProximityResult result = ccd.proximity(pose, max_distance, max_pairs);
      INFO("trial " << trial << ", max_pairs " << max_pairs << ", listed " << result.pairs.size());
      REQUIRE(result.pairs.size() <= max_pairs);
      CHECK(result.clearance_m <= max_distance);
      CHECK(std::is_sorted(result.pairs.begin(), result.pairs.end(),
                           [](const auto& a, const auto& b) { return a.distance < b.distance; }));
      std::size_t within = 0;
      for (const BruteForcePair& pair : pairs) {
        within += pair.distance <= max_distance;
        if (listed(result, pair.features)) {
          CHECK(pair.distance <= result.clearance_m + 1e-15);
          const PairClosestPoints points = ccd.closest_points(pair.features, pose);
          CHECK(points.distance == Approx(pair.distance).margin(1e-15));
        } else {
          CHECK(pair.distance >= result.clearance_m - 1e-15);  // no unlisted pair is nearer
        }
      }
      if (max_pairs > within) {
        CHECK(result.pairs.size() == within);  // every pair within the distance
        CHECK(result.clearance_m == max_distance);
      } else {
        ++crowded;
        CHECK(result.pairs.size() == max_pairs);
      }
    }
  }
  CHECK(crowded > 10);  // the cap was exercised
}

// The same query worked in slices (MeshCcd::start_proximity): whatever the
// slice, the answer is proximity()'s bit for bit, and the nearest-distance
// bound it gives on the way never exceeds the true nearest distance and is
// that distance once the search is complete.
TEST_CASE("a proximity query worked in slices answers as one worked at once") {
  const TriangleMesh sphere = shape_mesh(test::sphere_tool(0.01).shape.value());
  SceneObject object;
  object.name = "box";
  object.mesh = shape_mesh(*test::box_object(Vec3(0.04, 0.04, 0.04), Pose{}).shape);
  const std::vector<SceneObject> scene = {object};
  const MeshCcd ccd(sphere, scene);
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> lateral(-0.03, 0.03), gap(0.0001, 0.01), angle(-3, 3);
  for (int trial = 0; trial < 20; ++trial) {
    const Pose pose{Vec3(lateral(rng), lateral(rng), 0.02 + 0.01 + gap(rng)),
                    quat_from_rotation_vector(Vec3(angle(rng), angle(rng), angle(rng)))};
    const std::vector<BruteForcePair> pairs = all_pairs(ccd, sphere, object.mesh, pose);
    double nearest = std::numeric_limits<double>::infinity();
    for (const BruteForcePair& pair : pairs) nearest = std::min(nearest, pair.distance);
    for (const std::size_t max_pairs : {std::size_t{0}, std::size_t{8}, std::size_t{100000}}) {
      const ProximityResult whole = ccd.proximity(pose, 0.05, max_pairs);
      for (const int64_t slice : {1, 7, 100}) {
        INFO("trial " << trial << ", max_pairs " << max_pairs << ", slice " << slice);
        ProximityInSlices sliced = ccd.start_proximity(pose, 0.05, max_pairs);
        int slices = 0;
        double bound = 0;
        bool complete = false;
        while (!complete) {
          complete = sliced.advance(slice);
          ++slices;
          CHECK(sliced.nearest_bound() <= nearest + 1e-15);
          CHECK(sliced.nearest_bound() >= bound);  // it only tightens
          bound = sliced.nearest_bound();
        }
        CHECK(bound == Approx(nearest).margin(1e-15));
        if (slice == 1) CHECK(slices > 10);
        const int64_t opened = sliced.opened();
        CHECK(opened >= slices - 1);
        const ProximityResult answer = sliced.finish();
        CHECK(answer.clearance_m == whole.clearance_m);
        REQUIRE(answer.pairs.size() == whole.pairs.size());
        for (std::size_t i = 0; i < answer.pairs.size(); ++i) {
          CHECK(answer.pairs[i].features == whole.pairs[i].features);
          CHECK(answer.pairs[i].distance == whole.pairs[i].distance);
        }
        CHECK(answer.bv_tests == whole.bv_tests);
      }
    }
  }
  // One that was never started is complete and lists nothing.
  ProximityInSlices none;
  CHECK(none.advance(1));
  CHECK(none.finish().pairs.empty());
}

// Many pairs measured at one pose (MeshCcd::closest_points and evaluate over
// a span) give each pair's values alone, bit for bit: on a coarse sphere (42
// vertices) and on one with more (2,562) than the batch keeps placed at once
// (64), so that vertices taking one another's place occur.
TEST_CASE("closest points and geometry of many pairs at one pose are those of each pair alone") {
  SceneObject object;
  object.name = "scene";
  object.mesh = shape_mesh(*test::box_object(Vec3(0.04, 0.04, 0.04), Pose{}).shape);
  const std::vector<SceneObject> scene = {object};
  for (const int subdivisions : {1, 4}) {
    Shape shape = test::sphere_tool(0.01).shape.value();
    shape.subdivisions = subdivisions;
    const TriangleMesh sphere = shape_mesh(shape);
    const MeshCcd ccd(sphere, scene);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> lateral(-0.03, 0.03), gap(0.0001, 0.004), angle(-3, 3);
    std::size_t kinds_seen[3] = {0, 0, 0};
    bool shared_slot = false;  // two tool vertices a multiple of 64 apart in one batch
    for (int trial = 0; trial < 20; ++trial) {
      const Pose pose{Vec3(lateral(rng), lateral(rng), 0.03 + gap(rng)),
                      quat_from_rotation_vector(Vec3(angle(rng), angle(rng), angle(rng)))};
      const ProximityResult found = ccd.proximity(pose, 0.005, 100000);
      std::vector<ContactFeatures> pairs;
      std::vector<int> vertices;
      for (const ProximityPair& p : found.pairs) {
        pairs.push_back(p.features);
        if (p.features.kind == ContactFeatureKind::kToolVertexSceneFace)
          vertices.push_back(p.features.tool_feature);
      }
      for (const int a : vertices)
        for (const int b : vertices) shared_slot = shared_slot || (a != b && a % 64 == b % 64);
      // Measured at another pose than the search's, as the certifier does.
      const Pose moved{pose.p + Vec3(0.0003, -0.0002, 0.0001),
                       (pose.q * quat_from_rotation_vector(Vec3(0.01, 0.02, -0.01))).normalized()};
      std::vector<PairClosestPoints> points;
      ccd.closest_points(pairs, moved, points);
      std::vector<FeatureGeometry> geometry;
      ccd.evaluate(pairs, moved, geometry);
      REQUIRE(points.size() == pairs.size());
      REQUIRE(geometry.size() == pairs.size());
      for (std::size_t i = 0; i < pairs.size(); ++i) {
        const PairClosestPoints alone = ccd.closest_points(pairs[i], moved);
        const FeatureGeometry alone_geometry = ccd.evaluate(pairs[i], moved);
        INFO("subdivisions " << subdivisions << ", trial " << trial << ", pair " << i);
        CHECK(points[i].distance == alone.distance);
        CHECK(points[i].tool_point == alone.tool_point);
        CHECK(points[i].scene_point == alone.scene_point);
        CHECK(geometry[i].point == alone_geometry.point);
        CHECK(geometry[i].normal == alone_geometry.normal);
        CHECK(geometry[i].gap == alone_geometry.gap);
        CHECK(geometry[i].distance == alone_geometry.distance);
        ++kinds_seen[static_cast<int>(pairs[i].kind)];
      }
    }
    CHECK(kinds_seen[0] > 0);
    CHECK(kinds_seen[1] > 0);
    CHECK(kinds_seen[2] > 0);
    if (sphere.vertices.size() > 64) CHECK(shared_slot);
  }
}

}  // namespace
}  // namespace hb
