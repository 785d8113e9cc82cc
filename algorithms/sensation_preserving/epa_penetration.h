// The direction in which one overlapping convex piece leaves another by the
// least translation: own EPA from GJK's simplex, libccd's GJK/EPA and MPR
// as further candidates, each polished to the exact minimum translation.
// libccd appears only in epa_penetration.cpp.
#pragma once

#include "algorithms/sensation_preserving/convex_body.h"
#include "algorithms/sensation_preserving/gjk.h"

namespace hb::convex_detail {

/// Unit normal that moves b out of a, for pieces GJK found overlapping
/// (`overlap` is its result); `scale` is the larger piece's extent (m).
Vec3 penetration_normal(const Body& a, const Body& b, const GjkResult& overlap, double scale);

}  // namespace hb::convex_detail
