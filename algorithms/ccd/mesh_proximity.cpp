// Proximity of the tool and the scene at one pose: which feature pairs lie
// within a distance, found by descending both sphere trees nearest node
// pair first and pruning node pairs whose spheres are farther apart than
// the current threshold. The
// threshold starts at the distance asked for and shrinks to the distance of
// the (max_pairs + 1)-th nearest pair found so far once that many are
// known, so that a crowded contact costs about max_pairs pairs' work.
#include "algorithms/ccd/mesh_proximity.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>
#include <span>
#include <utility>
#include <vector>

#include "algorithms/ccd/key_set.h"
#include "hapticbench/closest_points.h"

namespace hb::ccd_detail {

namespace {

// One key per feature pair, for removing the pairs found again through
// another leaf that shares a vertex or an edge.
uint64_t pair_key(const ContactFeatures& f) {
  return (static_cast<uint64_t>(f.kind) << 62) ^ (static_cast<uint64_t>(f.scene_object) << 52) ^
         (static_cast<uint64_t>(static_cast<uint32_t>(f.tool_feature)) << 26) ^
         static_cast<uint64_t>(static_cast<uint32_t>(f.scene_feature));
}

// Lower bounds are lowered by this fraction of the lengths they are made
// of, so that rounding can never make one exceed a distance computed
// pair by pair.
constexpr double kBoundSlack = 1e-12;

}  // namespace

class ProximitySearch {
 public:
  // Best first: node pairs in increasing order of the lower bound on their
  // features' distance, so the nearest pairs are found early and the
  // threshold shrinks before most of the trees is opened.
  ProximitySearch(const MeshFeatures& tool, std::span<const MeshFeatures> scene,
                  const Pose& tool_pose, double max_distance, std::size_t max_pairs)
      : tool_(tool),
        scene_(scene),
        rotation_(tool_pose.q.normalized().toRotationMatrix()),
        translation_(tool_pose.p),
        max_distance_(max_distance),
        threshold_(max_distance),
        max_pairs_(max_pairs) {
    if (tool_.tree.empty()) return;
    for (std::size_t o = 0; o < scene.size(); ++o)
      if (!scene[o].tree.empty()) push(static_cast<int>(o), 0, scene[o], 0);
  }

  // Opens at most `node_pairs` node pairs (all that are left when negative);
  // true once the search is complete.
  bool advance(int64_t node_pairs) {
    for (int64_t opened = 0; !open_.empty() && (node_pairs < 0 || opened < node_pairs); ++opened) {
      ++opened_;
      const NodePair pair = open_.top();
      open_.pop();
      if (pair.lower_bound > threshold_) {  // every other pair is farther still
        open_ = {};
        break;
      }
      const MeshFeatures& objects = scene_[static_cast<std::size_t>(pair.object)];
      const SphereTreeNode& tool_node = tool_.node(pair.tool);
      const SphereTreeNode& scene_node = objects.node(pair.scene);
      if (tool_node.is_leaf() && scene_node.is_leaf()) {
        leaf_pair(tool_node, tool_.leaf(pair.tool), objects, scene_node, objects.leaf(pair.scene),
                  pair.object, pair.near_tool, pair.near_scene);
        continue;
      }
      // Open the larger sphere (or the one that is not a leaf).
      if (scene_node.is_leaf() || (!tool_node.is_leaf() && tool_node.radius >= scene_node.radius)) {
        push(pair.object, tool_node.first, objects, pair.scene);
        push(pair.object, tool_node.first + 1, objects, pair.scene);
      } else {
        push(pair.object, pair.tool, objects, scene_node.first);
        push(pair.object, pair.tool, objects, scene_node.first + 1);
      }
    }
    double bound = std::min(nearest_found_, max_distance_);
    if (!open_.empty()) bound = std::min(bound, open_.top().lower_bound);
    nearest_bound_ = std::max(nearest_bound_, bound);
    return open_.empty();
  }

  // No feature pair is nearer than this (m), from what has been opened so
  // far: the nearest pair found, the least bound of the node pairs still
  // open, the distance asked for; the greatest such bound met so far (a
  // node pair's children may be bounded lower than it was).
  double nearest_bound() const { return nearest_bound_; }
  int64_t opened() const { return opened_; }

  ProximityResult finish() {
    advance(-1);
    result_.clearance_m = max_distance_;
    if (nearest_.size() > max_pairs_) {
      result_.clearance_m = nearest_.top().distance;  // the nearest pair left out
      nearest_.pop();
    }
    result_.pairs.resize(nearest_.size());
    for (std::size_t i = nearest_.size(); i-- > 0;) {
      result_.pairs[i] = nearest_.top();
      nearest_.pop();
    }
    return std::move(result_);
  }

 private:
  struct NodePair {
    double lower_bound;  ///< no two features of the nodes are nearer (m)
    int object, tool, scene;
    /// For a pair of leaves, bit k: the leaf's k-th triangle came within the
    /// threshold of the other leaf's sphere when the pair was pushed (the
    /// threshold only shrinks, so a triangle without its bit stays beyond).
    std::uint8_t near_tool, near_scene;
  };
  struct Nearer {
    bool operator()(const NodePair& a, const NodePair& b) const {
      return a.lower_bound > b.lower_bound;
    }
  };

  Vec3 world(const Vec3& tool_point) const { return translation_ + rotation_ * tool_point; }

  Vec3 tool_coordinates(const Vec3& world_point) const {
    return rotation_.transpose() * (world_point - translation_);
  }

  // The node pair's lower bound: the spheres' distance, raised, when a node
  // is a leaf, to the distance from the other node's sphere to the leaf's
  // nearest triangle (far tighter where a leaf holds a few large triangles,
  // as a box's faces).
  void push(int object, int tool, const MeshFeatures& scene, int scene_node) {
    const SphereTreeNode& a = tool_.node(tool);
    const SphereTreeNode& b = scene.node(scene_node);
    ++result_.bv_tests;
    const Vec3 tool_centre = world(a.centre);
    double bound = (tool_centre - b.centre).norm() - a.radius - b.radius;
    if (bound > threshold_) return;
    const double slack = kBoundSlack * (a.radius + b.radius);
    std::uint8_t near_scene = 0xFF, near_tool = 0xFF;
    if (b.is_leaf())
      bound = std::max(bound, leaf_bound(scene, scene.leaf(scene_node), tool_centre, a.radius,
                                         slack, near_scene));
    if (bound <= threshold_ && a.is_leaf())
      bound = std::max(bound, leaf_bound(tool_, tool_.leaf(tool), tool_coordinates(b.centre),
                                         b.radius, slack, near_tool));
    if (bound <= threshold_)
      open_.push(NodePair{bound, object, tool, scene_node, near_tool, near_scene});
  }

  /// A lower bound (m) of the distance from a sphere of `radius` about
  /// `centre` (the mesh's frame) to the leaf's nearest triangle, lowered by
  /// `slack`; `near` gets bit k where the leaf's k-th triangle's bound is
  /// within the threshold.
  double leaf_bound(const MeshFeatures& mesh, const LeafFeatures& leaf, const Vec3& centre,
                    double radius, double slack, std::uint8_t& near) const {
    double nearest = std::numeric_limits<double>::infinity();
    near = 0;
    for (int k = 0; k < leaf.triangle_count; ++k) {
      const double distance =
          distance_to_triangle(mesh, leaf.triangles[k], centre) - radius - slack;
      nearest = std::min(nearest, distance);
      if (distance <= threshold_) near = static_cast<std::uint8_t>(near | 1u << k);
    }
    return nearest;
  }

  static double distance_to_triangle(const MeshFeatures& mesh, int triangle, const Vec3& point) {
    const auto& tri = mesh.triangle(triangle);
    return (point - closest_point_on_triangle(point, mesh.vertex(tri[0]), mesh.vertex(tri[1]),
                                              mesh.vertex(tri[2])))
        .norm();
  }

  // Every feature pair of two leaves, each skipped when a cheap lower bound
  // on its distance already exceeds the threshold: a vertex's distance to
  // the other leaf's sphere or to a face's plane, an edge's midpoint sphere
  // against the other leaf's sphere or the other edge's.
  void leaf_pair(const SphereTreeNode& tool_node, const LeafFeatures& tool_leaf,
                 const MeshFeatures& scene, const SphereTreeNode& scene_node,
                 const LeafFeatures& scene_leaf, int object, unsigned near_tool,
                 unsigned near_scene) {
    // A feature pair is nearer than the threshold only if its scene feature
    // lies on a near scene triangle and its tool feature on a near tool
    // triangle (the masks push() made).
    if (near_scene == 0 || near_tool == 0) return;
    Vec3 tool_vertices[LeafFeatures::kMaxVertices];
    for (int i = 0; i < tool_leaf.vertex_count; ++i)
      tool_vertices[i] = world(tool_.vertex(tool_leaf.vertices[i]));
    auto tool_local = [&](int global) {
      for (int i = 0; i < tool_leaf.vertex_count; ++i)
        if (tool_leaf.vertices[i] == global) return tool_vertices[i];
      return world(tool_.vertex(global));
    };
    const Vec3 tool_centre = world(tool_node.centre);
    auto beyond = [&](const Vec3& point, double radius, const Vec3& centre, double centre_radius) {
      return (point - centre).norm() - radius - centre_radius > threshold_;
    };
    // Tool vertices against scene faces.
    for (int i = 0; i < tool_leaf.vertex_count; ++i) {
      const Vec3& v = tool_vertices[i];
      if (!(tool_leaf.vertex_triangles[i] & near_tool)) continue;
      if (beyond(v, 0, scene_node.centre, scene_node.radius)) continue;
      for (int k = 0; k < scene_leaf.triangle_count; ++k) {
        if (!(near_scene >> k & 1u)) continue;
        const int face = scene_leaf.triangles[k];
        const auto& tri = scene.triangle(face);
        const Vec3& normal = scene.face_normals[static_cast<std::size_t>(face)];
        if (std::abs(normal.dot(v - scene.vertex(tri[0]))) > threshold_) continue;
        const Vec3 on_face = closest_point_on_triangle(v, scene.vertex(tri[0]),
                                                       scene.vertex(tri[1]), scene.vertex(tri[2]));
        consider({ContactFeatureKind::kToolVertexSceneFace, object, tool_leaf.vertices[i], face},
                 (v - on_face).norm());
      }
    }
    // Scene vertices against tool faces.
    for (int k = 0; k < tool_leaf.triangle_count; ++k) {
      if (!(near_tool >> k & 1u)) continue;
      const int face = tool_leaf.triangles[k];
      const auto& tri = tool_.triangle(face);
      const Vec3 a = tool_local(tri[0]), b = tool_local(tri[1]), c = tool_local(tri[2]);
      const Vec3 normal = rotation_ * tool_.face_normals[static_cast<std::size_t>(face)];
      for (int j = 0; j < scene_leaf.vertex_count; ++j) {
        if (!(scene_leaf.vertex_triangles[j] & near_scene)) continue;
        const Vec3& vertex = scene.vertex(scene_leaf.vertices[j]);
        if (beyond(vertex, 0, tool_centre, tool_node.radius)) continue;
        if (std::abs(normal.dot(vertex - a)) > threshold_) continue;
        const double distance = (vertex - closest_point_on_triangle(vertex, a, b, c)).norm();
        consider({ContactFeatureKind::kSceneVertexToolFace, object, face, scene_leaf.vertices[j]},
                 distance);
      }
    }
    // Edges against edges.
    for (int i = 0; i < tool_leaf.edge_count; ++i) {
      if (!(tool_leaf.edge_triangles[i] & near_tool)) continue;
      const auto& te = tool_.edge(tool_leaf.edges[i]);
      const Vec3 p0 = tool_local(te[0]), p1 = tool_local(te[1]);
      const ToolEdge edge{tool_leaf.edges[i], p0, p1, 0.5 * (p0 + p1), 0.5 * (p1 - p0).norm()};
      if (beyond(edge.middle, edge.half, scene_node.centre, scene_node.radius)) continue;
      // Every scene edge is under half as long as a tool edge longer than
      // the scene leaf's diameter (a small tile's edges under a long face's).
      if (edge.half > 2 * scene_node.radius)
        edge_pairs<true>(edge, scene, scene_leaf, near_scene, object);
      else
        edge_pairs<false>(edge, scene, scene_leaf, near_scene, object);
    }
  }

  /// A tool edge placed in the world (m): its ends, middle and half length.
  struct ToolEdge {
    int index;
    Vec3 p0, p1, middle;
    double half;
  };

  /// The tool edge against the scene leaf's edges on near triangles. An
  /// edge lies within half its length of its middle, so a pair is no nearer
  /// than one edge's middle is from the other edge, less that half: the
  /// shorter edge's middle bounds best, the scene edge's when
  /// kBySceneMiddles, else the tool edge's.
  template <bool kBySceneMiddles>
  void edge_pairs(const ToolEdge& edge, const MeshFeatures& scene, const LeafFeatures& scene_leaf,
                  unsigned near_scene, int object) {
    for (int j = 0; j < scene_leaf.edge_count; ++j) {
      if (!(scene_leaf.edge_triangles[j] & near_scene)) continue;
      const auto& se = scene.edge(scene_leaf.edges[j]);
      const Vec3& q0 = scene.vertex(se[0]);
      const Vec3& q1 = scene.vertex(se[1]);
      if constexpr (kBySceneMiddles) {
        const Vec3 scene_middle = 0.5 * (q0 + q1);
        const double scene_half = 0.5 * (q1 - q0).norm();
        if ((scene_middle - closest_point_on_segment(scene_middle, edge.p0, edge.p1)).norm() -
                scene_half - kBoundSlack * scene_half >
            threshold_)
          continue;
      } else if ((edge.middle - closest_point_on_segment(edge.middle, q0, q1)).norm() - edge.half -
                     kBoundSlack * edge.half >
                 threshold_) {
        continue;
      }
      const double distance = closest_points_of_segments(edge.p0, edge.p1, q0, q1).distance();
      consider({ContactFeatureKind::kEdgeEdge, object, edge.index, scene_leaf.edges[j]}, distance);
    }
  }

  void consider(const ContactFeatures& features, double distance) {
    ++result_.pair_tests;
    if (!(distance <= threshold_)) return;
    if (!seen_.insert(pair_key(features))) return;
    nearest_found_ = std::min(nearest_found_, distance);
    nearest_.push(ProximityPair{features, distance});
    if (nearest_.size() > max_pairs_ + 1) nearest_.pop();
    // With max_pairs + 1 pairs known, nothing farther than the farthest of
    // them can be listed or lower the clearance.
    if (nearest_.size() == max_pairs_ + 1)
      threshold_ = std::min(threshold_, nearest_.top().distance);
  }

  // The heap's top is the farthest pair kept (ties: the last by features).
  struct Farther {
    bool operator()(const ProximityPair& a, const ProximityPair& b) const { return nearer(a, b); }
  };

  const MeshFeatures& tool_;
  std::span<const MeshFeatures> scene_;
  Mat3 rotation_;
  Vec3 translation_;
  double max_distance_;
  double threshold_;
  double nearest_found_ = std::numeric_limits<double>::infinity();
  int64_t opened_ = 0;
  double nearest_bound_ = 0;
  std::size_t max_pairs_;
  std::priority_queue<ProximityPair, std::vector<ProximityPair>, Farther> nearest_;
  KeySet seen_;
  std::priority_queue<NodePair, std::vector<NodePair>, Nearer> open_;
  ProximityResult result_;
};

ProximityInSlices::Search start_proximity_search(const MeshFeatures& tool,
                                                 std::span<const MeshFeatures> scene,
                                                 const Pose& tool_pose, double max_distance,
                                                 std::size_t max_pairs) {
  return ProximityInSlices::Search(
      new ProximitySearch(tool, scene, tool_pose, max_distance, max_pairs));
}

ProximityResult search_proximity(const MeshFeatures& tool, std::span<const MeshFeatures> scene,
                                 const Pose& tool_pose, double max_distance,
                                 std::size_t max_pairs) {
  return ProximitySearch(tool, scene, tool_pose, max_distance, max_pairs).finish();
}

PairClosestPoints pair_closest_points(const MeshFeatures& tool, const MeshFeatures& scene,
                                      const ContactFeatures& features, const Mat3& rotation,
                                      const Vec3& translation) {
  return pair_closest_points_placed(tool, scene, features, [&](int v) -> Vec3 {
    return placed_vertex(tool, rotation, translation, v);
  });
}

PlacedToolVertices::PlacedToolVertices(const MeshFeatures& tool, const Mat3& rotation,
                                       const Vec3& translation)
    : tool_(tool), rotation_(rotation), translation_(translation) {
  vertex_.fill(-1);
}

}  // namespace hb::ccd_detail

namespace hb {

void ProximityInSlices::Deleter::operator()(ccd_detail::ProximitySearch* search) const {
  delete search;
}

bool ProximityInSlices::advance(int64_t node_pairs) {
  return search_ == nullptr || search_->advance(std::max<int64_t>(node_pairs, 1));
}

int64_t ProximityInSlices::opened() const { return search_ == nullptr ? 0 : search_->opened(); }

double ProximityInSlices::nearest_bound() const {
  return search_ == nullptr ? 0.0 : search_->nearest_bound();
}

ProximityResult ProximityInSlices::finish() {
  if (search_ == nullptr) return ProximityResult{};
  ProximityResult result = search_->finish();
  search_.reset();
  return result;
}

}  // namespace hb
