// Continuous collision detection of two primitives whose four points move
// linearly during a step: a vertex against a triangle, an edge against an
// edge. Conservative (a contact is never missed) and budgeted; see
// ccd_bisection.h for the tests and ccd_settings.h for the answer.
#pragma once

#include <array>

#include "algorithms/ccd/ccd_settings.h"
#include "hapticbench/pose.h"

namespace hb {

/// Four points, each moving on a straight line from `start` (t = 0) to
/// `end` (t = 1) at constant speed; world frame, m (any one length unit).
/// Vertex–face: [0] the vertex, [1], [2], [3] the triangle.
/// Edge–edge: [0]–[1] the first edge, [2]–[3] the second.
struct LinearCcdQuery {
  std::array<Vec3, 4> start;
  std::array<Vec3, 4> end;
};

/// Whether vertex [0] touches the closed triangle ([1], [2], [3]) at some
/// t in [0, 1], and the earliest such t (as a lower bound).
CcdResult vertex_face_ccd(const LinearCcdQuery& query, const CcdSettings& settings = {});

/// Whether closed segment [0]–[1] touches closed segment [2]–[3] at some t
/// in [0, 1], and the earliest such t (as a lower bound).
CcdResult edge_edge_ccd(const LinearCcdQuery& query, const CcdSettings& settings = {});

}  // namespace hb
