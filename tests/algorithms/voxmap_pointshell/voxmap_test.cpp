// The scene voxmap and the pointshell (algorithms/voxmap_pointshell/
// voxmap.cpp) against ground truth: voxel states against CGAL's exact
// inside/outside and distances on a real mesh, against the closed-form
// signed distance of a box, the pointshell against a sphere's closed form,
// and the on-disk cache. Units m.
#include "algorithms/voxmap_pointshell/voxmap.h"

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "hapticbench/shapes.h"
#include "harness/mesh_io/mesh_io.h"
#include "harness/reference/oracle.h"
#include "tests/support/scratch_dir.h"

namespace hb {
namespace {

const double kSqrt3 = std::sqrt(3.0);

CacheSettings uncached() { return CacheSettings{false, {}}; }

SceneObject bunny_object() {
  const std::string path = std::string(HAPTICBENCH_SOURCE_DIR) + "/models/bunny00.off";
  if (!std::filesystem::exists(path))
    FAIL(path << " is missing: run scripts/extract-models (CMake's configure step runs it)");
  SceneObject object;
  object.name = "bunny00.off";
  object.mesh = read_mesh_file(path, 0.1);
  object.pose = Pose{Vec3(0.01, -0.02, 0.005), quat_from_rotation_vector(Vec3(0.3, -0.5, 0.2))};
  object.content_hash = "bunny00 test";
  return object;
}

SceneObject box_object(const Vec3& size, const Pose& pose) {
  SceneObject object;
  object.name = "box";
  Shape shape;
  shape.type = ShapeType::kBox;
  shape.size = size;
  object.shape = shape;
  object.mesh = shape_mesh(shape);
  object.pose = pose;
  object.content_hash = "box test";
  return object;
}

Eigen::AlignedBox3d grown(const Eigen::AlignedBox3d& box, double margin) {
  return Eigen::AlignedBox3d(box.min().array() - margin, box.max().array() + margin);
}

Eigen::AlignedBox3d world_bounds(const SceneObject& object) {
  Eigen::AlignedBox3d box;
  for (const Vec3& v : object.mesh.vertices) box.extend(object.pose.transform_point(v));
  return box;
}

TEST_CASE("voxmap states agree with CGAL's inside/outside except within one voxel of the surface",
          "[voxmap_pointshell]") {
  const std::vector<SceneObject> scene{bunny_object()};
  const std::unique_ptr<Oracle> cgal = make_cgal_oracle(scene);
  const Eigen::AlignedBox3d bounds = world_bounds(scene[0]);
  for (const double h : {0.002, 0.001}) {
    VoxmapSettings settings;
    settings.voxel_size_m = h;
    settings.proximity_layers = 2;
    const SceneVoxmap voxmap = build_scene_voxmap(scene, grown(bounds, 0.01), settings, uncached());
    REQUIRE(voxmap.objects_voxelised == 1);

    // Uniform points over the bounds, and points near the surface.
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0, 1);
    std::normal_distribution<double> offset(0, 2 * h);
    std::vector<Vec3> points;
    const Eigen::AlignedBox3d box = grown(bounds, 4 * h);
    for (int i = 0; i < 6000; ++i)
      points.push_back(box.min() +
                       box.sizes().cwiseProduct(Vec3(unit(random), unit(random), unit(random))));
    const std::vector<Vec3>& vertices = scene[0].mesh.vertices;
    for (int i = 0; i < 6000; ++i) {
      const Vec3& v = vertices[static_cast<std::size_t>(i * 7919) % vertices.size()];
      points.push_back(scene[0].pose.transform_point(v) +
                       Vec3(offset(random), offset(random), offset(random)));
    }
    PointQueryResult truth;
    cgal->query_points({.points = points, .want_inside = true, .want_closest = true}, truth);

    // The state is φ at the voxel's centre, and the point is at most √3/2 h
    // from the centre, so a wrong side is possible only within (√3−1)/2 h of
    // the surface, a surface voxel holds points within (1+√3)/2 h, and a
    // proximity voxel points within (L + 1/2 + √3/2) h.
    int mismatches_near = 0, counted[4] = {0, 0, 0, 0};
    for (std::size_t i = 0; i < points.size(); ++i) {
      const VoxelState state = voxmap.lookup.state(voxmap.lookup.voxel_of(points[i]));
      const bool inside = truth.inside[i] != 0;
      const double distance = truth.distance[i];
      ++counted[static_cast<int>(state)];
      INFO("h " << h << " point " << points[i].transpose() << " state " << static_cast<int>(state)
                << " inside " << inside << " distance " << distance);
      switch (state) {
        case VoxelState::kInterior:
          if (!inside) {
            ++mismatches_near;
            CHECK(distance <= h);
          }
          break;
        case VoxelState::kSurface:
          CHECK(distance <= (1 + kSqrt3) / 2 * h + 1e-7);
          break;
        case VoxelState::kProximity:
          if (inside) ++mismatches_near;
          CHECK((!inside || distance <= h));
          CHECK(distance <= (settings.proximity_layers + 0.5 + kSqrt3 / 2) * h + 1e-7);
          break;
        case VoxelState::kFree:
          if (inside) ++mismatches_near;
          CHECK((!inside || distance <= h));
          CHECK(distance >= (settings.proximity_layers + 0.5 - kSqrt3 / 2) * h - 1e-7);
          break;
      }
    }
    // Every state occurs, so the checks above are not vacuous.
    for (int s = 0; s < 4; ++s) CHECK(counted[s] > 100);
    CHECK(mismatches_near < static_cast<int>(points.size()) / 20);
  }
}

TEST_CASE("each voxel's state is the closed-form signed distance at its centre, classified",
          "[voxmap_pointshell]") {
  // A tilted box: its mesh is exact, so φ is the closed form.
  const Vec3 size(0.05, 0.03, 0.02);
  const Pose pose{Vec3(0.003, 0.001, -0.002), quat_from_rotation_vector(Vec3(0.2, 0.4, -0.3))};
  const std::vector<SceneObject> scene{box_object(size, pose)};
  Shape shape;
  shape.type = ShapeType::kBox;
  shape.size = size;
  const double h = 0.002;
  for (const bool signed_distance : {false, true}) {
    VoxmapSettings settings;
    settings.voxel_size_m = h;
    settings.proximity_layers = 1;
    settings.signed_distance = signed_distance;
    const SceneVoxmap voxmap =
        build_scene_voxmap(scene, grown(world_bounds(scene[0]), 0.01), settings, uncached());
    int checked = 0;
    for (int i = -25; i <= 25; ++i) {
      for (int j = -25; j <= 25; ++j) {
        for (int k = -25; k <= 25; ++k) {
          const Eigen::Vector3i voxel(i, j, k);
          const Vec3 centre = voxmap.lookup.centre_of(voxel);
          const double phi = shape_signed_distance(shape, pose.inverse_transform_point(centre));
          // Stay clear of the thresholds by float rounding.
          const double margin = 1e-6;
          bool near_threshold = false;
          for (const double t : {-0.5 * h, 0.5 * h, 1.5 * h})
            near_threshold = near_threshold || std::abs(phi - t) < margin;
          if (near_threshold) continue;
          VoxelState expected = VoxelState::kFree;
          if (phi < -0.5 * h) {
            expected = VoxelState::kInterior;
          } else if (phi <= 0.5 * h) {
            expected = VoxelState::kSurface;
          } else if (phi <= 1.5 * h) {
            expected = VoxelState::kProximity;
          }
          INFO("voxel " << voxel.transpose() << " phi " << phi);
          REQUIRE(voxmap.lookup.state(voxel) == expected);
          if (signed_distance && std::abs(phi) < 2 * h)
            REQUIRE(voxmap.lookup.distance(voxel) == Approx(phi).margin(1e-6));
          ++checked;
        }
      }
    }
    CHECK(checked > 100000);
  }
}

TEST_CASE("the signed-distance variant interpolates φ trilinearly with its exact gradient",
          "[voxmap_pointshell]") {
  // An axis-aligned box face is a plane: φ is linear there and trilinear
  // interpolation reproduces it exactly.
  const std::vector<SceneObject> scene{box_object(Vec3(0.2, 0.2, 0.02), Pose{})};
  VoxmapSettings settings;
  settings.voxel_size_m = 0.002;
  settings.signed_distance = true;
  const SceneVoxmap voxmap = build_scene_voxmap(
      scene, Eigen::AlignedBox3d(Vec3(-0.03, -0.03, -0.02), Vec3(0.03, 0.03, 0.03)), settings,
      uncached());
  std::mt19937 random(3);
  std::uniform_real_distribution<double> xy(-0.02, 0.02), z(0.01 - 0.005, 0.01 + 0.004);
  for (int n = 0; n < 200; ++n) {
    const Vec3 p(xy(random), xy(random), z(random));
    Vec3 gradient;
    const double phi = voxmap.lookup.interpolated_distance(p, gradient);
    CHECK(phi == Approx(p.z() - 0.01).margin(1e-6));
    CHECK((gradient - Vec3::UnitZ()).norm() < 1e-4);
    // The gradient is the derivative of the interpolant.
    for (int a = 0; a < 3; ++a) {
      const double step = 1e-7;
      Vec3 unused;
      const double plus = voxmap.lookup.interpolated_distance(p + step * Vec3::Unit(a), unused);
      const double minus = voxmap.lookup.interpolated_distance(p - step * Vec3::Unit(a), unused);
      CHECK((plus - minus) / (2 * step) == Approx(gradient[a]).margin(1e-3));
    }
  }
}

TEST_CASE("the voxmap covers only objects whose band meets the region", "[voxmap_pointshell]") {
  const std::vector<SceneObject> scene{
      box_object(Vec3(0.02, 0.02, 0.02), Pose{}),
      box_object(Vec3(0.02, 0.02, 0.02), Pose{Vec3(0.5, 0, 0), Quat::Identity()})};
  VoxmapSettings settings;
  settings.voxel_size_m = 0.002;
  const SceneVoxmap near_first = build_scene_voxmap(
      scene, Eigen::AlignedBox3d(Vec3(-0.05, -0.05, -0.05), Vec3(0.05, 0.05, 0.05)), settings,
      uncached());
  CHECK(near_first.objects_voxelised == 1);
  CHECK(near_first.lookup.state(near_first.lookup.voxel_of(Vec3::Zero())) == VoxelState::kInterior);
  // Outside the region everything reads free, even inside the second box.
  CHECK(near_first.lookup.state(near_first.lookup.voxel_of(Vec3(0.5, 0, 0))) == VoxelState::kFree);
  const SceneVoxmap nothing = build_scene_voxmap(
      scene, Eigen::AlignedBox3d(Vec3(0.2, 0.2, 0.2), Vec3(0.3, 0.3, 0.3)), settings, uncached());
  CHECK(nothing.objects_voxelised == 0);
  CHECK(nothing.lookup.state(nothing.lookup.voxel_of(Vec3::Zero())) == VoxelState::kFree);
}

TEST_CASE("an open surface marked distance_only has surface voxels but no interior",
          "[voxmap_pointshell]") {
  // A box without its top face: open, so no inside. Walls at ±15.3 mm,
  // clear of the voxel faces (odd multiples of 1 mm).
  SceneObject open = box_object(Vec3(0.0306, 0.0306, 0.0306), Pose{});
  std::vector<std::array<int, 3>> kept;
  for (std::size_t t = 0; t < open.mesh.triangles.size(); ++t)
    if (open.mesh.face_normal(t).z() < 0.5) kept.push_back(open.mesh.triangles[t]);
  REQUIRE(kept.size() == open.mesh.triangles.size() - 2);
  open.mesh.triangles = kept;
  open.distance_only = true;
  VoxmapSettings settings;
  settings.voxel_size_m = 0.002;
  const SceneVoxmap voxmap =
      build_scene_voxmap({open}, grown(world_bounds(open), 0.01), settings, uncached());
  const std::vector<int64_t> counts = voxmap.lookup.state_counts();
  CHECK(counts[static_cast<int>(VoxelState::kInterior)] == 0);
  CHECK(counts[static_cast<int>(VoxelState::kSurface)] > 0);
  // A wall voxel is surface, the middle of the box is free (8 voxels from every face).
  CHECK(voxmap.lookup.state(voxmap.lookup.voxel_of(Vec3(0.0153, 0, 0))) == VoxelState::kSurface);
  CHECK(voxmap.lookup.state(voxmap.lookup.voxel_of(Vec3::Zero())) == VoxelState::kFree);
}

TEST_CASE("clearance is a lower bound on the distance to every non-free voxel",
          "[voxmap_pointshell]") {
  const std::vector<SceneObject> scene{box_object(Vec3(0.03, 0.03, 0.03), Pose{})};
  VoxmapSettings settings;
  settings.voxel_size_m = 0.001;
  settings.proximity_layers = 2;
  const SceneVoxmap voxmap =
      build_scene_voxmap(scene, Eigen::AlignedBox3d(Vec3(-0.2, -0.2, -0.2), Vec3(0.2, 0.2, 0.2)),
                         settings, uncached());
  // Non-free voxels reach out to (L + 1/2) h beyond the box, plus half a
  // voxel for the cube: distance from p to the region is at least the
  // distance to the grown box.
  const double reach = 0.015 + (settings.proximity_layers + 1) * settings.voxel_size_m;
  std::mt19937 random(5);
  std::uniform_real_distribution<double> coordinate(-0.25, 0.25);
  int positive = 0;
  for (int n = 0; n < 2000; ++n) {
    const Vec3 p(coordinate(random), coordinate(random), coordinate(random));
    const double outside = (p.cwiseAbs().array() - reach).cwiseMax(0.0).matrix().norm();
    const double bound = voxmap.lookup.clearance(p);
    INFO("p " << p.transpose());
    CHECK(bound <= outside + 1e-12);
    if (bound > 0) ++positive;
  }
  CHECK(positive > 1000);  // and it is not trivially zero
}

TEST_CASE("near the scene, clearance is within a voxel of the distance to the non-free voxels",
          "[voxmap_pointshell]") {
  // The bunny, so that surfaces meet the grid at every angle; the distance
  // to the non-free voxels' cubes by brute force over a window.
  const std::vector<SceneObject> scene{bunny_object()};
  VoxmapSettings settings;
  settings.voxel_size_m = 0.001;
  settings.signed_distance = true;
  const Eigen::AlignedBox3d bounds = world_bounds(scene[0]);
  const SceneVoxmap voxmap = build_scene_voxmap(scene, grown(bounds, 0.01), settings, uncached());
  const VoxelLookup& lookup = voxmap.lookup;
  const double h = settings.voxel_size_m;
  const int window = VoxelLookup::kFineCap + 2;
  std::mt19937 random(9);
  std::uniform_real_distribution<double> unit(0, 1);
  int near = 0, tight = 0;
  for (int n = 0; n < 3000 && near < 300; ++n) {
    // Within the object's bounds, so inside the lookup's arrays.
    const Vec3 p =
        bounds.min() + bounds.sizes().cwiseProduct(Vec3(unit(random), unit(random), unit(random)));
    const Eigen::Vector3i centre = lookup.voxel_of(p);
    double distance = std::numeric_limits<double>::infinity();
    int chebyshev = window + 1;  // voxels, to the nearest non-free voxel
    for (int dx = -window; dx <= window; ++dx) {
      for (int dy = -window; dy <= window; ++dy) {
        for (int dz = -window; dz <= window; ++dz) {
          const Eigen::Vector3i v = centre + Eigen::Vector3i(dx, dy, dz);
          if (lookup.state(v) == VoxelState::kFree) continue;
          const Vec3 c = lookup.centre_of(v);
          const Vec3 gap = ((p - c).cwiseAbs().array() - 0.5 * h).cwiseMax(0.0);
          distance = std::min(distance, gap.norm());
          chebyshev = std::min(chebyshev, std::max({std::abs(dx), std::abs(dy), std::abs(dz)}));
        }
      }
    }
    if (!(distance < (VoxelLookup::kFineCap - 1) * h)) continue;  // beyond the fine map
    ++near;
    const double bound = lookup.clearance(p);
    INFO("p " << p.transpose() << " distance " << distance);
    CHECK(bound <= distance + 1e-12);
    // Exactly the Chebyshev bound (k − 1) h within the fine map's reach.
    if (chebyshev <= VoxelLookup::kFineCap)
      CHECK(bound == Approx(std::max(chebyshev - 1, 0) * h).margin(1e-15));
    // Chebyshev: at worst √3 (a diagonal) and one voxel (cube to cube) below.
    CHECK(bound >= distance / kSqrt3 - 1.0001 * h);
    if (bound > 0) ++tight;
  }
  CHECK(near >= 300);
  CHECK(tight > 100);
}

TEST_CASE("pointshell points are surface voxel centres with inward normals",
          "[voxmap_pointshell]") {
  Shape sphere;
  sphere.type = ShapeType::kSphere;
  sphere.radius = 0.02;
  sphere.subdivisions = 4;
  const TriangleMesh mesh = shape_mesh(sphere);
  const double spacing = 0.001;
  const PointShellPoints shell = build_pointshell(mesh, spacing, uncached());
  // The centres within s/2 of the surface fill a shell of volume ≈ area·s:
  // about one point per s² of surface.
  const double area = 4 * M_PI * sphere.radius * sphere.radius;
  CHECK(shell.points.size() > 0.9 * area / (spacing * spacing));
  CHECK(shell.points.size() < 1.1 * area / (spacing * spacing));
  for (std::size_t i = 0; i < shell.points.size(); ++i) {
    const Vec3& p = shell.points[i];
    INFO("point " << p.transpose());
    // A voxel centre on the spacing grid...
    for (int a = 0; a < 3; ++a) CHECK(std::abs(p[a] / spacing - std::round(p[a] / spacing)) < 1e-9);
    // ...within half a voxel of the (inscribed) mesh surface...
    CHECK(std::abs(p.norm() - sphere.radius) <= 0.5 * spacing + 3e-5);
    // ...with the inward normal of the sphere.
    CHECK(shell.normals[i].norm() == Approx(1).margin(1e-9));
    CHECK(shell.normals[i].dot(-p.normalized()) > std::cos(5 * M_PI / 180));
  }
}

TEST_CASE("the pointshell covers a closed tool at the spacing whatever its alignment with the grid",
          "[voxmap_pointshell]") {
  // Cubes whose faces lie on a plane of voxel centres (half-size k·h) and
  // halfway between two (half-size (k + ½)·h, where φ = ±h/2 on both sides
  // and the earlier rule |φ| ≤ h/2 could keep no point at all: a 3 cm cube
  // at 2 mm had an empty pointshell), and a sphere. One layer of points per
  // face: about 6 (L/h)² for a cube of edge L, every point within a voxel's
  // half-diagonal of the surface, every surface sample within one of a point
  // (a small cube shares its edges: n³ − (n − 2)³ points, 0.74 × 6 n² at n = 7).
  const double h = 0.002;
  std::vector<std::pair<std::string, TriangleMesh>> tools;
  for (double half_in_voxels : {3.0, 3.5, 5.0, 7.5, 8.0, 10.5}) {
    Shape cube;
    cube.type = ShapeType::kBox;
    cube.size = Vec3::Constant(2 * half_in_voxels * h);
    tools.emplace_back("cube of half-size " + std::to_string(half_in_voxels) + " h",
                       shape_mesh(cube));
  }
  Shape sphere;
  sphere.type = ShapeType::kSphere;
  sphere.radius = 0.0075;
  sphere.subdivisions = 4;
  tools.emplace_back("sphere of radius 7.5 mm", shape_mesh(sphere));
  for (const auto& [name, mesh] : tools) {
    INFO(name);
    const PointShellPoints shell = build_pointshell(mesh, h, uncached());
    double area = 0;
    for (const auto& t : mesh.triangles)
      area += 0.5 * (mesh.vertices[t[1]] - mesh.vertices[t[0]])
                        .cross(mesh.vertices[t[2]] - mesh.vertices[t[0]])
                        .norm();
    const double expected = area / (h * h);
    CHECK(shell.points.size() >= 0.7 * expected);  // n³ − (n − 2)³ of 6 n² on small cubes
    CHECK(shell.points.size() <= 1.6 * expected);
    // Distances to the surface, brute force over the triangles' samples.
    std::vector<Vec3> surface;
    for (const auto& t : mesh.triangles) {
      const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
      const int n = static_cast<int>(std::max((b - a).norm(), (c - a).norm()) / (0.25 * h)) + 1;
      for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j)
          surface.push_back(a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n));
    }
    const auto nearest = [](const Vec3& p, const std::vector<Vec3>& set) {
      double best = 1e300;
      for (const Vec3& q : set) best = std::min(best, (p - q).squaredNorm());
      return std::sqrt(best);
    };
    double farthest_point = 0, worst_cover = 0;
    for (const Vec3& p : shell.points)
      farthest_point = std::max(farthest_point, nearest(p, surface));
    for (std::size_t i = 0; i < surface.size(); i += 7)
      worst_cover = std::max(worst_cover, nearest(surface[i], shell.points));
    CHECK(farthest_point <= 0.5 * std::sqrt(3.0) * h + 0.25 * h);
    CHECK(worst_cover <= h);
  }
}

TEST_CASE("a second build loads the cache, a corrupt cache file is rebuilt",
          "[voxmap_pointshell]") {
  test::ScratchDir dir("voxmap_cache");
  const CacheSettings cache{true, dir.path()};
  const std::vector<SceneObject> scene{bunny_object()};
  VoxmapSettings settings;
  settings.voxel_size_m = 0.002;
  settings.signed_distance = true;
  const Eigen::AlignedBox3d region = grown(world_bounds(scene[0]), 0.005);

  const SceneVoxmap first = build_scene_voxmap(scene, region, settings, cache);
  CHECK_FALSE(first.stats.cache_hit);
  REQUIRE(std::filesystem::exists(first.stats.cache_file));
  const SceneVoxmap second = build_scene_voxmap(scene, region, settings, cache);
  CHECK(second.stats.cache_hit);
  CHECK(second.stats.cache_file == first.stats.cache_file);
  // Same states and distances, voxel for voxel.
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int n = 0; n < 20000; ++n) {
    const Vec3 p =
        region.min() + region.sizes().cwiseProduct(Vec3(unit(random), unit(random), unit(random)));
    const Eigen::Vector3i v = first.lookup.voxel_of(p);
    REQUIRE(first.lookup.state(v) == second.lookup.state(v));
    REQUIRE(first.lookup.distance(v) == second.lookup.distance(v));
  }

  // Another voxel size, variant or pose is another file.
  VoxmapSettings other = settings;
  other.signed_distance = false;
  CHECK_FALSE(build_scene_voxmap(scene, region, other, cache).stats.cache_hit);
  std::vector<SceneObject> moved = scene;
  moved[0].pose.p.x() += 1e-4;
  CHECK_FALSE(build_scene_voxmap(moved, region, settings, cache).stats.cache_hit);

  // Truncated file: rebuilt, no crash, then written again.
  const auto size = std::filesystem::file_size(first.stats.cache_file);
  std::filesystem::resize_file(first.stats.cache_file, size / 2);
  const SceneVoxmap after_truncation = build_scene_voxmap(scene, region, settings, cache);
  CHECK_FALSE(after_truncation.stats.cache_hit);
  CHECK_FALSE(after_truncation.stats.cache_problem.empty());
  CHECK(build_scene_voxmap(scene, region, settings, cache).stats.cache_hit);
  // Garbage: the same.
  {
    std::ofstream out(first.stats.cache_file, std::ios::binary | std::ios::trunc);
    out << "not a cache file";
  }
  CHECK_FALSE(build_scene_voxmap(scene, region, settings, cache).stats.cache_hit);
  CHECK(build_scene_voxmap(scene, region, settings, cache).stats.cache_hit);
  // Damaged bytes in the grids, length kept: rebuilt, to the same voxmap.
  {
    std::fstream io(first.stats.cache_file, std::ios::binary | std::ios::in | std::ios::out);
    io.seekp(static_cast<std::streamoff>(std::filesystem::file_size(first.stats.cache_file) / 2));
    io.write("\xde\xad\xbe\xef", 4);
  }
  const SceneVoxmap after_damage = build_scene_voxmap(scene, region, settings, cache);
  CHECK_FALSE(after_damage.stats.cache_hit);
  CHECK_FALSE(after_damage.stats.cache_problem.empty());
  for (int n = 0; n < 2000; ++n) {
    const Vec3 p =
        region.min() + region.sizes().cwiseProduct(Vec3(unit(random), unit(random), unit(random)));
    const Eigen::Vector3i v = first.lookup.voxel_of(p);
    REQUIRE(first.lookup.state(v) == after_damage.lookup.state(v));
  }

  // The pointshell is cached the same way.
  const PointShellPoints shell_first = build_pointshell(scene[0].mesh, 0.002, cache);
  const PointShellPoints shell_second = build_pointshell(scene[0].mesh, 0.002, cache);
  CHECK_FALSE(shell_first.stats.cache_hit);
  CHECK(shell_second.stats.cache_hit);
  CHECK(shell_first.points == shell_second.points);
  CHECK(shell_first.normals == shell_second.normals);

  // No temporary files are left behind.
  for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
    CHECK(entry.path().extension() == ".hbcache");
}

TEST_CASE("an unwritable cache folder is skipped, not fatal", "[voxmap_pointshell]") {
  test::ScratchDir dir("voxmap_cache_blocked");
  // A file where the folder should be.
  const std::filesystem::path blocked = dir / "not_a_folder";
  std::ofstream(blocked) << "x";
  const std::vector<SceneObject> scene{box_object(Vec3(0.02, 0.02, 0.02), Pose{})};
  VoxmapSettings settings;
  const SceneVoxmap voxmap = build_scene_voxmap(scene, grown(world_bounds(scene[0]), 0.01),
                                                settings, CacheSettings{true, blocked / "sub"});
  CHECK_FALSE(voxmap.stats.cache_hit);
  CHECK_FALSE(voxmap.stats.cache_problem.empty());
  CHECK(voxmap.lookup.state(voxmap.lookup.voxel_of(Vec3::Zero())) == VoxelState::kInterior);
}

}  // namespace
}  // namespace hb
