// Continuous collision detection of a primitive of a rigidly moving body
// (the tool, following a ScrewMotion over the step) against a static
// primitive of the scene: the god-object's three contact kinds. Conservative
// and budgeted like the linear kernels (ccd_settings.h); the coplanarity
// function is evaluated directly on interval enclosures of the moving
// points, with cos(ωt) and sin(ωt) bounded by interval_cos/interval_sin.
// One evaluation costs about twice a linear one: enclosing the moving
// points (with a sixth in libm's cos and sin) on top of the same tests.
#pragma once

#include <array>

#include "algorithms/ccd/ccd_settings.h"
#include "algorithms/ccd/screw_motion.h"
#include "hapticbench/pose.h"

namespace hb {

/// A vertex of the moving body (body coordinates, m) against a static
/// triangle (world frame, m).
CcdResult screw_vertex_face_ccd(const ScrewMotion& motion, const Vec3& body_vertex,
                                const std::array<Vec3, 3>& world_triangle,
                                const CcdSettings& settings = {});

/// A triangle of the moving body (body coordinates, m) against a static
/// vertex (world frame, m).
CcdResult screw_face_vertex_ccd(const ScrewMotion& motion, const std::array<Vec3, 3>& body_triangle,
                                const Vec3& world_vertex, const CcdSettings& settings = {});

/// An edge of the moving body (body coordinates, m) against a static edge
/// (world frame, m).
CcdResult screw_edge_edge_ccd(const ScrewMotion& motion, const std::array<Vec3, 2>& body_edge,
                              const std::array<Vec3, 2>& world_edge,
                              const CcdSettings& settings = {});

}  // namespace hb
