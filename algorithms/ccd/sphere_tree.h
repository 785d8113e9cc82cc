// Binary bounding-sphere tree of a triangle mesh, the hierarchy the mesh
// continuous collision detection traverses (lecture notes, "Bounding
// Volumes"). Built top down: a node's triangles are split at the median of
// their centroids along the longest axis of the centroids' bounding box,
// until at most kMaxLeafTriangles remain. Each node's sphere is centred at
// the centre of the bounding box of its triangles' vertices, with the
// largest vertex distance as radius, rounded up so that the sphere encloses
// every vertex exactly, not merely to rounding.
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "hapticbench/pose.h"

namespace hb {

/// One node of a SphereTree. Coordinates are those of the vertices the tree
/// was built from (m).
struct SphereTreeNode {
  Vec3 centre = Vec3::Zero();  ///< m
  double radius = 0;           ///< m; every vertex of the node's triangles is within it
  /// Leaf: the first of its `count` entries in SphereTree::triangle_order().
  /// Inner node: the index of its first child; the second child follows it.
  int first = 0;
  int count = 0;  ///< triangles of a leaf (1..kMaxLeafTriangles); 0 for an inner node

  bool is_leaf() const { return count > 0; }
};

class SphereTree {
 public:
  static constexpr int kMaxLeafTriangles = 4;

  SphereTree() = default;
  /// vertices: m, any frame; triangles: indices into vertices (checked by
  /// the caller). An empty triangle list gives an empty tree.
  SphereTree(std::span<const Vec3> vertices, std::span<const std::array<int, 3>> triangles);
  /// A tree as built earlier (from a cache): nodes and triangle order as
  /// nodes() and triangle_order() gave them.
  SphereTree(std::vector<SphereTreeNode> nodes, std::vector<int> triangle_order)
      : nodes_(std::move(nodes)), triangle_order_(std::move(triangle_order)) {}

  bool empty() const { return nodes_.empty(); }
  /// Every node; the root is node 0.
  const std::vector<SphereTreeNode>& nodes() const { return nodes_; }
  /// Triangle indices, each leaf's contiguous.
  const std::vector<int>& triangle_order() const { return triangle_order_; }
  std::span<const int> leaf_triangles(const SphereTreeNode& leaf) const {
    return std::span<const int>(triangle_order_)
        .subspan(static_cast<std::size_t>(leaf.first), static_cast<std::size_t>(leaf.count));
  }
  std::size_t memory_bytes() const {
    return nodes_.capacity() * sizeof(SphereTreeNode) + triangle_order_.capacity() * sizeof(int);
  }

 private:
  std::vector<SphereTreeNode> nodes_;
  std::vector<int> triangle_order_;
};

}  // namespace hb
