#include "algorithms/sensation_preserving/hierarchy_contacts.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

#include "algorithms/sensation_preserving/convex_proximity.h"
#include "hapticbench/input_error.h"

namespace hb {

namespace {

const ConvexNode& node_at(const ConvexHierarchy& h, int index, const char* which) {
  if (index < 0 || static_cast<std::size_t>(index) >= h.nodes.size())
    throw InputError("", std::string(which) + " hierarchy node " + std::to_string(index),
                     "node index out of range (" + std::to_string(h.nodes.size()) + " nodes)");
  const ConvexNode& node = h.nodes[static_cast<std::size_t>(index)];
  if (node.vertices.empty())
    throw InputError("", std::string(which) + " hierarchy node " + std::to_string(index),
                     "a convex piece needs at least one vertex");
  return node;
}

bool has_children(const ConvexNode& node) { return node.children[0] >= 0; }

// Whether two inner pieces are apart by more than the margin, as
// convex_apart decides it: first along the direction kept for them, then
// by GJK (whose direction is kept). `size` (m) bounds the pieces' extents
// and positions: a direction counts only with 1e-9 of it to spare, far
// above the rounding of the heights and GJK's touch tolerance (1e-12 of
// the extent), so that GJK would find such a pair apart too.
bool pieces_apart(const PlacedConvex& scene_piece, const PlacedConvex& tool_piece, double margin,
                  int tool_node, int scene_node, double size, SeparatingAxes* axes,
                  HierarchyContactStats& stats) {
  if (axes == nullptr) return convex_apart(scene_piece, tool_piece, margin);
  if (const Vec3* axis = axes->find(tool_node, scene_node)) {
    if (separation_along(scene_piece, tool_piece, *axis) > margin + 1e-9 * size) {
      ++stats.axis_separations;
      axes->keep(tool_node, scene_node, *axis);
      return true;
    }
  }
  Vec3 axis;
  if (!convex_apart(scene_piece, tool_piece, margin, &axis)) return false;
  if (axis.allFinite()) axes->keep(tool_node, scene_node, axis);
  return true;
}

}  // namespace

void find_hierarchy_contacts(const ConvexHierarchy& tool, const Pose& tool_pose,
                             const ConvexHierarchy& scene, const Pose& scene_pose,
                             const HierarchyContactSettings& settings,
                             std::vector<PieceContact>& out, HierarchyContactStats& stats,
                             SeparatingAxes* axes) {
  const double threshold = settings.perceptibility_threshold;
  const double margin = settings.contact_margin_m;
  if (!(threshold >= 0) || !std::isfinite(threshold))
    throw InputError("", "perceptibility_threshold", "expected a finite number >= 0");
  if (!(margin >= 0) || !std::isfinite(margin))
    throw InputError("", "contact_margin_m", "expected a finite number >= 0 (m)");
  if (tool.root < 0 || scene.root < 0) return;

  // Kept between calls (per thread): the slow loop queries once per scene
  // object, 144 times an update on a tiled floor.
  thread_local std::vector<std::pair<int, int>> stack;
  stack.assign(1, {tool.root, scene.root});
  while (!stack.empty()) {
    const auto [ti, si] = stack.back();
    stack.pop_back();
    const ConvexNode& t = node_at(tool, ti, "tool");
    const ConvexNode& s = node_at(scene, si, "scene");
    ++stats.node_pairs_tested;
    const Vec3 tool_centre = tool_pose.transform_point(t.centre);
    const Vec3 scene_centre = scene_pose.transform_point(s.centre);
    const double reach = t.radius + s.radius + margin;
    if ((tool_centre - scene_centre).squaredNorm() > reach * reach) continue;

    const bool tool_splits = has_children(t), scene_splits = has_children(s);
    const bool perceptible = threshold == 0 || std::max(t.deviation_m, s.deviation_m) >
                                                   threshold * std::min(t.radius, s.radius);
    if (perceptible && (tool_splits || scene_splits)) {
      // The pieces enclose everything below them: pieces apart, subtrees apart.
      ++stats.piece_tests;
      if (pieces_apart(PlacedConvex{s.vertices, scene_pose}, PlacedConvex{t.vertices, tool_pose},
                       margin, ti, si,
                       t.radius + s.radius + tool_centre.norm() + scene_centre.norm(), axes, stats))
        continue;
      // Children pushed in reverse so that child 0 is visited first.
      if (tool_splits && (!scene_splits || t.radius >= s.radius)) {
        stack.emplace_back(t.children[1], si);
        stack.emplace_back(t.children[0], si);
      } else {
        stack.emplace_back(ti, s.children[1]);
        stack.emplace_back(ti, s.children[0]);
      }
      continue;
    }

    const int level = std::min(t.level, s.level);
    stats.deepest_level_reached =
        stats.gjk_calls == 0 ? level : std::min(stats.deepest_level_reached, level);
    ++stats.gjk_calls;
    const ConvexProximity proximity = convex_proximity(PlacedConvex{s.vertices, scene_pose},
                                                       PlacedConvex{t.vertices, tool_pose}, margin);
    if (!proximity.in_contact) continue;
    PieceContact contact;
    contact.point = proximity.point;
    contact.normal = proximity.normal;
    contact.depth = std::max(0.0, proximity.signed_depth);
    contact.gap_m = std::max(0.0, -proximity.signed_depth);
    contact.tool_node = ti;
    contact.scene_node = si;
    out.push_back(contact);
  }
  if (axes != nullptr) axes->next_query();
}

namespace {

/// Canonical order of contacts: deepest first, then by point, normal, nodes.
bool canonical_before(const PieceContact& a, const PieceContact& b) {
  if (a.depth != b.depth) return a.depth > b.depth;
  for (int i = 0; i < 3; ++i)
    if (a.point[i] != b.point[i]) return a.point[i] < b.point[i];
  for (int i = 0; i < 3; ++i)
    if (a.normal[i] != b.normal[i]) return a.normal[i] < b.normal[i];
  if (a.tool_node != b.tool_node) return a.tool_node < b.tool_node;
  return a.scene_node < b.scene_node;
}

ContactCluster summarize(const std::vector<const PieceContact*>& members) {
  ContactCluster cluster;
  cluster.members = static_cast<int>(members.size());
  Vec3 point_sum = Vec3::Zero(), weighted_normal = Vec3::Zero(), plain_normal = Vec3::Zero();
  cluster.depth = -std::numeric_limits<double>::infinity();
  for (const PieceContact* c : members) {
    point_sum += c->point;
    weighted_normal += c->depth * c->normal;
    plain_normal += c->normal;
    // Signed: a pair within the contact margin counts minus its gap, so a
    // cluster of such pairs acts only once the gap closes (as unclustered).
    cluster.depth = std::max(cluster.depth, c->depth - c->gap_m);
  }
  cluster.point = point_sum / static_cast<double>(members.size());
  // Depth-weighted; unweighted when no member penetrates; the deepest
  // member's own normal when the normals cancel.
  Vec3 normal = weighted_normal.norm() > 0 ? weighted_normal : plain_normal;
  if (!(normal.norm() > 1e-12)) normal = members.front()->normal;
  cluster.normal = normal.normalized();
  return cluster;
}

}  // namespace

std::vector<ContactCluster> cluster_contacts(const std::vector<PieceContact>& contacts, int k) {
  if (k < 1) throw InputError("", "cluster count k", "expected k >= 1, got " + std::to_string(k));
  std::vector<const PieceContact*> sorted;
  sorted.reserve(contacts.size());
  for (const PieceContact& c : contacts) sorted.push_back(&c);
  std::sort(sorted.begin(), sorted.end(),
            [](const PieceContact* a, const PieceContact* b) { return canonical_before(*a, *b); });
  const std::size_t n = sorted.size();
  std::vector<ContactCluster> clusters;
  if (n == 0) return clusters;
  if (static_cast<std::size_t>(k) >= n) {
    for (const PieceContact* c : sorted) clusters.push_back(summarize({c}));
    return clusters;
  }

  // Farthest-point seeding from the deepest contact.
  std::vector<Vec3> centres{sorted[0]->point};
  std::vector<double> nearest(n, std::numeric_limits<double>::infinity());
  while (centres.size() < static_cast<std::size_t>(k)) {
    std::size_t farthest = 0;
    double farthest_distance = -1;
    for (std::size_t i = 0; i < n; ++i) {
      nearest[i] = std::min(nearest[i], (sorted[i]->point - centres.back()).squaredNorm());
      if (nearest[i] > farthest_distance) {
        farthest_distance = nearest[i];
        farthest = i;
      }
    }
    if (farthest_distance <= 0) break;  // every remaining point is already a centre
    centres.push_back(sorted[farthest]->point);
  }

  // Lloyd's iterations until the assignment stops changing.
  std::vector<int> assignment(n, -1);
  for (int iteration = 0; iteration < 100; ++iteration) {
    bool changed = false;
    for (std::size_t i = 0; i < n; ++i) {
      int best = 0;
      double best_distance = std::numeric_limits<double>::infinity();
      for (std::size_t c = 0; c < centres.size(); ++c) {
        const double d = (sorted[i]->point - centres[c]).squaredNorm();
        if (d < best_distance) {
          best_distance = d;
          best = static_cast<int>(c);
        }
      }
      if (assignment[i] != best) {
        assignment[i] = best;
        changed = true;
      }
    }
    if (!changed) break;
    std::vector<Vec3> sums(centres.size(), Vec3::Zero());
    std::vector<int> counts(centres.size(), 0);
    for (std::size_t i = 0; i < n; ++i) {
      sums[static_cast<std::size_t>(assignment[i])] += sorted[i]->point;
      ++counts[static_cast<std::size_t>(assignment[i])];
    }
    for (std::size_t c = 0; c < centres.size(); ++c)
      if (counts[c] > 0) centres[c] = sums[c] / static_cast<double>(counts[c]);
  }

  for (std::size_t c = 0; c < centres.size(); ++c) {
    std::vector<const PieceContact*> members;
    for (std::size_t i = 0; i < n; ++i)
      if (assignment[i] == static_cast<int>(c)) members.push_back(sorted[i]);
    if (!members.empty()) clusters.push_back(summarize(members));
  }
  return clusters;
}

}  // namespace hb
