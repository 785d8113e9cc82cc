// Tests for algorithms/core/shapes.cpp: every shape's mesh is valid and
// matches the exact shape; signed distances at hand-computed points; closest
// points and normals; and agreement with an independent brute-force
// reference (distance to the mesh's triangles, inside/outside by ray parity).
#include "hapticbench/shapes.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <set>

#include "hapticbench/closest_points.h"
#include "hapticbench/input_error.h"
#include "hapticbench/mass_properties.h"
#include "tests/support/shape_fixtures.h"

namespace hb {
namespace {

using test::box_shape;
using test::capsule_shape;
using test::sphere_shape;

Shape box_with_hole_shape(const Vec3& size, double hole_x, double hole_y) {
  Shape s;
  s.type = ShapeType::kBoxWithHole;
  s.size = size;
  s.hole_size = Vec3(hole_x, hole_y, 0);
  return s;
}

double distance_to_mesh(const TriangleMesh& mesh, const Vec3& p) {
  double best = INFINITY;
  for (const auto& [i, j, k] : mesh.triangles) {
    const Vec3 q =
        closest_point_on_triangle(p, mesh.vertices[i], mesh.vertices[j], mesh.vertices[k]);
    best = std::min(best, (p - q).squaredNorm());
  }
  return std::sqrt(best);
}

// Crossings of the ray p + t d (t > 0) with the mesh (Möller–Trumbore).
int ray_crossings(const TriangleMesh& mesh, const Vec3& p, const Vec3& d) {
  int crossings = 0;
  for (const auto& [i, j, k] : mesh.triangles) {
    const Vec3 &a = mesh.vertices[i], &b = mesh.vertices[j], &c = mesh.vertices[k];
    const Vec3 e1 = b - a, e2 = c - a, h = d.cross(e2);
    const double det = e1.dot(h);
    if (std::abs(det) < 1e-300) continue;
    const Vec3 s = p - a;
    const double u = s.dot(h) / det;
    if (u < 0 || u > 1) continue;
    const Vec3 q = s.cross(e1);
    const double v = d.dot(q) / det;
    if (v < 0 || u + v > 1) continue;
    if (e2.dot(q) / det > 0) ++crossings;
  }
  return crossings;
}

// Inside by ray parity, majority of three skew directions so that a ray
// grazing an edge cannot decide alone.
bool inside_by_ray_parity(const TriangleMesh& mesh, const Vec3& p) {
  const Vec3 directions[3] = {Vec3(0.5377, 0.8191, 0.1981).normalized(),
                              Vec3(-0.3129, 0.2718, -0.9101).normalized(),
                              Vec3(0.7071, -0.6324, 0.3162).normalized()};
  int votes = 0;
  for (const Vec3& d : directions) votes += ray_crossings(mesh, p, d) % 2;
  return votes >= 2;
}

// How far the tessellation can be inside the exact surface (vertices lie on
// it). Sphere: radius minus the nearest face plane's distance from the
// centre. Capsule (convex mesh): radius minus the nearest face plane's
// distance from the axis segment's endpoints. Boxes are tessellated exactly.
double tessellation_depth(const Shape& shape, const TriangleMesh& mesh) {
  if (shape.type != ShapeType::kSphere && shape.type != ShapeType::kCapsule)
    return 1e-12 * shape.size.norm();
  const Vec3 ends[2] = {Vec3(0, 0, 0.5 * shape.length), Vec3(0, 0, -0.5 * shape.length)};
  double nearest = INFINITY;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vec3& a = mesh.vertices[mesh.triangles[t][0]];
    for (const Vec3& e : ends) nearest = std::min(nearest, mesh.face_normal(t).dot(a - e));
  }
  return shape.radius - nearest;
}

// Extent of a box that holds the shape.
Vec3 shape_extent(const Shape& shape) {
  switch (shape.type) {
    case ShapeType::kSphere:
      return Vec3::Constant(2 * shape.radius);
    case ShapeType::kCapsule:
      return Vec3(2 * shape.radius, 2 * shape.radius, shape.length + 2 * shape.radius);
    default:
      return shape.size;
  }
}

std::vector<Shape> sample_shapes() {
  return {box_shape(Vec3(0.4, 0.2, 0.1)), sphere_shape(0.03, 3), capsule_shape(0.02, 0.06, 3),
          capsule_shape(0.02, 0.0, 2), box_with_hole_shape(Vec3(0.1, 0.08, 0.05), 0.04, 0.03)};
}

}  // namespace

TEST_CASE("shape type names", "[shapes]") {
  CHECK(shape_type_name(ShapeType::kBox) == "box");
  CHECK(shape_type_name(ShapeType::kSphere) == "sphere");
  CHECK(shape_type_name(ShapeType::kCapsule) == "capsule");
  CHECK(shape_type_name(ShapeType::kBoxWithHole) == "box_with_hole");
}

TEST_CASE("box mesh: 8 vertices on the corners, exact volume", "[shapes]") {
  for (const Vec3& size : {Vec3(1, 1, 1), Vec3(0.4, 0.02, 3.0), Vec3(1e-3, 2e-3, 5e-4)}) {
    const TriangleMesh mesh = shape_mesh(box_shape(size));
    CHECK_FALSE(find_mesh_defect(mesh));
    CHECK(mesh.vertices.size() == 8);
    CHECK(mesh.triangles.size() == 12);
    CHECK(mesh.bounds().min().isApprox(-0.5 * size));
    CHECK(mesh.bounds().max().isApprox(0.5 * size));
    CHECK(mass_properties_from_density(mesh, 1.0).volume_m3 == Approx(size.prod()));
  }
}

TEST_CASE("icosphere mesh: counts, vertices on the sphere, valid", "[shapes]") {
  for (int subdivisions = 0; subdivisions <= 5; ++subdivisions) {
    INFO("subdivisions " << subdivisions);
    const double r = 0.025;
    const TriangleMesh mesh = shape_mesh(sphere_shape(r, subdivisions));
    const std::size_t faces = 20u << (2 * subdivisions);
    CHECK(mesh.triangles.size() == faces);
    CHECK(mesh.vertices.size() == faces / 2 + 2);  // Euler: V = F/2 + 2 for genus 0
    CHECK_FALSE(find_mesh_defect(mesh));
    double worst = 0;
    for (const Vec3& v : mesh.vertices) worst = std::max(worst, std::abs(v.norm() - r));
    CHECK(worst < 1e-15);
  }
}

TEST_CASE("capsule mesh: valid, vertices on the capsule, genus 0", "[shapes]") {
  for (double length : {0.0, 1e-12, 1e-7, 0.01, 0.2}) {
    for (int subdivisions = 0; subdivisions <= 4; ++subdivisions) {
      INFO("length " << length << ", subdivisions " << subdivisions);
      const Shape shape = capsule_shape(0.015, length, subdivisions);
      const TriangleMesh mesh = shape_mesh(shape);
      CHECK_FALSE(find_mesh_defect(mesh));
      CHECK(mesh.vertices.size() == mesh.triangles.size() / 2 + 2);
      double worst = 0;
      for (const Vec3& v : mesh.vertices)
        worst = std::max(worst, std::abs(shape_signed_distance(shape, v)));
      CHECK(worst < 1e-15);
      const Eigen::AlignedBox3d box = mesh.bounds();
      CHECK(box.max().z() == Approx(0.5 * length + 0.015));
      CHECK(box.min().z() == Approx(-0.5 * length - 0.015));
    }
  }
}

TEST_CASE("box_with_hole mesh: closed, genus 1, exact volume", "[shapes]") {
  for (const auto& [size, hx, hy] :
       {std::tuple{Vec3(1, 1, 0.2), 0.4, 0.4}, std::tuple{Vec3(0.1, 0.06, 0.3), 0.01, 0.05},
        std::tuple{Vec3(2, 3, 1), 1.99, 0.1}}) {
    const TriangleMesh mesh = shape_mesh(box_with_hole_shape(size, hx, hy));
    CHECK_FALSE(find_mesh_defect(mesh));
    std::set<std::pair<int, int>> edges;
    for (const auto& t : mesh.triangles)
      for (int c = 0; c < 3; ++c) edges.insert(std::minmax(t[c], t[(c + 1) % 3]));
    const long euler = static_cast<long>(mesh.vertices.size()) - static_cast<long>(edges.size()) +
                       static_cast<long>(mesh.triangles.size());
    CHECK(euler == 0);  // genus 1
    CHECK(mass_properties_from_density(mesh, 1.0).volume_m3 ==
          Approx((size.x() * size.y() - hx * hy) * size.z()));
  }
}

TEST_CASE("invalid shape parameters name the field", "[shapes]") {
  CHECK_THROWS_WITH(shape_mesh(box_shape(Vec3(1, 0, 1))), Catch::Contains("shape.size"));
  CHECK_THROWS_WITH(shape_mesh(sphere_shape(-1, 2)), Catch::Contains("shape.radius"));
  CHECK_THROWS_WITH(shape_mesh(sphere_shape(1, 9)), Catch::Contains("shape.subdivisions"));
  CHECK_THROWS_WITH(shape_mesh(capsule_shape(1, -0.1, 2)), Catch::Contains("shape.length"));
  CHECK_THROWS_WITH(shape_mesh(capsule_shape(1, NAN, 2)), Catch::Contains("shape.length"));
  CHECK_THROWS_WITH(shape_mesh(box_with_hole_shape(Vec3(1, 1, 1), 1.0, 0.5)),
                    Catch::Contains("shape.hole_size"));
  CHECK_THROWS_AS(shape_mesh(box_with_hole_shape(Vec3(1, 1, 1), 0.5, 0.0)), InputError);
}

TEST_CASE("box signed distance and closest points at known points", "[shapes]") {
  const Shape box = box_shape(Vec3(2, 4, 6));
  CHECK(shape_signed_distance(box, Vec3(0, 0, 0)) == Approx(-1));
  CHECK(shape_signed_distance(box, Vec3(0.9, 0, 0)) == Approx(-0.1));
  CHECK(shape_signed_distance(box, Vec3(3, 0, 0)) == Approx(2));
  CHECK(shape_signed_distance(box, Vec3(0, 0, -3.5)) == Approx(0.5));
  CHECK(shape_signed_distance(box, Vec3(2, 3, 0)) == Approx(std::sqrt(2.0)));    // edge
  CHECK(shape_signed_distance(box, Vec3(-2, 3, -4)) == Approx(std::sqrt(3.0)));  // corner
  CHECK(shape_signed_distance(box, Vec3(1, 2, 3)) == Approx(0).margin(1e-15));   // on corner

  SurfacePoint s = shape_closest_surface_point(box, Vec3(-2, 3, -4));
  CHECK(s.point.isApprox(Vec3(-1, 2, -3)));
  CHECK(s.normal.isApprox(Vec3(-1, 1, -1).normalized()));
  s = shape_closest_surface_point(box, Vec3(0.2, -1.5, 0.1));  // inside, nearest face -y
  CHECK(s.point.isApprox(Vec3(0.2, -2, 0.1)));
  CHECK(s.normal.isApprox(Vec3(0, -1, 0)));
  CHECK(s.signed_distance == Approx(-0.5));
}

TEST_CASE("sphere and capsule signed distance at known points", "[shapes]") {
  const Shape sphere = sphere_shape(0.5, 2);
  CHECK(shape_signed_distance(sphere, Vec3(0, 0, 0)) == Approx(-0.5));
  CHECK(shape_signed_distance(sphere, Vec3(0, 0.6, 0.8)) == Approx(0.5));
  SurfacePoint s = shape_closest_surface_point(sphere, Vec3(0, 0.6, 0.8));
  CHECK(s.point.isApprox(Vec3(0, 0.3, 0.4)));
  CHECK(s.normal.isApprox(Vec3(0, 0.6, 0.8)));
  CHECK(shape_closest_surface_point(sphere, Vec3::Zero()).normal.norm() == Approx(1));

  const Shape capsule = capsule_shape(0.1, 0.4, 2);  // axis segment z in [-0.2, 0.2]
  CHECK(shape_signed_distance(capsule, Vec3(0, 0, 0)) == Approx(-0.1));
  CHECK(shape_signed_distance(capsule, Vec3(0.3, 0, 0.1)) == Approx(0.2));
  CHECK(shape_signed_distance(capsule, Vec3(0, 0, 0.5)) == Approx(0.2));
  CHECK(shape_signed_distance(capsule, Vec3(0.3, 0, 0.6)) == Approx(0.4));
  CHECK(shape_signed_distance(capsule, Vec3(0, 0.05, -0.25)) ==
        Approx(std::sqrt(0.05 * 0.05 * 2) - 0.1));
  s = shape_closest_surface_point(capsule, Vec3(0.3, 0, 0.6));
  CHECK(s.point.isApprox(Vec3(0.06, 0, 0.28)));
  CHECK(s.normal.isApprox(Vec3(0.6, 0, 0.8)));
  s = shape_closest_surface_point(capsule, Vec3(0, 0, 0.1));  // on the axis
  CHECK(s.normal.z() == 0.0);
  CHECK(s.point.z() == Approx(0.1));
  CHECK(s.signed_distance == Approx(-0.1));
}

TEST_CASE("box_with_hole signed distance at known points", "[shapes]") {
  // Outer 1 x 1 x 0.2, hole 0.4 x 0.4 through z: material |x|,|y| <= 0.5,
  // not both |x| < 0.2 and |y| < 0.2, |z| <= 0.1.
  const Shape frame = box_with_hole_shape(Vec3(1, 1, 0.2), 0.4, 0.4);
  auto sd = [&](const Vec3& p) { return shape_signed_distance(frame, p); };
  CHECK(sd(Vec3(0.35, 0, 0)) == Approx(-0.1));   // top and bottom faces nearest
  CHECK(sd(Vec3(0.22, 0, 0)) == Approx(-0.02));  // hole wall nearest
  CHECK(sd(Vec3(0.25, 0.25, 0)) == Approx(-std::sqrt(2 * 0.05 * 0.05)));  // inner edge
  CHECK(sd(Vec3(0, 0, 0)) == Approx(0.2));                                // hole centre
  CHECK(sd(Vec3(0.15, 0.15, 0)) == Approx(0.05));                         // in the hole
  CHECK(sd(Vec3(0.7, 0, 0)) == Approx(0.2));                              // beside the box
  CHECK(sd(Vec3(0.6, 0.6, 0.2)) == Approx(std::sqrt(3 * 0.1 * 0.1)));     // outer corner
  // Above the hole near its rim: the nearest point is the rim edge, not the
  // top face's plane (max(box_sd, -hole_sd) would say 0.1).
  CHECK(sd(Vec3(0.1, 0, 0.2)) == Approx(std::sqrt(0.1 * 0.1 + 0.1 * 0.1)));

  SurfacePoint s = shape_closest_surface_point(frame, Vec3(0.22, 0, 0.01));
  CHECK(s.point.isApprox(Vec3(0.2, 0, 0.01)));
  CHECK(s.normal.isApprox(Vec3(-1, 0, 0)));  // out of the material, into the hole
  s = shape_closest_surface_point(frame, Vec3(0.25, 0.25, 0));
  CHECK(s.point.isApprox(Vec3(0.2, 0.2, 0)));
  CHECK(s.normal.isApprox(Vec3(-1, -1, 0).normalized()));
  s = shape_closest_surface_point(frame, Vec3(0.1, 0, 0.2));
  CHECK(s.point.isApprox(Vec3(0.2, 0, 0.1)));
  CHECK(s.normal.isApprox(Vec3(-1, 0, 1).normalized()));
  s = shape_closest_surface_point(frame, Vec3(-0.15, 0.01, -0.02));  // in the hole
  CHECK(s.point.isApprox(Vec3(-0.2, 0.01, -0.02)));
  CHECK(s.normal.isApprox(Vec3(1, 0, 0)));
}

TEST_CASE("closest points lie on the surface with unit outward normals", "[shapes]") {
  std::mt19937 rng(7);
  for (const Shape& shape : sample_shapes()) {
    INFO(shape_type_name(shape.type));
    const Vec3 extent = shape_extent(shape);
    const double scale = extent.norm();
    std::uniform_real_distribution<double> unit(-0.75, 0.75);
    for (int i = 0; i < 2000; ++i) {
      const Vec3 p(unit(rng) * extent.x(), unit(rng) * extent.y(), unit(rng) * extent.z());
      const SurfacePoint s = shape_closest_surface_point(shape, p);
      CHECK(shape_signed_distance(shape, p) == Approx(s.signed_distance).margin(1e-15));
      CHECK(std::abs(shape_signed_distance(shape, s.point)) < 1e-14 * scale);
      CHECK(s.normal.norm() == Approx(1.0));
      // p = point + sd · normal: the normal is the distance gradient.
      CHECK((s.point + s.signed_distance * s.normal - p).norm() < 1e-14 * scale);
      const double step = 1e-6 * scale;
      CHECK(shape_signed_distance(shape, s.point + step * s.normal) > 0.0);
      CHECK(shape_signed_distance(shape, s.point - step * s.normal) < 0.0);
    }
  }
}

TEST_CASE("signed distance agrees with the mesh: sign by ray parity, size by brute force",
          "[shapes]") {
  std::mt19937 rng(11);
  for (const Shape& shape : sample_shapes()) {
    INFO(shape_type_name(shape.type));
    const TriangleMesh mesh = shape_mesh(shape);
    const double depth = tessellation_depth(shape, mesh);
    REQUIRE(depth >= 0.0);
    const Vec3 extent = shape_extent(shape);
    std::uniform_real_distribution<double> unit(-0.7, 0.7);
    int inside = 0, outside = 0;
    for (int i = 0; i < 600; ++i) {
      const Vec3 p(unit(rng) * extent.x(), unit(rng) * extent.y(), unit(rng) * extent.z());
      const double sd = shape_signed_distance(shape, p);
      // The mesh is inscribed: it lies between the surface and `depth` below it.
      const double to_mesh = distance_to_mesh(mesh, p);
      if (sd >= 0.0) {
        CHECK(to_mesh >= sd - 1e-15);
        CHECK(to_mesh <= sd + depth + 1e-15);
      } else {
        CHECK(std::abs(to_mesh - (-sd)) <= depth + 1e-15);
      }
      if (sd > 1e-12 || sd < -depth - 1e-12) {
        const bool mesh_inside = inside_by_ray_parity(mesh, p);
        CHECK(mesh_inside == (sd < 0.0));
        (mesh_inside ? inside : outside) += 1;
      }
    }
    CHECK(inside > 50);
    CHECK(outside > 50);
  }
}

}  // namespace hb
