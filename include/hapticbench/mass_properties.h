// Mass properties of a closed triangle mesh of uniform density.
#pragma once

#include "hapticbench/pose.h"
#include "hapticbench/triangle_mesh.h"

namespace hb {

struct MassProperties {
  double mass_kg = 0;                         ///< kg
  Vec3 centre_of_mass = Vec3::Zero();         ///< m, mesh frame
  Mat3 inertia_about_com = Mat3::Identity();  ///< kg·m², mesh-frame axes, about the centre of mass
  double volume_m3 = 0;                       ///< m³
};

/// Exact mass properties of the solid bounded by a closed, outward-oriented
/// mesh (divergence theorem over signed tetrahedra). density in kg/m³.
MassProperties mass_properties_from_density(const TriangleMesh& mesh, double density_kg_m3);

}  // namespace hb
