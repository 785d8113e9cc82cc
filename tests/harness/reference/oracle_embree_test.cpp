// Checks of the Embree oracle against closed forms: the exact box distance
// and closest point, the exact sphere (outside its mesh's tessellation gap),
// the known resting depth of a box tool on a slab, the refusal of an open
// mesh, a closest-point search bounded by max_distance, and an
// independent brute-force ray-parity count on a real model.
// Units m; quaternions (qw,qx,qy,qz).
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "hapticbench/input_error.h"
#include "hapticbench/shapes.h"
#include "harness/mesh_io/mesh_io.h"
#include "harness/reference/oracle.h"
#include "tests/support/shape_fixtures.h"

namespace hb {
namespace {

using test::box_shape;
using test::sphere_shape;

SceneObject shape_object(const std::string& name, const Shape& shape, const Pose& pose) {
  SceneObject object;
  object.name = name;
  object.shape = shape;
  object.mesh = shape_mesh(shape);
  object.pose = pose;
  return object;
}

Pose make_pose(const Vec3& p, double angle, const Vec3& axis) {
  Pose pose;
  pose.p = p;
  pose.q = Quat(Eigen::AngleAxisd(angle, axis.normalized()));
  return pose;
}

PointQueryResult query_every_point(const Oracle& oracle, const std::vector<Vec3>& points) {
  PointQueryResult result;
  oracle.query_points({.points = points, .want_inside = true, .want_closest = true}, result);
  return result;
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// The oracle's first parity-ray direction (oracle_embree.cpp), rounded to
// float as the oracle rounds it: points placed on a line along it through
// a mesh vertex or edge send that ray exactly through the vertex or edge.
Vec3 first_parity_direction() {
  return Vec3(0.5377, 0.6189, 0.5723).normalized().cast<float>().cast<double>();
}

const Pose kCubePose = make_pose(Vec3(0.3, -0.2, 0.5), 0.7, Vec3(1, 2, 3));
const Shape kUnitCube = box_shape(Vec3(1, 1, 1));

TEST_CASE("a closest-point search stops at max_distance and answers it as a lower bound") {
  // The unit cube (turned and moved): points 0.3 m and 2 m off its +x face.
  const auto oracle = make_embree_oracle({shape_object("cube", kUnitCube, kCubePose)});
  const std::vector<Vec3> points = {kCubePose.transform_point(Vec3(0.8, 0.1, -0.2)),
                                    kCubePose.transform_point(Vec3(2.5, 0.1, -0.2))};
  PointQueryResult result;
  oracle->query_points(
      {.points = points, .want_inside = false, .want_closest = true, .max_distance = 1.0}, result);
  REQUIRE(result.distance.size() == 2);
  CHECK(result.distance[0] == Approx(0.3).epsilon(1e-12));  // within: exact
  CHECK(result.object[0] == 0);
  CHECK(result.distance[1] == 1.0);  // beyond: the bound, no point
  CHECK(result.object[1] == -1);
  CHECK(std::isnan(result.closest[1].x()));
  oracle->query_points({.points = points, .want_inside = false, .want_closest = true}, result);
  CHECK(result.distance[1] == Approx(2.0).epsilon(1e-12));
}

TEST_CASE("unit cube: inside and outside, also 1e-6 off every face") {
  const auto oracle = make_embree_oracle({shape_object("cube", kUnitCube, kCubePose)});
  REQUIRE(oracle->name() == "embree");
  std::vector<Vec3> local;   // cube frame
  std::vector<bool> inside;  // expected
  const std::array<double, 4> grid = {-0.4, -0.1, 0.2, 0.45};
  for (double x : grid)
    for (double y : grid)
      for (double z : grid) {
        local.emplace_back(x, y, z);
        inside.push_back(true);
        local.emplace_back(x + 1.2, y, z);  // beside the cube
        inside.push_back(false);
        local.emplace_back(x, y - 0.9, z + 1.05);
        inside.push_back(false);
      }
  for (int axis = 0; axis < 3; ++axis)
    for (double side : {-1.0, 1.0}) {
      Vec3 on_face(0.13, -0.27, 0.31);
      on_face[axis] = 0.5 * side;
      for (double offset : {-1e-6, 1e-6}) {
        local.push_back(on_face + offset * side * Vec3::Unit(axis));
        inside.push_back(offset < 0);
      }
    }
  // Just inside an edge and a corner, and just outside them.
  for (double offset : {-1e-6, 1e-6}) {
    local.emplace_back(0.5 + offset, -0.5 - offset, 0.2);
    inside.push_back(offset < 0);
    local.emplace_back(-0.5 - offset, 0.5 + offset, 0.5 + offset);
    inside.push_back(offset < 0);
  }

  std::vector<Vec3> world;
  for (const Vec3& p : local) world.push_back(kCubePose.transform_point(p));
  const PointQueryResult result = query_every_point(*oracle, world);
  REQUIRE(result.inside.size() == world.size());
  for (std::size_t i = 0; i < world.size(); ++i) {
    INFO("cube-frame point " << local[i].transpose());
    CHECK(static_cast<bool>(result.inside[i]) == inside[i]);
  }
}

TEST_CASE("unit cube: closest point, distance and normal equal the exact box's") {
  const auto oracle = make_embree_oracle({shape_object("cube", kUnitCube, kCubePose)});
  // Outside in a face region, an edge region and a corner region, at
  // distances from 1e-6 to 0.3 m: the nearest point is unique.
  std::vector<Vec3> local;
  for (double h : {1e-6, 1e-3, 0.05, 0.3}) {
    local.emplace_back(0.2, -0.1, 0.5 + h);                      // face +z
    local.emplace_back(-0.5 - h, 0.33, -0.41);                   // face -x
    local.emplace_back(0.5 + h, 0.5 + 0.7 * h, 0.1);             // edge +x +y
    local.emplace_back(-0.2, -0.5 - h, -0.5 - 2 * h);            // edge -y -z
    local.emplace_back(0.5 + h, -0.5 - 0.5 * h, 0.5 + 1.5 * h);  // corner
    local.emplace_back(-0.5 - h, -0.5 - h, -0.5 - h);            // corner
  }
  std::vector<Vec3> world;
  for (const Vec3& p : local) world.push_back(kCubePose.transform_point(p));
  const PointQueryResult result = query_every_point(*oracle, world);
  REQUIRE(result.distance.size() == world.size());
  for (std::size_t i = 0; i < world.size(); ++i) {
    INFO("cube-frame point " << local[i].transpose());
    const SurfacePoint exact = shape_closest_surface_point(kUnitCube, local[i]);
    CHECK(result.inside[i] == 0);
    CHECK(std::abs(result.distance[i] - shape_signed_distance(kUnitCube, local[i])) < 1e-12);
    CHECK((result.closest[i] - kCubePose.transform_point(exact.point)).norm() < 1e-12);
    CHECK(result.object[i] == 0);
    // The normal is the outward normal of a face adjacent to the nearest
    // point, i.e. a unit axis of the cube whose face plane the point lies
    // beyond.
    const Vec3 normal_local = kCubePose.q.conjugate() * result.normal[i];
    Eigen::Index axis = 0;
    normal_local.cwiseAbs().maxCoeff(&axis);
    CHECK(std::abs(std::abs(normal_local[axis]) - 1) < 1e-12);
    CHECK(normal_local[axis] * local[i][axis] > 0.5);
    const int outside_axes = (local[i].cwiseAbs().array() > 0.5).count();
    if (outside_axes == 1) {  // face region: the normal is the direction to the point
      CHECK((result.normal[i] - (world[i] - result.closest[i]).normalized()).norm() < 1e-6);
    }
  }

  // Inside, the distance is to the nearest face (several may tie).
  std::vector<Vec3> inside_local = {
      {0.1, 0.2, -0.3}, {0.45, 0.0, 0.0}, {0.49, -0.49, 0.3}, {-0.1, -0.2, -0.4999}, {0, 0, 0}};
  std::vector<Vec3> inside_world;
  for (const Vec3& p : inside_local) inside_world.push_back(kCubePose.transform_point(p));
  const PointQueryResult inner = query_every_point(*oracle, inside_world);
  for (std::size_t i = 0; i < inside_world.size(); ++i) {
    INFO("cube-frame point " << inside_local[i].transpose());
    CHECK(inner.inside[i] == 1);
    CHECK(std::abs(inner.distance[i] + shape_signed_distance(kUnitCube, inside_local[i])) < 1e-12);
    const Vec3 closest_local = kCubePose.inverse_transform_point(inner.closest[i]);
    CHECK(std::abs(shape_signed_distance(kUnitCube, closest_local)) < 1e-12);
    CHECK(std::abs((inner.closest[i] - inside_world[i]).norm() - inner.distance[i]) < 1e-12);
  }
}

TEST_CASE("two objects: the nearest object's index, point and inside flag") {
  const Shape small_box = box_shape(Vec3(0.2, 0.1, 0.4));
  const Pose small_pose = make_pose(Vec3(-1.0, 0.4, 0.2), -0.4, Vec3(0, 1, 1));
  const auto oracle = make_embree_oracle(
      {shape_object("cube", kUnitCube, kCubePose), shape_object("small", small_box, small_pose)});
  std::vector<Vec3> world;
  std::vector<int> expected_object;
  std::vector<Vec3> expected_closest;
  std::vector<bool> expected_inside;
  auto add = [&](int object, const Shape& shape, const Pose& pose, const Vec3& local) {
    world.push_back(pose.transform_point(local));
    expected_object.push_back(object);
    expected_closest.push_back(
        pose.transform_point(shape_closest_surface_point(shape, local).point));
    expected_inside.push_back(shape_signed_distance(shape, local) < 0);
  };
  add(0, kUnitCube, kCubePose, Vec3(0.1, 0.6, -0.2));
  add(0, kUnitCube, kCubePose, Vec3(0.55, 0.52, 0.51));
  add(1, small_box, small_pose, Vec3(0.12, 0.0, 0.1));
  add(1, small_box, small_pose, Vec3(-0.11, 0.06, 0.21));
  add(1, small_box, small_pose, Vec3(0.05, 0.01, -0.15));  // inside
  add(0, kUnitCube, kCubePose, Vec3(0.3, 0.3, 0.2));       // inside
  const PointQueryResult result = query_every_point(*oracle, world);
  for (std::size_t i = 0; i < world.size(); ++i) {
    INFO("point " << i);
    CHECK(result.object[i] == expected_object[i]);
    CHECK(static_cast<bool>(result.inside[i]) == expected_inside[i]);
    if (!expected_inside[i]) CHECK((result.closest[i] - expected_closest[i]).norm() < 1e-12);
  }
  Eigen::AlignedBox3d expected_bounds = transformed(shape_mesh(kUnitCube), kCubePose).bounds();
  expected_bounds.extend(transformed(shape_mesh(small_box), small_pose).bounds());
  CHECK((oracle->bounds().min() - expected_bounds.min()).norm() < 1e-15);
  CHECK((oracle->bounds().max() - expected_bounds.max()).norm() < 1e-15);
  CHECK(oracle->distance_only_objects().empty());
}

// Sphere mesh: inscribed, star-shaped about its centre. Points nearer the
// centre than every face plane are inside it, points farther than the
// radius are outside; between is the tessellation gap, where the exact
// sphere says nothing about the mesh.
struct SphereScene {
  Shape shape = sphere_shape(0.05, 3);
  Pose pose = make_pose(Vec3(-0.2, 0.1, 0.3), 1.1, Vec3(-1, 0.5, 2));
  TriangleMesh world = transformed(shape_mesh(shape), pose);
  double inradius = std::numeric_limits<double>::infinity();
  SphereScene() {
    for (std::size_t t = 0; t < world.triangles.size(); ++t) {
      const Vec3& a = world.vertices[world.triangles[t][0]];
      inradius = std::min(inradius, std::abs(world.face_normal(t).dot(a - pose.p)));
    }
  }
  /// 1 inside, 0 outside, -1 in the tessellation gap.
  int expected(const Vec3& p) const {
    const double r = (p - pose.p).norm();
    if (r < inradius - 1e-9) return 1;
    if (r > shape.radius + 1e-9) return 0;
    return -1;
  }
};

TEST_CASE("icosphere: inside/outside agrees with the exact sphere outside the gap") {
  const SphereScene sphere;
  REQUIRE(sphere.inradius > 0.95 * sphere.shape.radius);
  const auto oracle = make_embree_oracle({shape_object("ball", sphere.shape, sphere.pose)});
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> coordinate(-1.3 * sphere.shape.radius,
                                                    1.3 * sphere.shape.radius);
  std::vector<Vec3> points;
  for (int i = 0; i < 5000; ++i)
    points.push_back(sphere.pose.p +
                     Vec3(coordinate(random), coordinate(random), coordinate(random)));
  PointQueryResult result;
  oracle->query_points({.points = points}, result);
  CHECK(result.distance.empty());  // not asked for
  int checked = 0;
  int inside = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int expected = sphere.expected(points[i]);
    if (expected < 0) continue;
    ++checked;
    inside += expected;
    INFO("point " << points[i].transpose());
    CHECK(result.inside[i] == expected);
  }
  CHECK(checked > 4500);
  CHECK(inside > 1000);
}

TEST_CASE("icosphere: rays exactly through vertices and edges still classify right") {
  const SphereScene sphere;
  const auto oracle = make_embree_oracle({shape_object("ball", sphere.shape, sphere.pose)});
  const double radius = sphere.shape.radius;
  const Vec3 ray = first_parity_direction();

  // Targets on the mesh: every vertex and every edge midpoint.
  std::vector<Vec3> targets = sphere.world.vertices;
  for (const auto& [a, b, c] : sphere.world.triangles) {
    if (a < b) targets.push_back(0.5 * (sphere.world.vertices[a] + sphere.world.vertices[b]));
    if (b < c) targets.push_back(0.5 * (sphere.world.vertices[b] + sphere.world.vertices[c]));
    if (c < a) targets.push_back(0.5 * (sphere.world.vertices[c] + sphere.world.vertices[a]));
  }
  std::vector<Vec3> points;
  for (const Vec3& target : targets) {
    // Upstream along the first ray: that ray passes exactly through the target.
    for (double t : {0.02, 0.3, 1.1, 2.5}) points.push_back(target - t * radius * ray);
    // On the line from the centre through the target.
    for (double s : {0.5, 0.9, 1.1, 2.0})
      points.push_back(sphere.pose.p + s * (target - sphere.pose.p));
  }
  PointQueryResult result;
  oracle->query_points({.points = points}, result);
  int checked = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int expected = sphere.expected(points[i]);
    if (expected < 0) continue;
    ++checked;
    INFO("point " << points[i].transpose());
    CHECK(result.inside[i] == expected);
  }
  CHECK(checked > static_cast<int>(points.size()) / 2);
}

// Tool surface samples: the mesh vertices plus a grid on each face of the
// box (tool frame).
std::vector<Vec3> box_surface_grid(const Vec3& size, int per_edge) {
  std::vector<Vec3> points;
  const Vec3 half = 0.5 * size;
  for (int axis = 0; axis < 3; ++axis)
    for (double side : {-1.0, 1.0})
      for (int i = 0; i < per_edge; ++i)
        for (int j = 0; j < per_edge; ++j) {
          Vec3 p;
          p[axis] = side * half[axis];
          const int u = (axis + 1) % 3;
          const int v = (axis + 2) % 3;
          p[u] = -half[u] + size[u] * i / (per_edge - 1);
          p[v] = -half[v] + size[v] * j / (per_edge - 1);
          points.push_back(p);
        }
  return points;
}

TEST_CASE("box tool resting in a slab: penetration depth is the known depth") {
  // Slab top face at z = 0, 0.4 m wide: every tool point below z = 0 is
  // inside at depth -z (its nearest slab face is the top one).
  const auto oracle = make_embree_oracle({shape_object(
      "slab", box_shape(Vec3(0.4, 0.4, 0.02)), make_pose(Vec3(0, 0, -0.01), 0, Vec3::UnitZ()))});
  const Vec3 tool_size(0.04, 0.04, 0.04);
  const std::vector<Vec3> samples = box_surface_grid(tool_size, 5);
  const double depth = 0.0031;

  SECTION("face down") {
    const Pose tool_pose = make_pose(Vec3(0.013, -0.021, 0.02 - depth), 0, Vec3::UnitZ());
    std::vector<Vec3> world;
    int64_t below = 0;
    for (const Vec3& p : samples) {
      world.push_back(tool_pose.transform_point(p));
      below += world.back().z() < 0 ? 1 : 0;
    }
    const PenetrationResult result = oracle->penetration(world);
    CHECK(result.points == static_cast<int64_t>(samples.size()));
    CHECK(result.inside == below);
    CHECK(below >= 25);
    CHECK(std::abs(result.max_depth_m - depth) < 1e-9);
    CHECK(std::abs(result.rms_depth_m - depth) < 1e-9);  // every inside point is on the bottom
  }
  SECTION("tilted: the deepest point is a corner") {
    const double tilt = 0.3;
    const double centre_z = -depth + 0.02 * (std::sin(tilt) + std::cos(tilt));
    const Pose tool_pose = make_pose(Vec3(-0.05, 0.02, centre_z), tilt, Vec3::UnitY());
    std::vector<Vec3> world;
    double lowest = 0;
    for (const Vec3& p : samples) {
      world.push_back(tool_pose.transform_point(p));
      lowest = std::min(lowest, world.back().z());
    }
    REQUIRE(std::abs(lowest + depth) < 1e-12);  // the pose is what the closed form says
    const PenetrationResult result = oracle->penetration(world);
    CHECK(result.inside >= 2);  // the bottom edge's samples
    CHECK(std::abs(result.max_depth_m - depth) < 1e-9);
  }
  SECTION("sampled sphere tool: the lowest sample sets the depth") {
    const Shape ball = sphere_shape(0.02, 3);
    const Pose tool_pose = make_pose(Vec3(0.1, 0.05, 0.02 - depth), 0.4, Vec3(1, 1, 0));
    std::vector<Vec3> world;
    double sum_sq = 0;
    int64_t below = 0;
    double lowest = 0;
    for (const Vec3& p : shape_mesh(ball).vertices) {
      world.push_back(tool_pose.transform_point(p));
      const double z = world.back().z();
      if (z < 0) {
        ++below;
        sum_sq += z * z;
      }
      lowest = std::min(lowest, z);
    }
    const PenetrationResult result = oracle->penetration(world);
    CHECK(result.inside == below);
    CHECK(std::abs(result.max_depth_m + lowest) < 1e-12);
    CHECK(std::abs(result.rms_depth_m - std::sqrt(sum_sq / static_cast<double>(below))) < 1e-12);
  }
}

TEST_CASE("open mesh: refused for inside/outside, accepted for distances only") {
  SceneObject open_cube = shape_object("open_cube", kUnitCube, kCubePose);
  // The box mesh ends with its +z face (two triangles): drop it.
  open_cube.mesh.triangles.resize(open_cube.mesh.triangles.size() - 2);
  const SceneObject closed =
      shape_object("closed", kUnitCube, make_pose(Vec3(3, 0, 0), 0, Vec3::UnitZ()));

  try {
    make_embree_oracle({closed, open_cube});
    FAIL("an open mesh was accepted for inside/outside");
  } catch (const InputError& error) {
    const std::string what = error.what();
    INFO(what);
    CHECK(what.find("open_cube") != std::string::npos);
    CHECK(lower(error.message()).find("open") != std::string::npos);
    CHECK(error.location() == "/scene/1");
    CHECK(what.find("distance_only") != std::string::npos);
  }

  open_cube.distance_only = true;
  const auto oracle = make_embree_oracle({closed, open_cube});
  REQUIRE(oracle->distance_only_objects() == std::vector<std::string>{"open_cube"});
  const std::vector<Vec3> local = {Vec3(0, 0, 0), Vec3(0, 0, 0.4), Vec3(0.2, -0.1, -0.3)};
  std::vector<Vec3> world;
  for (const Vec3& p : local) world.push_back(kCubePose.transform_point(p));
  world.push_back(Vec3(3.1, 0.2, -0.3));  // inside the closed cube
  const PointQueryResult result = query_every_point(*oracle, world);
  CHECK(result.inside[0] == 0);
  CHECK(result.inside[1] == 0);
  CHECK(result.inside[2] == 0);
  CHECK(result.inside[3] == 1);
  CHECK(std::abs(result.distance[0] - 0.5) < 1e-12);
  // Below the missing face, the nearest triangles are the side walls.
  CHECK(std::abs(result.distance[1] - 0.5) < 1e-12);
  CHECK(std::abs(result.distance[2] - 0.2) < 1e-12);  // to the -z face
  CHECK(result.object[0] == 1);
  CHECK(result.object[3] == 0);
  CHECK(std::abs(result.distance[3] - 0.2) < 1e-12);
  CHECK_FALSE(oracle->intersection_volume(shape_mesh(kUnitCube)).has_value());
}

// Independent parity: rays along +x, +y and +z, every crossing found by a
// double-precision Moller-Trumbore test; majority of the three.
class BruteForceParity {
 public:
  explicit BruteForceParity(const TriangleMesh& mesh) : mesh_(mesh), bounds_(mesh.bounds()) {
    // Per ray axis, a grid over the other two coordinates listing the
    // triangles whose bounds overlap each cell: only those can meet a ray
    // along that axis from a point in the cell. The crossing test itself is
    // the plain one.
    for (int axis = 0; axis < 3; ++axis) {
      columns_[axis].resize(kCells * kCells);
      for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        Eigen::AlignedBox3d box;
        for (int corner : mesh.triangles[t]) box.extend(mesh.vertices[corner]);
        const auto [u0, v0] = cell(axis, box.min());
        const auto [u1, v1] = cell(axis, box.max());
        for (int u = u0; u <= u1; ++u)
          for (int v = v0; v <= v1; ++v) columns_[axis][u * kCells + v].push_back(t);
      }
    }
  }

  bool inside(const Vec3& p) const {
    int votes = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const auto [u, v] = cell(axis, p);
      int crossings = 0;
      for (std::size_t t : columns_[axis][u * kCells + v])
        crossings += crosses(p, Vec3::Unit(axis), t) ? 1 : 0;
      votes += crossings % 2;
    }
    return votes >= 2;
  }

 private:
  static constexpr int kCells = 64;

  std::pair<int, int> cell(int axis, const Vec3& p) const {
    const int u = (axis + 1) % 3;
    const int v = (axis + 2) % 3;
    auto index = [&](int k) {
      const double f = (p[k] - bounds_.min()[k]) / (bounds_.max()[k] - bounds_.min()[k]);
      return std::clamp(static_cast<int>(f * kCells), 0, kCells - 1);
    };
    return {index(u), index(v)};
  }

  bool crosses(const Vec3& origin, const Vec3& direction, std::size_t t) const {
    const Vec3& a = mesh_.vertices[mesh_.triangles[t][0]];
    const Vec3 e1 = mesh_.vertices[mesh_.triangles[t][1]] - a;
    const Vec3 e2 = mesh_.vertices[mesh_.triangles[t][2]] - a;
    const Vec3 p = direction.cross(e2);
    const double det = e1.dot(p);
    if (det == 0) return false;
    const Vec3 s = origin - a;
    const double u = s.dot(p) / det;
    if (u < 0 || u > 1) return false;
    const Vec3 q = s.cross(e1);
    const double v = direction.dot(q) / det;
    if (v < 0 || u + v > 1) return false;
    return e2.dot(q) / det > 0;
  }

  const TriangleMesh& mesh_;
  Eigen::AlignedBox3d bounds_;
  std::array<std::vector<std::vector<std::size_t>>, 3> columns_;
};

TEST_CASE("bunny: inside/outside agrees with a brute-force parity count") {
  const std::string path = HAPTICBENCH_SOURCE_DIR "/models/bunny00.off";
  if (!std::filesystem::exists(path)) {
    WARN("skipped: " << path << " is missing");
    return;
  }
  SceneObject bunny;
  bunny.name = "bunny00.off";
  bunny.mesh = read_mesh_file(path);
  const auto oracle = make_embree_oracle({bunny});
  const BruteForceParity brute_force(bunny.mesh);

  const Eigen::AlignedBox3d box = bunny.mesh.bounds();
  std::mt19937_64 random(11);
  std::vector<Vec3> points;
  for (int i = 0; i < 10000; ++i) {
    Vec3 p;
    for (int k = 0; k < 3; ++k)
      p[k] = std::uniform_real_distribution<double>(box.min()[k], box.max()[k])(random);
    points.push_back(p);
  }
  PointQueryResult result;
  oracle->query_points({.points = points}, result);
  int disagreements = 0;
  int inside = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const bool expected = brute_force.inside(points[i]);
    inside += expected ? 1 : 0;
    if (static_cast<bool>(result.inside[i]) != expected) {
      ++disagreements;
      UNSCOPED_INFO("disagrees at " << points[i].transpose());
    }
  }
  CHECK(disagreements == 0);
  CHECK(inside > 1000);  // the bunny fills a good part of its box
}

}  // namespace
}  // namespace hb
