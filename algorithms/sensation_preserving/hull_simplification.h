// Simplification of a convex polytope that keeps it convex and makes it only
// grow, so that it still encloses everything the original enclosed: the
// "filtered edge collapse" of sensation-preserving simplification.
#pragma once

#include "algorithms/sensation_preserving/convex_hull.h"

namespace hb {

/// Collapses edges of `hull` (as convex_hull returns it) until it has at
/// most max_vertices vertices (≥ 4), or no collapse is possible.
///
/// Solid: edge (a, b) collapses to the point c that lies on or outside the
/// planes of all triangles around a and b and adds the least volume (area-
/// weighted height above those planes, minimised over the intersections of
/// three of them, as in progressive hulls). The collapse is kept only if the
/// result is a closed manifold whose every vertex, a and b included, lies
/// on or behind every face plane: then it is convex and contains the
/// polytope before the collapse. Edges go lowest height of c above the old
/// surface first.
/// Flat polygon: edge (p_i, p_i+1) collapses to the crossing of the lines
/// through its two neighbouring edges (when they cross outside it), the
/// smallest distance from the edge first.
/// Returns the polytope unchanged when it already has few enough vertices.
ConvexPolytope simplify_enclosing(const ConvexPolytope& hull, int max_vertices);

}  // namespace hb
