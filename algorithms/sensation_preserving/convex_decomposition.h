// Convex surface decomposition (lecture notes, "Constructing the
// Hierarchy"): the mesh's triangles split into patches whose surface is
// convex, each grown greedily across shared edges from a seed triangle.
#pragma once

#include <vector>

#include "hapticbench/triangle_mesh.h"

namespace hb {

/// Partitions the triangles into convex patches (triangle indices; every
/// triangle in exactly one patch). Seeds are taken largest area first; a
/// patch grows breadth-first across shared edges, and a triangle joins when
/// the patch stays convex: every vertex of the patch lies behind the plane
/// of every triangle of it, up to an elevation of tolerance_rad seen from
/// the triangle's centroid (n·(v − c) ≤ sin(tolerance_rad)·|v − c|, plus
/// rounding). Degenerate (zero-area) triangles constrain nothing.
std::vector<std::vector<int>> convex_surface_patches(const TriangleMesh& mesh,
                                                     double tolerance_rad);

}  // namespace hb
