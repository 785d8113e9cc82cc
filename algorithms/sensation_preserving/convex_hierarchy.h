// The multiresolution hierarchy of Otaduy & Lin's sensation-preserving
// simplification (lecture notes, "Constructing the Hierarchy" and "Levels of
// Detail"): a convex surface decomposition of a mesh (patches whose surface
// is convex, grown greedily from faces), then pairwise merges of adjacent
// pieces, each merged piece simplified so that it stays convex and encloses
// what it replaces; a level of detail is marked each time the number of
// pieces halves. The hierarchy is also the bounding-volume hierarchy of the
// contact query. Built offline and cached on disk by content hash and
// settings.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "hapticbench/pose.h"
#include "hapticbench/triangle_mesh.h"

namespace hb {

struct ConvexHierarchySettings {
  /// Largest angle (rad) by which a face may fold back against the patch it
  /// joins and still count as convex (absorbs flat and nearly flat noise):
  /// a patch vertex may rise above a patch face's plane by at most
  /// sin(tolerance) times its distance from the face's centroid. In [0, π/2).
  double convexity_tolerance_rad = 1e-3;
  /// Most vertices a merged piece keeps (its hull is decimated by
  /// convexity-keeping, enclosing edge collapses down to this), ≥ 4. Leaves
  /// keep their whole hull. A merged piece keeps more only when no enclosing
  /// collapse is left (not seen on the models of models/).
  int max_piece_vertices = 32;
};

/// One node: a convex piece that stands for a patch of the original surface
/// (the union of the leaf patches below it). The piece encloses the patch
/// and the pieces of the node's children, so the hierarchy is also a
/// conservative bounding-volume hierarchy.
struct ConvexNode {
  std::vector<Vec3> vertices;  ///< convex piece's vertices, mesh frame, m
  /// Its faces, counter-clockwise from outside: every vertex lies on or
  /// behind every face's plane. A flat piece (a convex polygon) lists each
  /// triangle once on each side; a piece from degenerate triangles only (a
  /// segment or a point) has no triangles.
  std::vector<std::array<int, 3>> triangles;
  Vec3 centre = Vec3::Zero();  ///< bounding sphere of the piece and of the patch it covers, m
  double radius = 0;           ///< m
  /// Surface deviation (m): a bound on the distance from every point of the
  /// original patch this node covers to the surface of its piece. The piece
  /// encloses the patch, so this is how far the piece stands off the true
  /// surface (detail filled in or rounded off by merging and decimation); a
  /// piece's faces that close an open patch from behind (inside the solid)
  /// are not counted, which is why a leaf's deviation is 0 up to the
  /// patch's convexity tolerance and rounding. Computed per patch triangle
  /// as min over piece faces of the largest depth of the triangle's
  /// vertices below that face (the distance to the boundary of a convex
  /// piece is concave inside it), plus 1e-12 of the coordinates' magnitude.
  double deviation_m = 0;
  /// Level of detail at which the node appears: 0 for the decomposition's
  /// pieces, l for a piece made while going from level l − 1 to level l. It
  /// stays a piece of every later level until its parent appears.
  int level = 0;
  std::array<int, 2> children{-1, -1};  ///< node indices (smaller than this node's), -1 for a leaf
  std::vector<int> faces;               ///< original triangles covered (leaves only)
};

struct ConvexHierarchy {
  std::vector<ConvexNode> nodes;  ///< leaves first, then merged nodes in order of creation
  int root = -1;                  ///< covers the whole mesh (the last node)
  /// Number of pieces at each level of detail (level 0 first, the last one
  /// is 1): the nodes with level ≤ l whose parent has level > l. Each level
  /// is a matching of the previous level's pieces, cheapest merge first,
  /// that stops once the count is halved (rounded up); when merges of
  /// adjacent pieces leave more than 3/4 of the count, pieces near each
  /// other (Morton order of their centres) are merged too.
  std::vector<int> pieces_per_level;
  /// Key of what it was built from (mesh content hash, a hash of the mesh's
  /// coordinates and triangles, settings); set by cached_convex_hierarchy,
  /// empty from build_convex_hierarchy.
  std::string key;
};

/// Builds the hierarchy of a closed or open mesh (m, mesh frame):
/// 1. convex surface decomposition: patches grown greedily across shared
///    edges from the largest triangles, a triangle joining while the patch
///    stays convex; each patch's piece is its convex hull;
/// 2. levels of merges of pieces whose patches share a vertex, the merge
///    whose hull deviates least from the patches it covers first (among
///    equal deviations the smaller piece); the merged piece is the hull of
///    the two pieces (a leaf with more than max_piece_vertices vertices
///    enters as its simplification), decimated down to max_piece_vertices
///    by enclosing edge collapses (hull_simplification.h).
/// Throws InputError for an empty mesh, a non-finite coordinate, a vertex
/// index out of range or settings out of range.
ConvexHierarchy build_convex_hierarchy(const TriangleMesh& mesh,
                                       const ConvexHierarchySettings& settings);

/// The cached hierarchy for (content_hash, the mesh as stored, settings) if
/// the cache folder (default_cache_directory()) holds a readable one, else
/// builds it and stores it there (atomically: temp file + rename; a folder
/// that cannot be written is skipped). A damaged cache file (header, key,
/// length, checksum or structure wrong) is rebuilt, never trusted.
/// cache_hit tells which happened; `name` (e.g. "tool") names the mesh in
/// progress announcements (build_progress.h).
ConvexHierarchy cached_convex_hierarchy(const TriangleMesh& mesh, const std::string& content_hash,
                                        const ConvexHierarchySettings& settings,
                                        bool* cache_hit = nullptr,
                                        const std::string& name = "mesh");

}  // namespace hb
