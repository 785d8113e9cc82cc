// Indexed triangle mesh and its validation. Coordinates are metres in the
// mesh's own frame (after any scale). Triangles are counter-clockwise seen
// from outside, so face normals point out of the solid.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "hapticbench/pose.h"

namespace hb {

struct TriangleMesh {
  std::vector<Vec3> vertices;                 ///< metres, mesh frame
  std::vector<std::array<int, 3>> triangles;  ///< vertex indices, CCW from outside

  /// Unit outward normal of triangle t (zero for a degenerate triangle).
  Vec3 face_normal(std::size_t t) const;
  /// Axis-aligned bounds of the vertices, mesh frame (m).
  Eigen::AlignedBox3d bounds() const;
  /// Largest distance of a vertex from the given centre (m).
  double radius_about(const Vec3& centre) const;
};

/// What validation found first, with where it found it.
struct MeshDefect {
  std::string location;  ///< e.g. "triangle 37", "edge (4, 9)", "vertex 12"
  std::string message;   ///< what is wrong and what was expected
};

/// What a mesh must be: a closed solid (tools, meshes used for inside/outside
/// ground truth), or only a clean surface (a scene mesh kept for distances).
enum class MeshRequirement { kClosedSolid, kSurface };

/// Checks that the mesh bounds a solid: indices in range, no degenerate
/// (zero-area) or duplicate triangles, every edge shared by exactly two
/// triangles (closed, manifold), consistent orientation, and positive
/// enclosed volume (outward normals). Returns the first defect found.
/// With kSurface, only indices, coordinates, degenerate and duplicate
/// triangles are checked.
std::optional<MeshDefect> find_mesh_defect(
    const TriangleMesh& mesh, MeshRequirement requirement = MeshRequirement::kClosedSolid);

/// Throws InputError(source, defect.location, defect.message) on a defect.
void require_valid_mesh(const TriangleMesh& mesh, const std::string& source,
                        MeshRequirement requirement = MeshRequirement::kClosedSolid);

/// Applies a rigid pose to every vertex (result in the pose's parent frame).
TriangleMesh transformed(const TriangleMesh& mesh, const Pose& pose);

}  // namespace hb
