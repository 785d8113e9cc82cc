// Points on a mesh surface at a chosen spacing: where the oracles measure a
// posed tool's penetration.
#pragma once

#include <vector>

#include "hapticbench/pose.h"
#include "hapticbench/triangle_mesh.h"

namespace hb {

/// Points on the surface, mesh frame (m), about `spacing_m` apart: every
/// vertex is a candidate first (so corners and sharp features are kept),
/// then points on a barycentric grid of each triangle at half the spacing;
/// of all candidates, the first in each cubic cell of side spacing_m is
/// kept. Deterministic. The deepest point of a penetrating tool is therefore
/// within about one spacing (exactly a vertex for a polyhedral tool whose
/// deepest point is a vertex).
std::vector<Vec3> sample_surface(const TriangleMesh& mesh, double spacing_m);

}  // namespace hb
