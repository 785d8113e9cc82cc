// Tests for algorithms/core/mass_properties.cpp against closed forms: a
// tetrahedron's moments, a box away from the origin, and spheres and
// capsules bracketed between the exact solids inscribed in and enclosing
// their tessellations.
#include "hapticbench/mass_properties.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "hapticbench/input_error.h"
#include "hapticbench/shapes.h"
#include "tests/support/shape_fixtures.h"

namespace hb {
namespace {

using test::capsule_shape;
using test::kPi;
using test::sphere_shape;

// Inertia of a point mass m at offset r (about the origin): m (|r|² 1 − r rᵀ).
Mat3 point_mass_inertia(double m, const Vec3& r) {
  return m * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
}

// Every vertex on the inner side of every face plane: the mesh is the
// boundary of a convex polytope, i.e. the intersection of its face planes'
// half-spaces.
bool is_convex(const TriangleMesh& mesh, double tolerance) {
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vec3 n = mesh.face_normal(t);
    const Vec3& a = mesh.vertices[mesh.triangles[t][0]];
    for (const Vec3& v : mesh.vertices)
      if (n.dot(v - a) > tolerance) return false;
  }
  return true;
}

// Smallest distance from a point to any face plane; for a convex mesh it is
// the radius of the largest ball about the point that fits inside.
double min_face_plane_distance(const TriangleMesh& mesh, const Vec3& point) {
  double distance = INFINITY;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vec3& a = mesh.vertices[mesh.triangles[t][0]];
    distance = std::min(distance, mesh.face_normal(t).dot(a - point));
  }
  return distance;
}

// Solid capsule of radius r and axis segment length l along z, density rho:
// mass, and inertia about its centre (cylinder plus two hemispheres, each
// hemisphere 83/320 m r² about its own centre of mass, 3r/8 from its base).
struct CapsuleClosedForm {
  double volume, izz, ixx;
};
CapsuleClosedForm capsule_closed_form(double r, double l, double rho) {
  const double cylinder = kPi * r * r * l;
  const double ball = 4.0 / 3.0 * kPi * r * r * r;
  const double offset = 0.5 * l + 3.0 * r / 8.0;
  return {cylinder + ball, rho * (cylinder * r * r / 2 + ball * 2.0 / 5.0 * r * r),
          rho * (cylinder * (l * l / 12 + r * r / 4) +
                 ball * (83.0 / 320.0 * r * r + offset * offset))};
}

}  // namespace

TEST_CASE("tetrahedron matches the closed-form moments", "[mass_properties]") {
  // Tetrahedron 0, a e_x, b e_y, c e_z: ∫x² dV = a³bc/60, ∫xy dV = a²b²c/120.
  const double a = 1.0, b = 2.0, c = 3.0, rho = 7.0;
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {a, 0, 0}, {0, b, 0}, {0, 0, c}};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const MassProperties props = mass_properties_from_density(mesh, rho);

  const double volume = a * b * c / 6.0;
  CHECK(props.volume_m3 == Approx(volume));
  CHECK(props.mass_kg == Approx(rho * volume));
  CHECK(props.centre_of_mass.isApprox(Vec3(a, b, c) / 4.0));

  const double xx = a * a * a * b * c / 60, yy = a * b * b * b * c / 60,
               zz = a * b * c * c * c / 60;
  const double xy = a * a * b * b * c / 120, xz = a * a * b * c * c / 120,
               yz = a * b * b * c * c / 120;
  Mat3 about_origin;
  about_origin << yy + zz, -xy, -xz, -xy, xx + zz, -yz, -xz, -yz, xx + yy;
  about_origin *= rho;
  const Mat3 expected = about_origin - point_mass_inertia(props.mass_kg, props.centre_of_mass);
  CHECK((props.inertia_about_com - expected).norm() < 1e-12 * expected.norm());
}

TEST_CASE("box away from the origin: centre of mass found, box inertia", "[mass_properties]") {
  const double a = 0.3, b = 0.1, c = 0.05, rho = 2700.0;
  Shape box;
  box.type = ShapeType::kBox;
  box.size = Vec3(a, b, c);
  const double m = rho * a * b * c;
  const Vec3 principal(m / 12 * (b * b + c * c), m / 12 * (a * a + c * c),
                       m / 12 * (a * a + b * b));

  SECTION("translated only") {
    const Pose pose{Vec3(2.0, -1.0, 0.5), Quat::Identity()};
    const MassProperties props =
        mass_properties_from_density(transformed(shape_mesh(box), pose), rho);
    CHECK(props.mass_kg == Approx(m));
    CHECK(props.volume_m3 == Approx(a * b * c));
    CHECK((props.centre_of_mass - pose.p).norm() < 1e-12);
    const Mat3 expected = principal.asDiagonal();
    CHECK((props.inertia_about_com - expected).norm() < 1e-9 * expected.norm());
  }
  SECTION("rotated and far away: I = R diag Rᵀ") {
    const Pose pose{Vec3(1e3, 2e3, -5e2), Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()))};
    const MassProperties props =
        mass_properties_from_density(transformed(shape_mesh(box), pose), rho);
    CHECK(props.mass_kg == Approx(m).epsilon(1e-9));
    CHECK((props.centre_of_mass - pose.p).norm() < 1e-9);
    const Mat3 r = pose.q.toRotationMatrix();
    const Mat3 expected = r * principal.asDiagonal() * r.transpose();
    CHECK((props.inertia_about_com - expected).norm() < 1e-6 * expected.norm());
    CHECK(props.inertia_about_com.isApprox(props.inertia_about_com.transpose(), 0.0));
  }
}

TEST_CASE("icosphere lies between its inscribed and circumscribed balls", "[mass_properties]") {
  const double r = 0.02, rho = 1000.0;
  double previous_error = INFINITY;
  for (int subdivisions = 0; subdivisions <= 5; ++subdivisions) {
    INFO("subdivisions " << subdivisions);
    const TriangleMesh mesh = shape_mesh(sphere_shape(r, subdivisions));
    const MassProperties props = mass_properties_from_density(mesh, rho);
    // Convex, vertices on the sphere: the ball of radius r_in (nearest face
    // plane) is inside the mesh, the mesh inside the ball of radius r. Volume
    // and each axial moment ∫(|x|² − x_i²) dV grow with the solid.
    const double r_in = min_face_plane_distance(mesh, Vec3::Zero());
    const double v_in = 4.0 / 3.0 * kPi * std::pow(r_in, 3),
                 v_out = 4.0 / 3.0 * kPi * std::pow(r, 3);
    CHECK(props.volume_m3 >= v_in);
    CHECK(props.volume_m3 <= v_out);
    CHECK(props.centre_of_mass.norm() < 1e-15);
    for (int axis = 0; axis < 3; ++axis) {
      CHECK(props.inertia_about_com(axis, axis) >= 0.4 * rho * v_in * r_in * r_in);
      CHECK(props.inertia_about_com(axis, axis) <= 0.4 * rho * v_out * r * r);
    }
    const double error = 1.0 - props.volume_m3 / v_out;
    CHECK(error < previous_error);
    previous_error = error;
  }
  // Five subdivisions: within 0.1 % of the solid sphere, 2/5 m r².
  const MassProperties fine = mass_properties_from_density(shape_mesh(sphere_shape(r, 5)), rho);
  const double mass = rho * 4.0 / 3.0 * kPi * r * r * r;
  CHECK(fine.mass_kg == Approx(mass).epsilon(1e-3));
  CHECK(fine.inertia_about_com(0, 0) == Approx(0.4 * mass * r * r).epsilon(2e-3));
}

TEST_CASE("capsule lies between the capsules inscribed in and enclosing its mesh",
          "[mass_properties]") {
  const double r = 0.01, l = 0.04, rho = 1200.0;
  const Vec3 top(0, 0, 0.5 * l), bottom(0, 0, -0.5 * l);
  for (int subdivisions = 0; subdivisions <= 3; ++subdivisions) {
    INFO("subdivisions " << subdivisions);
    const TriangleMesh mesh = shape_mesh(capsule_shape(r, l, subdivisions));
    REQUIRE(is_convex(mesh, 1e-15));
    // A convex mesh containing the axis segment contains the capsule whose
    // radius is the segment's least distance to a face plane, reached at an
    // endpoint; its vertices on the capsule put it inside the capsule of radius r.
    const double r_in =
        std::min(min_face_plane_distance(mesh, top), min_face_plane_distance(mesh, bottom));
    REQUIRE(r_in > 0.0);
    const CapsuleClosedForm inner = capsule_closed_form(r_in, l, rho);
    const CapsuleClosedForm outer = capsule_closed_form(r, l, rho);
    const MassProperties props = mass_properties_from_density(mesh, rho);
    CHECK(props.volume_m3 >= inner.volume);
    CHECK(props.volume_m3 <= outer.volume);
    CHECK(props.inertia_about_com(2, 2) >= inner.izz);
    CHECK(props.inertia_about_com(2, 2) <= outer.izz);
    CHECK(props.inertia_about_com(0, 0) >= inner.ixx);
    CHECK(props.inertia_about_com(0, 0) <= outer.ixx);
    CHECK(props.centre_of_mass.norm() < 1e-15);
    CHECK(props.inertia_about_com(0, 0) == Approx(props.inertia_about_com(1, 1)));
  }
  const MassProperties fine = mass_properties_from_density(shape_mesh(capsule_shape(r, l, 6)), rho);
  const CapsuleClosedForm exact = capsule_closed_form(r, l, rho);
  CHECK(fine.volume_m3 == Approx(exact.volume).epsilon(1e-3));
  CHECK(fine.inertia_about_com(2, 2) == Approx(exact.izz).epsilon(1e-3));
  CHECK(fine.inertia_about_com(0, 0) == Approx(exact.ixx).epsilon(1e-3));
}

TEST_CASE("bad density and inside-out meshes are rejected", "[mass_properties]") {
  Shape box;
  box.type = ShapeType::kBox;
  box.size = Vec3(1, 1, 1);
  TriangleMesh mesh = shape_mesh(box);
  CHECK_THROWS_AS(mass_properties_from_density(mesh, 0.0), InputError);
  CHECK_THROWS_AS(mass_properties_from_density(mesh, -1.0), InputError);
  CHECK_THROWS_WITH(mass_properties_from_density(mesh, NAN), Catch::Contains("density"));
  for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  CHECK_THROWS_WITH(mass_properties_from_density(mesh, 1000.0), Catch::Contains("positive volume"));
}

}  // namespace hb
