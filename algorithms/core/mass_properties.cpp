#include "hapticbench/mass_properties.h"

#include <cmath>
#include <sstream>

#include "hapticbench/input_error.h"

namespace hb {

// The solid is split into one signed tetrahedron per triangle, with a common
// apex o. By the divergence theorem the signed tetrahedra outside the solid
// cancel, so the sums below are exact for any closed, outward-oriented mesh.
// For a tetrahedron (o, o + a, o + b, o + c) with D = a · (b × c):
//   volume                  D / 6
//   first moment about o    D / 24 · (a + b + c)
//   second moment about o   D / 120 · (s sᵀ + a aᵀ + b bᵀ + c cᵀ),  s = a + b + c
// (the covariance ∫ x xᵀ dV of the canonical tetrahedron, [[2,1,1],[1,2,1],
// [1,1,2]] / 120, mapped by the matrix [a b c]).
MassProperties mass_properties_from_density(const TriangleMesh& mesh, double density_kg_m3) {
  if (!std::isfinite(density_kg_m3) || density_kg_m3 <= 0.0) {
    std::ostringstream got;
    got << density_kg_m3;
    throw InputError("", "density",
                     "expected a positive finite density in kg/m^3, got " + got.str());
  }

  // The apex at the bounding-box centre keeps the terms small for a mesh far
  // from its own origin.
  const Vec3 apex = mesh.bounds().center();
  double six_volume = 0.0;
  Vec3 first_moment_24 = Vec3::Zero();    // 24 × ∫ (x − o) dV
  Mat3 second_moment_120 = Mat3::Zero();  // 120 × ∫ (x − o)(x − o)ᵀ dV
  for (const auto& [i, j, k] : mesh.triangles) {
    const Vec3 a = mesh.vertices[i] - apex;
    const Vec3 b = mesh.vertices[j] - apex;
    const Vec3 c = mesh.vertices[k] - apex;
    const double d = a.dot(b.cross(c));
    const Vec3 s = a + b + c;
    six_volume += d;
    first_moment_24 += d * s;
    second_moment_120 +=
        d * (s * s.transpose() + a * a.transpose() + b * b.transpose() + c * c.transpose());
  }

  const double volume = six_volume / 6.0;
  if (!(volume > 0.0)) {
    std::ostringstream got;
    got << volume;
    throw InputError("", "mesh",
                     "encloses no positive volume (" + got.str() +
                         " m^3); expected a closed mesh with outward normals");
  }

  const Vec3 com_from_apex = first_moment_24 / (24.0 * volume);
  // Parallel-axis shift of the covariance from the apex to the centre of mass.
  const Mat3 covariance_about_com =
      second_moment_120 / 120.0 - volume * com_from_apex * com_from_apex.transpose();

  MassProperties result;
  result.volume_m3 = volume;
  result.mass_kg = density_kg_m3 * volume;
  result.centre_of_mass = apex + com_from_apex;
  // I = ρ ∫ (|r|² 1 − r rᵀ) dV = ρ (tr(C) 1 − C).
  result.inertia_about_com =
      density_kg_m3 * (covariance_about_com.trace() * Mat3::Identity() - covariance_about_com);
  // Symmetric by construction up to rounding; make it exactly so.
  result.inertia_about_com =
      0.5 * (result.inertia_about_com + result.inertia_about_com.transpose()).eval();
  return result;
}

}  // namespace hb
