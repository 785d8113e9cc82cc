// Procedural primitive shapes: their exact parameters (for analytic ground
// truth and penalty_analytic) and a closed triangle mesh of each (for
// everything else). Each shape is centred on its own frame's origin.
#pragma once

#include <string>

#include "hapticbench/pose.h"
#include "hapticbench/triangle_mesh.h"

namespace hb {

enum class ShapeType { kBox, kSphere, kCapsule, kBoxWithHole };

struct Shape {
  ShapeType type = ShapeType::kBox;
  Vec3 size = Vec3::Zero();       ///< box / box_with_hole outer extents (m), full lengths
  double radius = 0;              ///< sphere, capsule radius (m)
  double length = 0;              ///< capsule: length of the axis segment along z (m)
  int subdivisions = 3;           ///< sphere: icosphere subdivision levels; capsule: rings
  Vec3 hole_size = Vec3::Zero();  ///< box_with_hole: x, y extents of the through-hole
                                  ///< along z (m); z unused
};

/// "box", "sphere", "capsule", "box_with_hole".
std::string shape_type_name(ShapeType type);

/// A closed, outward-oriented, valid triangle mesh of the shape (m, shape frame).
/// A sphere's vertices lie on the sphere (the mesh is inscribed).
TriangleMesh shape_mesh(const Shape& shape);

/// Signed distance (m) from a point in the shape frame to the exact shape
/// surface: negative inside. Exact for box, sphere, capsule, box_with_hole.
double shape_signed_distance(const Shape& shape, const Vec3& point);

/// Closest point on the exact surface (shape frame) and outward unit normal there.
struct SurfacePoint {
  Vec3 point;
  Vec3 normal;
  double signed_distance;
};
SurfacePoint shape_closest_surface_point(const Shape& shape, const Vec3& point);

}  // namespace hb
