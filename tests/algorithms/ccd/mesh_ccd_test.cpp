// Mesh continuous collision detection: a cube and a bar against boxes with
// closed-form times of contact; the armadillo moving onto the bunny along
// random screw motions, checked against CGAL's exact triangle intersection
// at sampled poses; evaluate() against hand-computed geometry. Units m;
// time is the unitless fraction of the step.
#include "algorithms/ccd/mesh_ccd.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "hapticbench/input_error.h"
#include "hapticbench/mass_properties.h"
#include "harness/mesh_io/mesh_io.h"
#include "tests/support/cgal_mesh_intersection.h"
#include "tests/support/shape_fixtures.h"

namespace hb {
namespace {

using test::pose;

// ---------------------------------------------------------------------------
// Boxes

/// Box [-h, h] about the origin. Vertex i is at (±h.x, ±h.y, ±h.z) with bit
/// 0, 1, 2 of i choosing +. Each face is split along the diagonal from its
/// lowest-numbered vertex; triangles face outward.
TriangleMesh box_mesh(const Vec3& h) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i)
    mesh.vertices.emplace_back(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(),
                               i & 4 ? h.z() : -h.z());
  const int quads[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
  for (const auto& q : quads) {
    for (const std::array<int, 3> t :
         {std::array<int, 3>{q[0], q[1], q[2]}, std::array<int, 3>{q[0], q[2], q[3]}}) {
      const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
      if ((b - a).cross(c - a).dot(a + b + c) < 0)
        mesh.triangles.push_back({t[0], t[2], t[1]});
      else
        mesh.triangles.push_back(t);
    }
  }
  return mesh;
}

int find_triangle(const TriangleMesh& mesh, std::array<int, 3> vertices) {
  std::sort(vertices.begin(), vertices.end());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    std::array<int, 3> sorted = mesh.triangles[t];
    std::sort(sorted.begin(), sorted.end());
    if (sorted == vertices) return static_cast<int>(t);
  }
  FAIL("no such triangle");
  return -1;
}

int find_edge(std::span<const std::array<int, 2>> edges, int a, int b) {
  const std::array<int, 2> key{std::min(a, b), std::max(a, b)};
  for (std::size_t e = 0; e < edges.size(); ++e)
    if (edges[e] == key) return static_cast<int>(e);
  FAIL("no such edge");
  return -1;
}

SceneObject box_object(const Vec3& half, const Vec3& centre) {
  SceneObject object;
  object.name = "box";
  object.mesh = box_mesh(half);
  object.pose.p = centre;
  return object;
}

Pose pose_at(const ScrewMotion& motion, double t) {
  return Pose{motion.point_at(Vec3::Zero(), t), Quat(motion.rotation_at(t)).normalized()};
}

// The scene box of most analytic cases: top face z = 0.05, |x|, |y| <= 0.1.
const Vec3 kSlabHalf(0.1, 0.1, 0.05);
// The cube tool: half side 0.01 about its frame's origin.
const Vec3 kCubeHalf(0.01, 0.01, 0.01);

TEST_CASE("a cube translating onto a box face lands at the closed-form time", "[mesh_ccd]") {
  const std::vector<SceneObject> scene{box_object(kSlabHalf, Vec3::Zero())};
  const MeshCcd ccd(box_mesh(kCubeHalf), scene);
  // The centre sinks from z = 0.1 to 0.05; the bottom face z_c − 0.01
  // reaches the top face z = 0.05 when z_c = 0.06, at t = 0.8.
  const ScrewMotion motion(pose(Vec3(0.003, -0.002, 0.1)), pose(Vec3(0.003, -0.002, 0.05)));
  const MeshCcdResult r = ccd.first_contact(motion, MeshCcdSettings{});
  REQUIRE(r.contact);
  CHECK(r.toi <= 0.8);
  CHECK(r.toi >= 0.8 - 1e-5);
  CHECK_FALSE(r.budget_exhausted);
  CHECK(r.bv_tests > 0);
  CHECK(r.primitive_queries > 0);
  CHECK(r.primitive_evaluations >= r.primitive_queries);
  // Flat on the face: the four bottom corners, each against the top face,
  // and every contact pushes up.
  int corners = 0;
  for (const MeshCcdContact& c : r.contacts) {
    INFO("kind " << static_cast<int>(c.features.kind) << " tool " << c.features.tool_feature
                 << " scene " << c.features.scene_feature);
    CHECK(c.geometry.normal.z() > 1 - 1e-12);
    CHECK(c.geometry.gap >= -1e-12);
    CHECK(c.geometry.gap <= 0.05 * 1e-5 + 1e-12);
    CHECK(c.toi >= r.toi);
    CHECK(c.toi <= r.toi + MeshCcdSettings{}.contact_window);
    if (c.features.kind == ContactFeatureKind::kToolVertexSceneFace) {
      CHECK(c.features.tool_feature < 4);  // vertices with bit 2 clear: z = −0.01
      ++corners;
    }
  }
  CHECK(corners >= 4);
  CHECK(r.contacts.size() >= 4);
  CHECK(std::is_sorted(r.contacts.begin(), r.contacts.end(),
                       [](const auto& a, const auto& b) { return a.toi < b.toi; }));
}

TEST_CASE("a turning bar hits a wall at the angle its corner says", "[mesh_ccd]") {
  // Bar of half length 0.1 along x, half width 0.005, turning about z by π/2
  // with no translation. The wall's face is the plane y = 0.05. The corner
  // (0.1, 0.005) is at height 0.1 sin θ + 0.005 cos θ = ρ sin(θ + φ), the
  // first to reach 0.05.
  const Vec3 bar_half(0.1, 0.005, 0.005);
  const std::vector<SceneObject> scene{
      box_object(Vec3(0.3, 0.05, 0.1), Vec3(0, 0.1, 0))};  // y in [0.05, 0.15]
  const MeshCcd ccd(box_mesh(bar_half), scene);
  const ScrewMotion motion(pose(Vec3::Zero()), pose(Vec3::Zero(), std::numbers::pi / 2));
  const double rho = std::hypot(0.1, 0.005), phi = std::atan2(0.005, 0.1);
  const double theta = std::asin(0.05 / rho) - phi;
  const double t_contact = theta / (std::numbers::pi / 2);
  const MeshCcdResult r = ccd.first_contact(motion, MeshCcdSettings{});
  REQUIRE(r.contact);
  CHECK(r.toi <= t_contact);
  CHECK(r.toi >= t_contact - 1e-5);
  REQUIRE_FALSE(r.contacts.empty());
  // The first contacts are the corner vertices (0.1, 0.005, ±0.005), vertices
  // 3 and 7, on the wall, whose normal is −y.
  bool corner_found = false;
  for (const MeshCcdContact& c : r.contacts)
    if (c.features.kind == ContactFeatureKind::kToolVertexSceneFace) {
      CHECK((c.features.tool_feature == 3 || c.features.tool_feature == 7));
      CHECK(c.geometry.normal.y() < -1 + 1e-12);
      CHECK(std::abs(c.geometry.gap) < 1e-6);
      corner_found = true;
    }
  CHECK(corner_found);
  // The same wall moved to y = 0.11 is out of the bar's reach (0.100125).
  const std::vector<SceneObject> far_scene{box_object(Vec3(0.3, 0.05, 0.1), Vec3(0, 0.16, 0))};
  CHECK_FALSE(MeshCcd(box_mesh(bar_half), far_scene).first_contact(motion, {}).contact);
}

TEST_CASE("motions that miss report no contact", "[mesh_ccd]") {
  const std::vector<SceneObject> scene{box_object(kSlabHalf, Vec3::Zero())};
  const MeshCcd ccd(box_mesh(kCubeHalf), scene);
  // Sliding across 1e-3 above the face, turning a little: the lowest point
  // of the cube turned by 0.3 rad about z stays at z_c − 0.01.
  const MeshCcdResult above = ccd.first_contact(
      ScrewMotion(pose(Vec3(-0.05, 0, 0.061)), pose(Vec3(0.05, 0.02, 0.061), 0.3)),
      MeshCcdSettings{});
  CHECK_FALSE(above.contact);
  CHECK(above.toi == 1);
  CHECK(above.contacts.empty());
  // Sinking, but stopping 5e-4 short.
  CHECK_FALSE(
      ccd.first_contact(ScrewMotion(pose(Vec3(0, 0, 0.1)), pose(Vec3(0, 0, 0.0605))), {}).contact);
  // Passing beside the box.
  CHECK_FALSE(
      ccd.first_contact(ScrewMotion(pose(Vec3(0.12, 0, 0.1)), pose(Vec3(0.12, 0, -0.1))), {})
          .contact);
}

TEST_CASE("the nearest of several objects is hit first, touching at t = 0 answers 0",
          "[mesh_ccd]") {
  // Object 1's top face (z = 0.03) lies in the path before object 0's
  // (z = −0.05): the cube's bottom reaches z = 0.03 when z_c = 0.04, at
  // t = (0.1 − 0.04) / 0.2 = 0.3.
  const std::vector<SceneObject> scene{box_object(kSlabHalf, Vec3(0, 0, -0.1)),
                                       box_object(Vec3(0.02, 0.02, 0.01), Vec3(0, 0, 0.02))};
  const MeshCcd ccd(box_mesh(kCubeHalf), scene);
  const MeshCcdResult r =
      ccd.first_contact(ScrewMotion(pose(Vec3(0, 0, 0.1)), pose(Vec3(0, 0, -0.1))), {});
  REQUIRE(r.contact);
  CHECK(r.toi <= 0.3);
  CHECK(r.toi >= 0.3 - 1e-5);
  for (const MeshCcdContact& c : r.contacts) CHECK(c.features.scene_object == 1);
  // Resting on the face at the start.
  const MeshCcdResult resting =
      ccd.first_contact(ScrewMotion(pose(Vec3(0, 0, 0.04)), pose(Vec3(0.01, 0, 0.05))), {});
  REQUIRE(resting.contact);
  CHECK(resting.toi == 0);
}

TEST_CASE("a feature pair with an index out of range is rejected naming the index", "[mesh_ccd]") {
  const std::vector<SceneObject> scene{box_object(kSlabHalf, Vec3::Zero())};
  const MeshCcd ccd(box_mesh(kCubeHalf), scene);
  const Pose at_rest = pose(Vec3(0, 0, 0.05));
  const ScrewMotion motion(at_rest, pose(Vec3(0, 0, 0.04)));
  const std::vector<std::pair<ContactFeatures, std::string>> bad = {
      {{ContactFeatureKind::kToolVertexSceneFace, 1, 0, 0}, "no scene object 1"},
      {{ContactFeatureKind::kToolVertexSceneFace, 0, 8, 0}, "index 8 out of range [0, 8)"},
      {{ContactFeatureKind::kSceneVertexToolFace, 0, 0, -1}, "index -1 out of range [0, 8)"},
      {{ContactFeatureKind::kEdgeEdge, 0, 0, 18}, "index 18 out of range [0, 18)"},
  };
  for (const auto& [features, message] : bad) {
    INFO(message);
    CHECK_THROWS_WITH(ccd.evaluate(features, at_rest), Catch::Contains(message));
    CHECK_THROWS_WITH(ccd.closest_points(features, at_rest), Catch::Contains(message));
    // In a batch, after good pairs (enough of them for the vertex cache).
    std::vector<ContactFeatures> pairs(10, {ContactFeatureKind::kToolVertexSceneFace, 0, 0, 0});
    pairs.push_back(features);
    std::vector<FeatureGeometry> geometry;
    CHECK_THROWS_WITH(ccd.evaluate(pairs, at_rest, geometry), Catch::Contains(message));
    std::vector<PairClosestPoints> points;
    CHECK_THROWS_WITH(ccd.closest_points(pairs, at_rest, points), Catch::Contains(message));
    CHECK_THROWS_WITH(ccd.first_contact_among(motion, pairs, {}), Catch::Contains(message));
  }
}

TEST_CASE("bad input and settings are rejected", "[mesh_ccd]") {
  const std::vector<SceneObject> scene{box_object(kSlabHalf, Vec3::Zero())};
  CHECK_THROWS_AS(MeshCcd(TriangleMesh{}, scene), InputError);
  TriangleMesh bad = box_mesh(kCubeHalf);
  bad.vertices[3].x() = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(MeshCcd(bad, scene), Catch::Contains("tool vertex 3"));
  std::vector<SceneObject> bad_scene = scene;
  bad_scene[0].mesh.vertices[5].z() = std::numeric_limits<double>::infinity();
  CHECK_THROWS_AS(MeshCcd(box_mesh(kCubeHalf), bad_scene), InputError);
  bad = box_mesh(kCubeHalf);
  bad.triangles[2][1] = 8;
  CHECK_THROWS_WITH(MeshCcd(bad, scene), Catch::Contains("tool triangle 2"));

  MeshCcdSettings settings;
  CHECK_NOTHROW(validate_mesh_ccd_settings(settings, "params.ccd"));
  settings.contact_window = 1.5;
  CHECK_THROWS_WITH(validate_mesh_ccd_settings(settings, "params.ccd"),
                    Catch::Contains("params.ccd.contact_window"));
  settings = MeshCcdSettings{};
  settings.contact_window = -1e-9;
  CHECK_THROWS_AS(validate_mesh_ccd_settings(settings, "params.ccd"), InputError);
  settings = MeshCcdSettings{};
  settings.primitive.max_evaluations = 0;
  CHECK_THROWS_WITH(validate_mesh_ccd_settings(settings, "params.ccd"),
                    Catch::Contains("params.ccd.primitive.max_evaluations"));

  // A motion with a NaN is answered conservatively: contact at t = 0.
  const MeshCcd ccd(box_mesh(kCubeHalf), scene);
  const MeshCcdResult r = ccd.first_contact(
      ScrewMotion(pose(Vec3(0, 0, std::numeric_limits<double>::quiet_NaN())), pose(Vec3::Zero())),
      {});
  CHECK(r.contact);
  CHECK(r.toi == 0);
  // The tool's radius about its frame: the cube's half diagonal.
  CHECK(ccd.tool_radius() >= std::sqrt(3.0) * 0.01);
  CHECK(ccd.tool_radius() <= std::sqrt(3.0) * 0.01 * (1 + 1e-9));
  CHECK(ccd.memory_bytes() > 0);
  CHECK(ccd.tool_edges().size() == 18);  // 12 box edges and 6 face diagonals
  CHECK(ccd.scene_edges(0).size() == 18);
}

// ---------------------------------------------------------------------------
// evaluate()

TEST_CASE("evaluate: vertex against face and face against vertex", "[mesh_ccd]") {
  const std::vector<SceneObject> scene{box_object(kSlabHalf, Vec3::Zero())};
  const TriangleMesh cube = box_mesh(kCubeHalf);
  const MeshCcd ccd(cube, scene);
  const TriangleMesh& slab = scene[0].mesh;
  // Top face triangles: (4, 5, 7) holds the points with y < x, (4, 7, 6) the others.
  const int lower_right = find_triangle(slab, {4, 5, 7});
  const int upper_left = find_triangle(slab, {4, 7, 6});
  // Cube vertex 0 (−0.01, −0.01, −0.01) with the cube at (0.003, −0.002,
  // 0.07): at (−0.007, −0.012, 0.06), 0.01 above the face, over (4, 5, 7).
  const Pose above = pose(Vec3(0.003, -0.002, 0.07));
  FeatureGeometry g =
      ccd.evaluate({ContactFeatureKind::kToolVertexSceneFace, 0, 0, lower_right}, above);
  CHECK(g.gap == Approx(0.01).margin(1e-15));
  CHECK(g.distance == Approx(0.01).margin(1e-15));
  CHECK((g.normal - Vec3::UnitZ()).norm() < 1e-15);
  CHECK((g.point - Vec3(-0.007, -0.012, 0.05)).norm() < 1e-15);
  // Against the other triangle: the same plane, but the closest point lies on
  // the diagonal y = x, 0.005 / √2 away in the plane.
  g = ccd.evaluate({ContactFeatureKind::kToolVertexSceneFace, 0, 0, upper_left}, above);
  CHECK(g.gap == Approx(0.01).margin(1e-15));
  CHECK(g.distance == Approx(std::sqrt(0.01 * 0.01 + 0.005 * 0.005 / 2)).margin(1e-15));
  CHECK((g.point - Vec3(-0.0095, -0.0095, 0.05)).norm() < 1e-15);
  // Turned by 45° about z the cube's vertex 2 (−0.01, 0.01, −0.01) is at
  // (−0.01√2, 0) from the centre in the plane; with the centre at
  // (0.02, 0.03, 0.055) it is 0.005 below the face's plane, inside.
  g = ccd.evaluate({ContactFeatureKind::kToolVertexSceneFace, 0, 2, upper_left},
                   pose(Vec3(0.02, 0.03, 0.055), std::numbers::pi / 4));
  CHECK(g.gap == Approx(-0.005).margin(1e-15));
  CHECK(g.distance == Approx(0.005).margin(1e-15));
  CHECK((g.point - Vec3(0.02 - 0.01 * std::sqrt(2.0), 0.03, 0.05)).norm() < 1e-15);

  // Scene corner vertex 7 (0.1, 0.1, 0.05) under the cube's bottom face
  // (z = −0.01 in the cube, triangles of vertices 0..3) with the cube at
  // (0.102, 0.097, 0.064): the face is at z = 0.054, 0.004 above the corner.
  const Pose over_corner = pose(Vec3(0.102, 0.097, 0.064));
  for (const std::array<int, 3> t : {std::array<int, 3>{0, 1, 3}, std::array<int, 3>{0, 3, 2}}) {
    const int face = find_triangle(cube, t);
    g = ccd.evaluate({ContactFeatureKind::kSceneVertexToolFace, 0, face, 7}, over_corner);
    CHECK(g.gap == Approx(0.004).margin(1e-15));
    CHECK((g.normal - Vec3::UnitZ()).norm() < 1e-15);
    CHECK(g.point == Vec3(0.1, 0.1, 0.05));
    // The corner lies under triangle (0, 3, 2) (in the cube: (−0.002,
    // 0.003), y > x) and beside (0, 1, 3), whose diagonal is 0.005 / √2 away.
    const double expected = t[1] == 3 ? 0.004 : std::sqrt(0.004 * 0.004 + 0.005 * 0.005 / 2);
    CHECK(g.distance == Approx(expected).margin(1e-15));
  }
}

TEST_CASE("evaluate: edge against edge, crossing, apart and parallel", "[mesh_ccd]") {
  const std::vector<SceneObject> scene{box_object(kSlabHalf, Vec3::Zero())};
  const MeshCcd ccd(box_mesh(kCubeHalf), scene);
  // Tool edge 0–1: along x at y = z = −0.01 in the cube. Scene edge 5–7:
  // along y at x = 0.1, z = 0.05, between the top (+z) and the +x face.
  const int tool_x_edge = find_edge(ccd.tool_edges(), 0, 1);
  const int scene_y_edge = find_edge(ccd.scene_edges(0), 5, 7);
  const ContactFeatures crossing{ContactFeatureKind::kEdgeEdge, 0, tool_x_edge, scene_y_edge};
  // The cube at (0.1, 0.05, 0.063): the tool edge at y = 0.04, z = 0.053,
  // crossing over the scene edge 0.003 above it.
  FeatureGeometry g = ccd.evaluate(crossing, pose(Vec3(0.1, 0.05, 0.063)));
  CHECK(g.gap == Approx(0.003).margin(1e-15));
  CHECK(g.distance == Approx(0.003).margin(1e-15));
  CHECK((g.normal - Vec3::UnitZ()).norm() < 1e-15);  // x × y, towards top + side
  CHECK((g.point - Vec3(0.1, 0.04, 0.05)).norm() < 1e-15);
  // Sunk 0.002 below it: negative gap, same normal.
  g = ccd.evaluate(crossing, pose(Vec3(0.1, 0.05, 0.058)));
  CHECK(g.gap == Approx(-0.002).margin(1e-15));
  CHECK(g.distance == Approx(0.002).margin(1e-15));
  CHECK((g.normal - Vec3::UnitZ()).norm() < 1e-15);
  // Moved along x so the tool edge ends at x = 0.12: the lines are still
  // 0.003 apart, the segments' closest points 0.02 apart along x more.
  g = ccd.evaluate(crossing, pose(Vec3(0.13, 0.05, 0.063)));
  CHECK(g.gap == Approx(0.003).margin(1e-15));
  CHECK(g.distance == Approx(std::hypot(0.02, 0.003)).margin(1e-15));
  CHECK((g.point - Vec3(0.1, 0.04, 0.05)).norm() < 1e-15);

  // Parallel: tool edge 1–3 (along y at x = 0.01, z = −0.01 in the cube)
  // with the cube at (0.095, 0, 0.063) lies at x = 0.105, z = 0.053, offset
  // (0.005, 0, 0.003) from the scene edge's line.
  const int tool_y_edge = find_edge(ccd.tool_edges(), 1, 3);
  const ContactFeatures parallel{ContactFeatureKind::kEdgeEdge, 0, tool_y_edge, scene_y_edge};
  g = ccd.evaluate(parallel, pose(Vec3(0.095, 0, 0.063)));
  CHECK(g.normal.allFinite());
  CHECK((g.normal - Vec3(0.005, 0, 0.003).normalized()).norm() < 1e-12);
  CHECK(g.gap == Approx(std::hypot(0.005, 0.003)).margin(1e-15));
  CHECK(g.distance == Approx(std::hypot(0.005, 0.003)).margin(1e-15));
  // On the same line: the normal is the adjacent faces' (1, 0, 1)/√2.
  g = ccd.evaluate(parallel, pose(Vec3(0.09, 0, 0.06)));
  CHECK(g.normal.allFinite());
  CHECK((g.normal - Vec3(1, 0, 1).normalized()).norm() < 1e-12);
  CHECK(std::abs(g.gap) < 1e-15);
  CHECK(g.distance < 1e-15);
}

// ---------------------------------------------------------------------------
// Real models against CGAL

const std::string kModels = std::string(HAPTICBENCH_SOURCE_DIR) + "/models/";

TriangleMesh model(const std::string& file, double scale) {
  const std::string path = kModels + file;
  if (!std::filesystem::exists(path))
    FAIL(path << " is missing: run scripts/extract-models (CMake's configure step runs it)");
  return read_mesh_file(path, scale);
}

Quat random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Quat q(normal(rng), normal(rng), normal(rng), normal(rng));
  return q.normalized();
}

Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  return Vec3(normal(rng), normal(rng), normal(rng)).normalized();
}

// As scenarios/meshes/armadillo_on_bunny.json scales them: a 5 cm armadillo
// (frame at its centre of mass) and a 20 cm bunny, with CGAL's exact
// intersection test.
struct ArmadilloOnBunny {
  TriangleMesh tool = centred(model("armadillo.off", 3.305e-4));
  SceneObject bunny = bunny_object();
  MeshCcd ccd{tool, std::vector<SceneObject>{bunny}};
  test::CgalMeshIntersection cgal{bunny.mesh};

  static TriangleMesh centred(TriangleMesh mesh) {
    const Vec3 com = mass_properties_from_density(mesh, 1000).centre_of_mass;
    for (Vec3& v : mesh.vertices) v -= com;
    return mesh;
  }
  static SceneObject bunny_object() {
    SceneObject object;
    object.name = "bunny00.off";
    object.mesh = model("bunny00.off", 0.2);
    return object;
  }

  /// The tool at a random orientation, sunk a random depth in [depth_lo,
  /// depth_hi] (m) past the tangent plane at a random point of the bunny;
  /// `normal` gets the plane's normal.
  Pose sunk(std::mt19937& rng, double depth_lo, double depth_hi, Vec3& normal) const {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const auto& tri = bunny.mesh.triangles[std::uniform_int_distribution<std::size_t>(
        0, bunny.mesh.triangles.size() - 1)(rng)];
    double u = unit(rng), v = unit(rng);
    if (u + v > 1) u = 1 - u, v = 1 - v;
    const Vec3 &a = bunny.mesh.vertices[tri[0]], &b = bunny.mesh.vertices[tri[1]],
               &c = bunny.mesh.vertices[tri[2]];
    normal = (b - a).cross(c - a).normalized();
    const Quat rotation = random_rotation(rng);
    double extent = 0;  // the tool's extent along −normal from its frame
    for (const Vec3& p : tool.vertices) extent = std::max(extent, -normal.dot(rotation * p));
    const double depth = depth_lo + (depth_hi - depth_lo) * unit(rng);
    return Pose{a + u * (b - a) + v * (c - a) + (extent - depth) * normal, rotation};
  }

  /// Ranges of a random motion onto the bunny (m, rad).
  struct MotionRanges {
    double depth_lo, depth_hi;  ///< the end, sunk past the tangent plane (sunk())
    double back_lo, back_hi;    ///< the start's distance from the end
    double spread;              ///< weight of a random unit vector added to the normal
    double turn;                ///< largest turn from the end's orientation
  };

  /// A motion with the ranges; false (try again) unless it heads away from
  /// the surface, its start is free and its end intersects (CGAL).
  bool random_motion(std::mt19937& rng, const MotionRanges& ranges, Pose& start, Pose& end) const {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    Vec3 normal;
    end = sunk(rng, ranges.depth_lo, ranges.depth_hi, normal);
    const Vec3 away = (normal + ranges.spread * random_unit(rng)).normalized();
    if (away.dot(normal) < 0.2) return false;
    start.p = end.p + (ranges.back_lo + (ranges.back_hi - ranges.back_lo) * unit(rng)) * away;
    start.q =
        (end.q * Quat(Eigen::AngleAxisd(ranges.turn * unit(rng), random_unit(rng)))).normalized();
    return !cgal.intersects(tool, start) && cgal.intersects(tool, end);
  }

  /// CGAL finds no intersection at 20 times before `toi` and, unless a
  /// kernel answered by its budget (a conservative, earlier time), one
  /// within 1e-3 after it.
  void check_first_contact(const ScrewMotion& motion, double toi, bool budget_exhausted) const {
    for (int k = 0; k < 20; ++k) {
      const double t = toi * k / 20.0;
      INFO("t " << t);
      CHECK_FALSE(cgal.intersects(tool, pose_at(motion, t)));
    }
    if (budget_exhausted) return;
    bool intersects_soon = false;
    for (int k = 1; k <= 4 && !intersects_soon; ++k)
      intersects_soon = cgal.intersects(tool, pose_at(motion, std::min(1.0, toi + 2.5e-4 * k)));
    CHECK(intersects_soon);
  }
};

TEST_CASE("armadillo onto bunny: no intersection before the toi, intersection just after",
          "[mesh_ccd][cgal]") {
  const ArmadilloOnBunny s;
  std::mt19937 rng(20240611);
  constexpr int kMotions = 16;
  int accepted = 0;
  for (int attempt = 0; attempt < 200 && accepted < kMotions; ++attempt) {
    // End pose: sunk 0.2–2 mm; start: 5–30 mm away, mostly along the
    // normal, turned by up to 0.4 rad.
    Pose start, end;
    if (!s.random_motion(rng, {2e-4, 2e-3, 0.005, 0.03, 0.6, 0.4}, start, end)) continue;
    ++accepted;

    const ScrewMotion motion(start, end);
    const MeshCcdResult r = s.ccd.first_contact(motion, MeshCcdSettings{});
    INFO("motion " << accepted << " toi " << r.toi);
    REQUIRE(r.contact);
    REQUIRE_FALSE(r.contacts.empty());
    s.check_first_contact(motion, r.toi, r.budget_exhausted);
    // The first pair is (nearly) touching at the toi: no point of the tool
    // moves more than `speed` per unit of t.
    const double speed = (end.p - start.p).norm() + motion.angle() * s.ccd.tool_radius();
    if (!r.budget_exhausted) CHECK(r.contacts.front().geometry.distance <= 1e-4 * speed);
  }
  CHECK(accepted == kMotions);
}

TEST_CASE("the kernels of a proximity query's pairs find what the whole search finds",
          "[mesh_ccd][cgal]") {
  // Short motions (the god-object's slow-loop moves) of the armadillo onto
  // the bunny: every pair that can meet during a motion whose points move at
  // most `reach` is within `reach` at its start, so the pairs a proximity
  // query lists within that distance hold the first contact.
  const ArmadilloOnBunny s;
  std::mt19937 rng(77);
  constexpr int kMotions = 12;
  int accepted = 0;
  for (int attempt = 0; attempt < 300 && accepted < kMotions; ++attempt) {
    // End: sunk 20–200 µm; start: 0.1–0.5 mm back, turned by up to 5 mrad.
    Pose start, end;
    if (!s.random_motion(rng, {2e-5, 2e-4, 1e-4, 5e-4, 0.5, 5e-3}, start, end)) continue;
    ++accepted;
    const ScrewMotion motion(start, end);
    const double reach = (end.p - start.p).norm() + motion.angle() * s.ccd.tool_radius();
    const ProximityResult near = s.ccd.proximity(start, 1.01 * reach, 100000);
    std::vector<ContactFeatures> pairs;
    for (const ProximityPair& pair : near.pairs) pairs.push_back(pair.features);

    const MeshCcdResult among = s.ccd.first_contact_among(motion, pairs, MeshCcdSettings{});
    const MeshCcdResult whole = s.ccd.first_contact(motion, MeshCcdSettings{});
    INFO("motion " << accepted << ": " << pairs.size() << " pairs, toi " << among.toi
                   << ", whole search " << whole.toi);
    REQUIRE(among.contact);
    REQUIRE_FALSE(among.contacts.empty());
    CHECK(among.bv_tests == 0);
    CHECK(among.primitive_queries == static_cast<int64_t>(pairs.size()));
    CHECK(among.toi == Approx(whole.toi).margin(2e-6));
    s.check_first_contact(motion, among.toi, among.budget_exhausted);
    // Without the pairs there is nothing to hit.
    CHECK_FALSE(s.ccd.first_contact_among(motion, {}, MeshCcdSettings{}).contact);
  }
  CHECK(accepted == kMotions);
}

}  // namespace
}  // namespace hb
