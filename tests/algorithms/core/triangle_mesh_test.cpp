// Tests for algorithms/core/triangle_mesh.cpp: geometry queries, every kind
// of defect validation reports (and where), and rigid transforms.
#include "hapticbench/triangle_mesh.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "hapticbench/input_error.h"
#include "hapticbench/shapes.h"

namespace hb {
namespace {

// Corner tetrahedron 0, e_x, e_y, e_z; faces counter-clockwise from outside.
TriangleMesh corner_tetrahedron() {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return mesh;
}

// Axis-aligned cube [lo, lo + edge]^3, written out by hand.
TriangleMesh cube(double lo, double edge) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i)
    mesh.vertices.emplace_back(lo + edge * (i & 1), lo + edge * ((i >> 1) & 1),
                               lo + edge * ((i >> 2) & 1));
  mesh.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                    {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return mesh;
}

TriangleMesh flipped(TriangleMesh mesh) {
  for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  return mesh;
}

// Concatenates b after a, renumbering b's indices.
TriangleMesh merged(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh mesh = a;
  const int offset = static_cast<int>(a.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (const auto& t : b.triangles)
    mesh.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  return mesh;
}

MeshDefect defect_of(const TriangleMesh& mesh) {
  const auto defect = find_mesh_defect(mesh);
  REQUIRE(defect.has_value());
  return *defect;
}

}  // namespace

TEST_CASE("face normals are unit and outward, zero when degenerate", "[triangle_mesh]") {
  TriangleMesh mesh = corner_tetrahedron();
  CHECK(mesh.face_normal(0).isApprox(Vec3(0, 0, -1)));
  CHECK(mesh.face_normal(1).isApprox(Vec3(0, -1, 0)));
  CHECK(mesh.face_normal(2).isApprox(Vec3(-1, 0, 0)));
  CHECK(mesh.face_normal(3).isApprox(Vec3(1, 1, 1).normalized()));
  mesh.vertices.push_back({2, 0, 0});
  mesh.triangles.push_back({0, 1, 4});  // collinear corners
  CHECK(mesh.face_normal(4) == Vec3::Zero());
}

TEST_CASE("bounds and radius", "[triangle_mesh]") {
  const TriangleMesh mesh = cube(-0.5, 2.0);
  const Eigen::AlignedBox3d box = mesh.bounds();
  CHECK(box.min().isApprox(Vec3(-0.5, -0.5, -0.5)));
  CHECK(box.max().isApprox(Vec3(1.5, 1.5, 1.5)));
  CHECK(mesh.radius_about(Vec3(0.5, 0.5, 0.5)) == Approx(std::sqrt(3.0)));
  CHECK(mesh.radius_about(Vec3(-0.5, -0.5, -0.5)) == Approx(2.0 * std::sqrt(3.0)));
  CHECK(TriangleMesh{}.bounds().isEmpty());
}

TEST_CASE("valid closed meshes have no defect", "[triangle_mesh]") {
  CHECK_FALSE(find_mesh_defect(corner_tetrahedron()));
  CHECK_FALSE(find_mesh_defect(cube(3.0, 0.1)));
  // A hollow cube: the inner shell faces into the cavity, total volume > 0.
  CHECK_FALSE(find_mesh_defect(merged(cube(0, 3), flipped(cube(1, 1)))));
  // Size does not matter: a micrometre tetrahedron is as valid as a metre one.
  TriangleMesh tiny = corner_tetrahedron();
  for (Vec3& v : tiny.vertices) v *= 1e-6;
  CHECK_FALSE(find_mesh_defect(tiny));
  CHECK_NOTHROW(require_valid_mesh(tiny, "tiny.off"));
}

TEST_CASE("empty mesh", "[triangle_mesh]") {
  const MeshDefect defect = defect_of(TriangleMesh{});
  CHECK(defect.location == "mesh");
  CHECK_THAT(defect.message, Catch::Contains("empty"));
}

TEST_CASE("vertex index out of range names the triangle", "[triangle_mesh]") {
  TriangleMesh mesh = corner_tetrahedron();
  mesh.triangles[2] = {0, 7, 2};
  MeshDefect defect = defect_of(mesh);
  CHECK(defect.location == "triangle 2");
  CHECK_THAT(defect.message, Catch::Contains("7") && Catch::Contains("0..3"));

  mesh = corner_tetrahedron();
  mesh.triangles[1][2] = -1;
  CHECK(defect_of(mesh).location == "triangle 1");

  // Indices are checked before coordinates.
  mesh.vertices[0].x() = NAN;
  CHECK(defect_of(mesh).location == "triangle 1");
}

TEST_CASE("non-finite vertex names the vertex", "[triangle_mesh]") {
  TriangleMesh mesh = corner_tetrahedron();
  mesh.vertices[3].y() = INFINITY;
  const MeshDefect defect = defect_of(mesh);
  CHECK(defect.location == "vertex 3");
  CHECK_THAT(defect.message, Catch::Contains("finite"));
}

TEST_CASE("degenerate triangles", "[triangle_mesh]") {
  SECTION("repeated index") {
    TriangleMesh mesh = corner_tetrahedron();
    mesh.triangles[3] = {1, 2, 1};
    const MeshDefect defect = defect_of(mesh);
    CHECK(defect.location == "triangle 3");
    CHECK_THAT(defect.message, Catch::Contains("repeats vertex 1"));
  }
  SECTION("collinear corners: zero area relative to the mesh size") {
    TriangleMesh mesh = corner_tetrahedron();
    mesh.vertices.push_back({0.5, 0, 0});  // midpoint of edge 0-1
    mesh.triangles.push_back({0, 4, 1});
    const MeshDefect defect = defect_of(mesh);
    CHECK(defect.location == "triangle 4");
    CHECK_THAT(defect.message, Catch::Contains("zero area"));
  }
  SECTION("sliver far below 1e-12 of the squared size") {
    TriangleMesh mesh = corner_tetrahedron();
    mesh.vertices.push_back({0.5, 1e-14, 0});
    mesh.triangles.insert(mesh.triangles.begin(), {0, 4, 1});
    CHECK(defect_of(mesh).location == "triangle 0");
  }
}

TEST_CASE("duplicate triangle in any order or winding", "[triangle_mesh]") {
  TriangleMesh mesh = corner_tetrahedron();
  mesh.triangles.push_back({3, 2, 1});  // triangle 3 reversed
  const MeshDefect defect = defect_of(mesh);
  CHECK(defect.location == "triangle 4");
  CHECK_THAT(defect.message, Catch::Contains("duplicates triangle 3"));
}

TEST_CASE("open boundary names the edge", "[triangle_mesh]") {
  TriangleMesh mesh = corner_tetrahedron();
  mesh.triangles.pop_back();  // remove face (1, 2, 3)
  const MeshDefect defect = defect_of(mesh);
  // Triangle 0 = (0, 2, 1) is the first to use a boundary edge: 2-1.
  CHECK(defect.location == "edge (1, 2)");
  CHECK_THAT(defect.message, Catch::Contains("open boundary: edge used by 1 triangle") &&
                                 Catch::Contains("a closed mesh needs 2"));
}

TEST_CASE("non-manifold edge names the edge and the count", "[triangle_mesh]") {
  TriangleMesh mesh = corner_tetrahedron();
  mesh.vertices.push_back({0.5, -1, -1});
  mesh.triangles.push_back({0, 1, 4});  // a fin on edge 0-1
  const MeshDefect defect = defect_of(mesh);
  CHECK(defect.location == "edge (0, 1)");
  CHECK_THAT(defect.message, Catch::Contains("non-manifold: edge used by 3"));
}

TEST_CASE("inconsistent orientation names the edge", "[triangle_mesh]") {
  TriangleMesh mesh = corner_tetrahedron();
  mesh.triangles[3] = {1, 3, 2};  // one face flipped
  const MeshDefect defect = defect_of(mesh);
  CHECK(defect.location == "edge (1, 2)");
  CHECK_THAT(defect.message,
             Catch::Contains("inconsistent orientation") && Catch::Contains("triangles 0 and 3"));
}

TEST_CASE("inside-out mesh", "[triangle_mesh]") {
  const MeshDefect defect = defect_of(flipped(cube(0, 1)));
  CHECK(defect.location == "mesh");
  CHECK_THAT(defect.message, Catch::Contains("inside-out: normals point inward"));
}

TEST_CASE("large meshes are validated and a single flipped triangle is found", "[triangle_mesh]") {
  Shape sphere;
  sphere.type = ShapeType::kSphere;
  sphere.radius = 0.05;
  sphere.subdivisions = 6;
  TriangleMesh mesh = shape_mesh(sphere);
  REQUIRE(mesh.triangles.size() == 81920);
  CHECK_FALSE(find_mesh_defect(mesh));

  const std::size_t bad = 54321;
  std::swap(mesh.triangles[bad][1], mesh.triangles[bad][2]);
  const MeshDefect defect = defect_of(mesh);
  const auto& [a, b, c] = mesh.triangles[bad];
  auto edge = [](int i, int j) {
    return "edge (" + std::to_string(std::min(i, j)) + ", " + std::to_string(std::max(i, j)) + ")";
  };
  CHECK((defect.location == edge(a, b) || defect.location == edge(b, c) ||
         defect.location == edge(c, a)));
  CHECK_THAT(defect.message, Catch::Contains("inconsistent orientation"));
}

TEST_CASE("require_valid_mesh throws InputError naming file and place", "[triangle_mesh]") {
  TriangleMesh mesh = corner_tetrahedron();
  mesh.triangles.pop_back();
  try {
    require_valid_mesh(mesh, "models/part.stl");
    FAIL("expected InputError");
  } catch (const InputError& error) {
    CHECK(error.source() == "models/part.stl");
    CHECK(error.location() == "edge (1, 2)");
    CHECK_THAT(error.what(), Catch::StartsWith("models/part.stl: edge (1, 2): open boundary"));
  }
}

TEST_CASE("transformed applies the pose to every vertex", "[triangle_mesh]") {
  const TriangleMesh mesh = cube(0, 1);
  Pose pose;
  pose.p = Vec3(1, 2, 3);
  pose.q = Quat(Eigen::AngleAxisd(0.5 * M_PI, Vec3::UnitZ()));
  const TriangleMesh moved = transformed(mesh, pose);
  REQUIRE(moved.vertices.size() == mesh.vertices.size());
  CHECK(moved.triangles == mesh.triangles);
  // A quarter turn about z maps (x, y, z) to (-y, x, z).
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vec3& v = mesh.vertices[i];
    CHECK((moved.vertices[i] - Vec3(1 - v.y(), 2 + v.x(), 3 + v.z())).norm() < 1e-12);
  }
  CHECK_FALSE(find_mesh_defect(moved));  // rigid motions keep orientation
}

}  // namespace hb
