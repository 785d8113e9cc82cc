// The sensation-preserving contact query (lecture notes, "Collision
// Detection Strategy" and "Sensation-Preserving Contact Queries"): the tool's
// and the scene's convex hierarchies are traversed together; a pair of
// nodes whose bounding spheres overlap is refined into its children only
// where the finer level's detail is perceptible for the size of the contact,
//   max(δ_a, δ_b) > threshold · min(r_a, r_b)
// (δ: the nodes' surface deviations, r: their bounding radii, the contact
// region's scale), and otherwise answered with the current level's convex
// pieces by GJK/EPA (libccd): their penetration depth, normal and point.
// threshold = 0 descends to the leaves everywhere (full resolution).
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "algorithms/sensation_preserving/convex_hierarchy.h"
#include "hapticbench/pose.h"

namespace hb {

/// One contact between two convex pieces.
struct PieceContact {
  /// World, m: midway between the pieces' deepest points — on the plane
  /// halfway between the scene piece's extreme face, edge or vertex along
  /// the normal and the tool piece's along its opposite, at the centre of
  /// their overlap seen along the normal.
  Vec3 point;
  Vec3 normal;   ///< world, unit, pushes the tool out of the scene
  double depth;  ///< m, penetration depth along the normal (≥ 0)
  int tool_node = -1, scene_node = -1;
  /// m: for pieces apart by less than the contact margin, their distance
  /// (depth is then 0 and the normal points from the scene piece's closest
  /// point to the tool piece's); 0 for penetrating pieces.
  double gap_m = 0;
};

struct HierarchyContactSettings {
  double perceptibility_threshold = 0.05;  ///< unitless, ≥ 0 (0: full resolution)
  /// Pieces that do not overlap but are closer than this (m) are contacts
  /// too (depth 0, their distance in gap_m); only penetrating pairs are
  /// reported when 0. Bounding spheres are grown by it in the traversal.
  double contact_margin_m = 0;
};

/// Counters, added to on every call (reset them by assigning {}).
struct HierarchyContactStats {
  int64_t node_pairs_tested = 0;  ///< bounding-sphere tests
  int64_t piece_tests = 0;        ///< convex–convex separation tests of inner pieces
  int64_t gjk_calls = 0;          ///< convex–convex queries
  /// Piece tests answered by a separating direction kept from the last
  /// query (SeparatingAxes), without GJK.
  int64_t axis_separations = 0;
  /// Smallest level of detail used (0 = leaves): the least level of the
  /// two nodes of any pair answered by a convex–convex query since the
  /// counters were zero; meaningful once gjk_calls > 0.
  int deepest_level_reached = 0;
};

/// Directions that separated pairs of inner pieces in one query, kept for
/// the next, a slow-loop interval later (frame coherence): a pair one of
/// them still shows apart is not given to GJK again. A direction proves
/// the pieces apart only with room for the rounding of the test and for
/// GJK's own tolerance, so the pairs found apart are those GJK finds.
class SeparatingAxes {
 public:
  /// The direction (world, unit, from the scene piece towards the tool's)
  /// kept for the pair by the last query, or null.
  const Vec3* find(int tool_node, int scene_node) const {
    const auto found = found_.find(key(tool_node, scene_node));
    return found == found_.end() ? nullptr : &found->second;
  }
  /// Keeps a direction for the next query.
  void keep(int tool_node, int scene_node, const Vec3& axis) {
    kept_[key(tool_node, scene_node)] = axis;
  }
  /// The query is over: what it kept is what the next one finds.
  void next_query() {
    found_.swap(kept_);
    kept_.clear();
  }

 private:
  static uint64_t key(int tool_node, int scene_node) {
    return static_cast<uint64_t>(static_cast<uint32_t>(tool_node)) << 32 |
           static_cast<uint32_t>(scene_node);
  }
  std::unordered_map<uint64_t, Vec3> found_, kept_;
};

/// Appends the contacts between the tool (hierarchy in tool coordinates, at
/// tool_pose) and one scene object (at scene_pose) to `out`, in traversal
/// order (depth first, child 0 before child 1). A pair is refined when the
/// detail is perceptible (always when the threshold is 0) and one of its
/// nodes has children: the node with the larger radius (the tool's on a
/// tie) when it has children, else the other. An empty hierarchy (root -1)
/// has no contacts. Throws InputError for a negative or non-finite setting,
/// a node index out of range or a node without vertices. With `axes` (one
/// per tool–scene pair of hierarchies, kept across queries), inner piece
/// pairs are first tried along the directions that separated them in the
/// last query: the same contacts, fewer GJK calls.
void find_hierarchy_contacts(const ConvexHierarchy& tool, const Pose& tool_pose,
                             const ConvexHierarchy& scene, const Pose& scene_pose,
                             const HierarchyContactSettings& settings,
                             std::vector<PieceContact>& out, HierarchyContactStats& stats,
                             SeparatingAxes* axes = nullptr);

/// A representative contact of a cluster: the k-means centroid of its
/// members' points, their depth-weighted mean normal (unit), their largest
/// depth, and how many contacts it stands for.
struct ContactCluster {
  Vec3 point;   ///< world, m: the members' mean point
  Vec3 normal;  ///< world, unit
  /// m: the members' largest signed depth, depth − gap_m (negative when
  /// every member is a pair within the contact margin: minus the smallest gap).
  double depth = 0;
  int members = 0;
};

/// Deterministic k-means (Lloyd's algorithm, seeded by farthest-point
/// selection from the deepest contact) of the contacts' points into at most
/// k clusters (k ≥ 1; fewer when there are fewer contacts). The contacts are
/// first put in a canonical order (deepest first, then by point, normal and
/// nodes), so the answer does not depend on their order; ties of distance
/// go to the earlier contact or cluster. Clusters come in seeding order
/// (the deepest contact's first); when k ≥ the number of contacts each
/// contact is its own cluster. Throws InputError for k < 1.
std::vector<ContactCluster> cluster_contacts(const std::vector<PieceContact>& contacts, int k);

}  // namespace hb
