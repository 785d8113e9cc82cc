// What the mesh continuous collision detection keeps of one triangle mesh
// (the tool in its own frame, or a scene object placed in the world): the
// unique edges and the faces around them, the triangles' planes, and the
// bounding-sphere tree with, per node, a slab around its triangles and, per
// leaf, its distinct vertices and edges. Built once by build_mesh_features.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "algorithms/ccd/sphere_tree.h"
#include "hapticbench/pose.h"

namespace hb::ccd_detail {

/// The plane of a triangle (a, b, c) as the doubles give it: normal
/// n = (b − a) × (c − a) rounded, so b and c need not lie exactly on
/// {x : n · (x − a) = 0}; [lo, hi] bounds n · (x − a) over the three
/// vertices, so every point of the triangle lies in that slab.
struct FacePlane {
  Vec3 normal = Vec3::Zero();  ///< m², the mesh's frame
  Vec3 anchor = Vec3::Zero();  ///< the triangle's first vertex, m
  double lo = 0, hi = 0;       ///< m³, lo <= 0 <= hi
};

/// A slab {x : lo <= n · (x − c) <= hi} holding a tree node's triangles,
/// c the node sphere's centre and n the unit mean normal of the triangles:
/// far thinner than the sphere for a nearly flat patch. Kept only where it
/// is thinner than the sphere's diameter (else n is zero: no slab).
struct NodeSlab {
  Vec3 normal = Vec3::Zero();  ///< unit to a few ulps, or zero
  double lo = 0, hi = 0;       ///< m
};

/// The distinct vertices and edges of a leaf's triangles, with which of the
/// leaf's triangles (bit k: its k-th) each belongs to.
struct LeafFeatures {
  static constexpr int kMaxTriangles = SphereTree::kMaxLeafTriangles;
  static constexpr int kMaxVertices = 3 * kMaxTriangles;
  int triangle_count = 0;
  int triangles[kMaxTriangles] = {};
  int vertex_count = 0;
  int vertices[kMaxVertices] = {};
  std::uint8_t vertex_triangles[kMaxVertices] = {};
  int corner[kMaxTriangles][3] = {};  ///< local vertex index of each corner
  int edge_count = 0;
  int edges[kMaxVertices] = {};  ///< at most as many distinct edges as corners
  std::uint8_t edge_triangles[kMaxVertices] = {};
};

/// A mesh with its unique edges, adjacency, planes and sphere tree, in the
/// frame its vertices are given in (the tool frame, or the world).
struct MeshFeatures {
  std::vector<Vec3> vertices;                      ///< m
  std::vector<std::array<int, 3>> triangles;       ///< vertex indices
  std::vector<std::array<int, 2>> edges;           ///< unique, smaller vertex index first
  std::vector<std::array<int, 3>> triangle_edges;  ///< edges (v0 v1), (v1 v2), (v2 v0)
  std::vector<int> edge_face_begin;  ///< faces of edge e: edge_faces[begin[e], begin[e + 1])
  std::vector<int> edge_faces;
  std::vector<Vec3> face_normals;  ///< unit, zero for a degenerate triangle
  std::vector<FacePlane> planes;
  SphereTree tree;
  std::vector<NodeSlab> slabs;  ///< per tree node
  std::vector<int> leaf_slot;   ///< per tree node: index into leaves, −1 for an inner node
  std::vector<LeafFeatures> leaves;

  const Vec3& vertex(int v) const { return vertices[static_cast<std::size_t>(v)]; }
  const std::array<int, 3>& triangle(int t) const { return triangles[static_cast<std::size_t>(t)]; }
  const std::array<int, 2>& edge(int e) const { return edges[static_cast<std::size_t>(e)]; }
  const SphereTreeNode& node(int n) const { return tree.nodes()[static_cast<std::size_t>(n)]; }
  const NodeSlab& slab(int n) const { return slabs[static_cast<std::size_t>(n)]; }
  const LeafFeatures& leaf(int n) const {
    return leaves[static_cast<std::size_t>(leaf_slot[static_cast<std::size_t>(n)])];
  }
  const FacePlane& plane(int t) const { return planes[static_cast<std::size_t>(t)]; }

  /// Sum of the unit normals of the faces sharing edge e (the mesh's frame).
  Vec3 edge_normal_sum(int e) const;
  std::size_t memory_bytes() const;
};

/// Checks that every coordinate is finite and at most kMaxCcdCoordinate in
/// magnitude and every index in range (else throws InputError located at
/// `name` + " vertex i" or " triangle i"), then derives the rest.
MeshFeatures build_mesh_features(std::vector<Vec3> vertices,
                                 std::vector<std::array<int, 3>> triangles,
                                 const std::string& name);

/// The checks build_mesh_features makes before building (same errors).
void check_mesh_features_input(const std::vector<Vec3>& vertices,
                               const std::vector<std::array<int, 3>>& triangles,
                               const std::string& name);

/// build_mesh_features through the disk cache (hapticbench/disk_cache.h,
/// kind "mesh_features", in default_cache_directory()): the same input
/// checks, then the stored structure when one was built from the same
/// vertices and triangles by the same code, else a fresh build that is
/// stored. *cache_hit says which.
MeshFeatures cached_mesh_features(std::vector<Vec3> vertices,
                                  std::vector<std::array<int, 3>> triangles,
                                  const std::string& name, bool* cache_hit);

}  // namespace hb::ccd_detail
