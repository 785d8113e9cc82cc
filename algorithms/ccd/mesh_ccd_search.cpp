// Earliest-first search of the first contact of a moving tool mesh with
// static scene meshes.
//
// A search entry is a tool node, a scene node and a time node (a dyadic
// sub-interval of [0, 1]) whose tests could not exclude a contact, with the
// earliest time in it at which the nodes may meet; entries are taken in
// order of that time (those no later than the last one taken from the
// queue go on a stack and are taken first). An entry that passed its tests
// is refined by halving its time node when the tool node's centre moves a
// lot during it compared with the two radii, else by opening the larger
// node; a pair of leaves is handed to the triangle tests and the primitive
// kernels. Every contact a kernel reports lowers the limit to its time plus
// the contact window: entries after the limit are never expanded, time
// nodes reaching past it are tested only up to it, entries tested before
// the limit came down are tested again, and the kernels search only up to
// it (CcdSettings::time_limit).
//
// Paths over a time node are bounded by chords (path_chord.h): a point's
// positions lie within a stray of the segment between its positions at the
// node's two ends, the stray growing with the square of the angle turned.
// The tests of a node pair over a time node T, each a necessary condition
// of contact during T, with the rounding bounded:
//  - the notes' sphere test ‖c_tool(t) − c_scene‖ <= r_tool + r_scene on
//    the tool centre's chord grown by its stray, which also gives the
//    earliest t at which it may hold;
//  - the tool sphere against the scene node's slab (mesh_features.h): the
//    centre's signed distance from the slab must come within r_tool.
// A pair of leaves then tests each pair of their triangles over T (boxes
// around the vertices' chords, then each triangle's vertices against the
// other's plane slab), each primitive pair of the triangle pairs left over
// T and its halves down to kPretestDepth levels (the kernels' own tests,
// ccd_bisection.h, on the chords' boxes), and runs the kernel of each
// primitive pair still left, once per search: the kernel covers [0, limit]
// on its own.
//
// Why every earlier contact is found: a contact of two triangles at time t
// is a contact of one of their primitive pairs (a vertex meeting a face or
// an edge meeting an edge first). Every test above is necessary for a
// contact during its interval, and the entries' time nodes that are not
// excluded cover [0, limit] for every pair of leaves, so the leaf pair and
// time node holding (t, the triangles) is reached unless t > limit, and
// its primitive pair's kernel runs.
#include "algorithms/ccd/mesh_ccd_search.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <queue>
#include <unordered_set>
#include <vector>

#include "algorithms/ccd/ccd_bisection.h"
#include "algorithms/ccd/interval.h"
#include "algorithms/ccd/path_chord.h"
#include "algorithms/ccd/screw_ccd.h"

namespace hb::ccd_detail {

namespace {

/// When the tool node centre's box over an entry's time node is wider (m)
/// than this fraction of the two radii, the time node is halved rather than
/// a node opened (inner pairs) or the triangles tested (leaf pairs): time
/// resolution keeps pairs whose nodes meet only after the contact out.
/// Chosen by timing the armadillo-on-bunny benchmark (mesh_ccd_bench).
constexpr double kInnerSpreadRatio = 0.5;
constexpr double kLeafSpreadRatio = 0.3;
/// Time nodes are not halved below this width (unitless).
constexpr double kMinTimeWidth = 0x1p-24;
/// Levels of halving of a leaf pair's time node a primitive pair's tests go
/// through before its kernel runs.
constexpr int kPretestDepth = 3;

IntervalVec3 point_interval(const Vec3& v) {
  return {Interval(v.x()), Interval(v.y()), Interval(v.z())};
}

struct ContactFeaturesHash {
  std::size_t operator()(const ContactFeatures& f) const {
    std::uint64_t h = static_cast<std::uint64_t>(f.kind);
    for (const int part : {f.scene_object, f.tool_feature, f.scene_feature})
      h = h * 0x9E3779B97F4A7C15ull + static_cast<std::uint32_t>(part);
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

bool boxes_overlap(const IntervalVec3& a, const IntervalVec3& b) {
  for (int k = 0; k < 3; ++k)
    if (a[k].hi < b[k].lo || b[k].hi < a[k].lo) return false;
  return true;
}

/// The three points, at every time their boxes enclose, lie strictly on one
/// side of the slab holding the triangle of `plane`: no point of their
/// triangle meets it.
bool separated_by_plane(const FacePlane& plane, const IntervalVec3* const corners[3]) {
  const IntervalVec3 normal = point_interval(plane.normal), anchor = point_interval(plane.anchor);
  bool above = true, below = true;
  for (int k = 0; k < 3 && (above || below); ++k) {
    const Interval side = dot(normal, *corners[k] - anchor);
    above = above && side.lo > plane.hi;
    below = below && side.hi < plane.lo;
  }
  return above || below;
}

/// A sphere of `radius` (m) about every point whose signed distance along
/// the slab's normal from its reference point is in `side` (m) lies beyond
/// the slab. The slab normal is unit to a few ulps, so the radius grows by
/// 1e-12 relative to stay an upper bound of the distance along it.
bool beyond_slab(const NodeSlab& slab, const Interval& side, double radius) {
  const double reach = next_up(radius * (1 + 1e-12));
  return side.lo - slab.hi > reach || slab.lo - side.hi > reach;
}

/// Some tool triangle in `tool_mask` and scene triangle in `scene_mask`
/// may meet (alive[i] bit j: tool triangle i and scene triangle j may).
bool any_pair_alive(const std::uint8_t* alive, unsigned tool_mask, unsigned scene_mask) {
  for (int i = 0; i < LeafFeatures::kMaxTriangles; ++i)
    if ((tool_mask >> i & 1u) && (alive[i] & scene_mask)) return true;
  return false;
}

class FirstContactSearch {
 public:
  FirstContactSearch(const MeshFeatures& tool, std::span<const MeshFeatures> scene,
                     const ScrewMotion& motion, const MeshCcdSettings& settings)
      : tool_(tool), scene_(scene), motion_(motion), frames_(motion), settings_(settings) {
    limit_cap_ =
        !(settings.primitive.time_limit < 1) ? 1.0 : std::max(settings.primitive.time_limit, 0.0);
    limit_ = limit_cap_;
    window_ = settings.contact_window >= 0 ? std::min(settings.contact_window, 1.0) : 0.0;
  }

  MeshCcdResult run() {
    TimeNode root;
    root.chord = frame_chord(frames_, motion_, 0.0, 1.0);
    times_.push_back(root);
    for (std::size_t o = 0; o < scene_.size(); ++o)
      if (!scene_[o].tree.empty()) {
        ToolCentrePath centre_path;
        push_if_may_meet(0, static_cast<int>(o), 0, 0, centre_path);
      }
    while (true) {
      Entry entry;
      if (!ready_.empty()) {
        entry = ready_.back();
        ready_.pop_back();
        if (entry.lo > limit_) continue;
      } else if (!queue_.empty()) {
        entry = queue_.top();
        if (entry.lo > limit_) break;
        queue_.pop();
        frontier_ = entry.lo;
      } else {
        break;
      }
      // Tested before the limit came down: tested again over the shorter span.
      ToolCentrePath centre_path;
      if (entry.tested_to > limit_ && time(entry.time_node).hi > limit_ &&
          pair_bounds(entry.tool_node, entry.object, entry.scene_node, entry.time_node, centre_path)
                  .earliest > limit_)
        continue;
      expand(entry);
    }
    return finish();
  }

 private:
  /// A dyadic sub-interval of [0, 1] with the tool frame at its ends.
  struct TimeNode {
    double lo = 0, hi = 1;
    FrameChord chord;           // at lo and hi
    int first_child = -1;       // the second child follows it
    double clipped_limit = -1;  // the limit `clipped` was computed for
    FrameChord clipped;         // at lo and clipped_limit
  };
  /// A pair of nodes that may meet during a time node.
  struct Entry {
    double lo;         // the earliest time the nodes may meet, in the time node
    double tested_to;  // the end of the span the tests covered
    double spread;     // how far apart (m) two positions of the tool node centre can be
    int tool_node, object, scene_node, time_node;
  };
  struct Later {
    bool operator()(const Entry& a, const Entry& b) const { return a.lo > b.lo; }
  };
  /// The tool node centre's path in the world over a time node, computed
  /// when first needed and shared by the tests of pairs that keep the tool
  /// node.
  struct ToolCentrePath {
    PathChord path;
    bool known = false;
  };

  const TimeNode& time(int index) const { return times_[static_cast<std::size_t>(index)]; }

  /// The tool frame at the time node's ends, cut at the current limit. The
  /// reference lasts until times_ grows (children_of).
  const FrameChord& chord_of(int index) {
    TimeNode& node = times_[static_cast<std::size_t>(index)];
    if (node.hi <= limit_) return node.chord;
    if (node.clipped_limit != limit_) {
      node.clipped = frame_chord(frames_, motion_, node.lo, std::max(node.lo, limit_));
      node.clipped_limit = limit_;
    }
    return node.clipped;
  }

  /// The index of the first of the time node's halves, made when first asked.
  int children_of(int index) {
    if (time(index).first_child < 0) {
      const double lo = time(index).lo, hi = time(index).hi, mid = 0.5 * (lo + hi);
      const int first = static_cast<int>(times_.size());
      for (const auto& [a, b] : {std::pair{lo, mid}, std::pair{mid, hi}}) {
        TimeNode child;
        child.lo = a;
        child.hi = b;
        child.chord = frame_chord(frames_, motion_, a, b);
        times_.push_back(child);
      }
      times_[static_cast<std::size_t>(index)].first_child = first;
    }
    return time(index).first_child;
  }

  /// What the tests of a node pair over a time node found: the earliest
  /// time the nodes may meet, and how far apart (m) two positions of the
  /// tool node's centre can be during the time node.
  struct PairBounds {
    double earliest = 2;  // > 1: they cannot meet
    double spread = 0;
  };

  /// The node pair's tests over the time node up to the limit: the sphere
  /// test on the tool centre's path, then the tool sphere against the scene
  /// node's slab.
  PairBounds pair_bounds(int tool_node, int object, int scene_node, int time_node,
                         ToolCentrePath& centre_path) {
    ++bv_tests_;
    const PairBounds apart;
    const SphereTreeNode& tool = tool_.node(tool_node);
    const MeshFeatures& mesh = scene_[static_cast<std::size_t>(object)];
    const SphereTreeNode& scene = mesh.node(scene_node);
    if (!centre_path.known) {
      centre_path.path = chord_of(time_node).world_path(tool.centre);
      centre_path.known = true;
    }
    const PathChord& centre = centre_path.path;
    const double first = centre.first_within(scene.centre, tool.radius + scene.radius);
    if (first > 1) return apart;
    const NodeSlab& slab = mesh.slab(scene_node);
    if (slab.normal.squaredNorm() > 0 &&
        beyond_slab(slab, centre.side(slab.normal, scene.centre), tool.radius))
      return apart;
    const TimeNode& node = time(time_node);
    const double end = std::min(node.hi, limit_);
    return {std::max(node.lo, next_down(node.lo + first * (end - node.lo))), centre.spread()};
  }

  void push_if_may_meet(int tool_node, int object, int scene_node, int time_node,
                        ToolCentrePath& centre_path) {
    if (time(time_node).lo > limit_) return;
    const double tested_to = std::min(time(time_node).hi, limit_);
    const PairBounds bounds = pair_bounds(tool_node, object, scene_node, time_node, centre_path);
    if (bounds.earliest > limit_) return;
    const Entry entry{bounds.earliest, tested_to,  bounds.spread, tool_node,
                      object,          scene_node, time_node};
    if (bounds.earliest <= frontier_)
      ready_.push_back(entry);
    else
      queue_.push(entry);
  }

  void expand(const Entry& e) {
    const SphereTreeNode& a = tool_.node(e.tool_node);
    const SphereTreeNode& b = scene_[static_cast<std::size_t>(e.object)].node(e.scene_node);
    const bool may_halve_time = time(e.time_node).hi - time(e.time_node).lo > kMinTimeWidth;
    const double reach = a.radius + b.radius;
    if (a.is_leaf() && b.is_leaf()) {
      if (may_halve_time && e.spread > kLeafSpreadRatio * reach)
        halve_time(e);
      else
        process_leaf_pair(e);
      return;
    }
    if (may_halve_time && e.spread > kInnerSpreadRatio * reach) {
      halve_time(e);
      return;
    }
    ToolCentrePath shared;
    if (!a.is_leaf() && (b.is_leaf() || a.radius >= b.radius)) {
      for (int child = a.first; child < a.first + 2; ++child) {
        shared.known = false;  // a new tool centre
        push_if_may_meet(child, e.object, e.scene_node, e.time_node, shared);
      }
    } else {
      for (int child = b.first; child < b.first + 2; ++child) {
        push_if_may_meet(e.tool_node, e.object, child, e.time_node, shared);
      }
    }
  }

  void halve_time(const Entry& e) {
    const int first = children_of(e.time_node);
    for (int child = first; child < first + 2; ++child) {
      ToolCentrePath centre_path;
      push_if_may_meet(e.tool_node, e.object, e.scene_node, child, centre_path);
    }
  }

  /// The triangles of a leaf pair over the entry's time node: triangle
  /// pairs, then primitive pairs, then kernels.
  void process_leaf_pair(const Entry& e) {
    const MeshFeatures& scene = scene_[static_cast<std::size_t>(e.object)];
    const LeafFeatures& tool_leaf = tool_.leaf(e.tool_node);
    const LeafFeatures& scene_leaf = scene.leaf(e.scene_node);
    const FrameChord frame = chord_of(e.time_node);  // a copy: times_ may grow

    // Tool vertices in the world; scene vertices in tool coordinates, made
    // when first needed.
    IntervalVec3 tool_boxes[LeafFeatures::kMaxVertices];
    for (int v = 0; v < tool_leaf.vertex_count; ++v)
      tool_boxes[v] = frame.world_path(tool_.vertex(tool_leaf.vertices[v])).box();
    IntervalVec3 scene_body_boxes[LeafFeatures::kMaxVertices];
    bool have_scene_body_boxes = false;
    IntervalVec3 scene_boxes[LeafFeatures::kMaxTriangles];
    for (int j = 0; j < scene_leaf.triangle_count; ++j) {
      const auto& tri = scene.triangle(scene_leaf.triangles[j]);
      Vec3 lo = scene.vertex(tri[0]), hi = lo;
      for (int c = 1; c < 3; ++c) {
        lo = lo.cwiseMin(scene.vertex(tri[static_cast<std::size_t>(c)]));
        hi = hi.cwiseMax(scene.vertex(tri[static_cast<std::size_t>(c)]));
      }
      scene_boxes[j] = {Interval(lo.x(), hi.x()), Interval(lo.y(), hi.y()),
                        Interval(lo.z(), hi.z())};
    }

    // alive[i] bit j: tool triangle i and scene triangle j may meet.
    std::uint8_t alive[LeafFeatures::kMaxTriangles] = {};
    bool any_alive = false;
    for (int i = 0; i < tool_leaf.triangle_count; ++i) {
      const IntervalVec3* corners[3] = {&tool_boxes[tool_leaf.corner[i][0]],
                                        &tool_boxes[tool_leaf.corner[i][1]],
                                        &tool_boxes[tool_leaf.corner[i][2]]};
      const IntervalVec3 box = hull(hull(*corners[0], *corners[1]), *corners[2]);
      for (int j = 0; j < scene_leaf.triangle_count; ++j) {
        if (!boxes_overlap(box, scene_boxes[j])) continue;
        if (separated_by_plane(scene.plane(scene_leaf.triangles[j]), corners)) continue;
        if (!have_scene_body_boxes) {
          for (int w = 0; w < scene_leaf.vertex_count; ++w)
            scene_body_boxes[w] = frame.body_path(scene.vertex(scene_leaf.vertices[w])).box();
          have_scene_body_boxes = true;
        }
        const IntervalVec3* scene_corners[3] = {&scene_body_boxes[scene_leaf.corner[j][0]],
                                                &scene_body_boxes[scene_leaf.corner[j][1]],
                                                &scene_body_boxes[scene_leaf.corner[j][2]]};
        if (separated_by_plane(tool_.plane(tool_leaf.triangles[i]), scene_corners)) continue;
        alive[i] = static_cast<std::uint8_t>(alive[i] | (1u << j));
        any_alive = true;
      }
    }
    if (!any_alive) return;

    for (int v = 0; v < tool_leaf.vertex_count; ++v)
      for (int j = 0; j < scene_leaf.triangle_count; ++j)
        if (any_pair_alive(alive, tool_leaf.vertex_triangles[v], 1u << j))
          tool_vertex_scene_face(e, tool_leaf.vertices[v], scene_leaf.triangles[j]);
    for (int i = 0; i < tool_leaf.triangle_count; ++i)
      for (int w = 0; w < scene_leaf.vertex_count; ++w)
        if (any_pair_alive(alive, 1u << i, scene_leaf.vertex_triangles[w]))
          scene_vertex_tool_face(e, tool_leaf.triangles[i], scene_leaf.vertices[w]);
    for (int te = 0; te < tool_leaf.edge_count; ++te)
      for (int se = 0; se < scene_leaf.edge_count; ++se)
        if (any_pair_alive(alive, tool_leaf.edge_triangles[te], scene_leaf.edge_triangles[se]))
          edge_edge(e, tool_leaf.edges[te], scene_leaf.edges[se]);
  }

  void tool_vertex_scene_face(const Entry& e, int tool_vertex, int scene_triangle) {
    const ContactFeatures features{ContactFeatureKind::kToolVertexSceneFace, e.object, tool_vertex,
                                   scene_triangle};
    if (done_.contains(features)) return;
    const MeshFeatures& scene = scene_[static_cast<std::size_t>(e.object)];
    const Vec3& vertex = tool_.vertex(tool_vertex);
    const auto& tri = scene.triangle(scene_triangle);
    const std::array<Vec3, 3> face{scene.vertex(tri[0]), scene.vertex(tri[1]),
                                   scene.vertex(tri[2])};
    const IntervalVec3 x1 = point_interval(face[0]), x2 = point_interval(face[1]),
                       x3 = point_interval(face[2]);
    if (!may_touch_during(e.time_node, [&](const FrameChord& frame) {
          const IntervalVec3 x0 = frame.world_path(vertex).box();
          return vertex_face_may_touch(x1 - x0, x2 - x0, x3 - x0);
        }))
      return;
    done_.insert(features);
    record(features, screw_vertex_face_ccd(motion_, vertex, face, kernel_settings()));
  }

  void scene_vertex_tool_face(const Entry& e, int tool_triangle, int scene_vertex) {
    const ContactFeatures features{ContactFeatureKind::kSceneVertexToolFace, e.object,
                                   tool_triangle, scene_vertex};
    if (done_.contains(features)) return;
    const Vec3& vertex = scene_[static_cast<std::size_t>(e.object)].vertex(scene_vertex);
    const auto& tri = tool_.triangle(tool_triangle);
    const std::array<Vec3, 3> face{tool_.vertex(tri[0]), tool_.vertex(tri[1]),
                                   tool_.vertex(tri[2])};
    const IntervalVec3 x1 = point_interval(face[0]), x2 = point_interval(face[1]),
                       x3 = point_interval(face[2]);
    if (!may_touch_during(e.time_node, [&](const FrameChord& frame) {
          const IntervalVec3 x0 = frame.body_path(vertex).box();
          return vertex_face_may_touch(x1 - x0, x2 - x0, x3 - x0);
        }))
      return;
    done_.insert(features);
    record(features, screw_face_vertex_ccd(motion_, face, vertex, kernel_settings()));
  }

  void edge_edge(const Entry& e, int tool_edge_index, int scene_edge_index) {
    const ContactFeatures features{ContactFeatureKind::kEdgeEdge, e.object, tool_edge_index,
                                   scene_edge_index};
    if (done_.contains(features)) return;
    const MeshFeatures& scene = scene_[static_cast<std::size_t>(e.object)];
    const auto& tool_ends = tool_.edge(tool_edge_index);
    const auto& scene_ends = scene.edge(scene_edge_index);
    const std::array<Vec3, 2> tool_edge{tool_.vertex(tool_ends[0]), tool_.vertex(tool_ends[1])};
    const std::array<Vec3, 2> scene_edge{scene.vertex(scene_ends[0]), scene.vertex(scene_ends[1])};
    const IntervalVec3 x2 = point_interval(scene_edge[0]), x3 = point_interval(scene_edge[1]);
    if (!may_touch_during(e.time_node, [&](const FrameChord& frame) {
          // The edge's direction turns without moving: its own path is tighter
          // than the difference of its ends' boxes.
          const IntervalVec3 x0 = frame.world_path(tool_edge[0]).box();
          return edge_edge_may_touch(frame.world_vector(tool_edge[1] - tool_edge[0]).box(), x2 - x0,
                                     x3 - x0);
        }))
      return;
    done_.insert(features);
    record(features, screw_edge_edge_ccd(motion_, tool_edge, scene_edge, kernel_settings()));
  }

  /// Whether `test` (given the tool frame at the ends of a span of t) cannot exclude
  /// the time node up to the limit, nor, in turn, one of its halves, down to
  /// `depth` levels below it. Earliest half first.
  template <class Test>
  bool may_touch_during(int node, const Test& test, int depth = kPretestDepth) {
    ++pretests_;
    if (!test(chord_of(node))) return false;
    if (depth == 0) return true;
    const int first = children_of(node);
    for (int child = first; child < first + 2; ++child)
      if (time(child).lo <= limit_ && may_touch_during(child, test, depth - 1)) return true;
    return false;
  }

  CcdSettings kernel_settings() const {
    CcdSettings settings = settings_.primitive;
    settings.time_limit = limit_;
    return settings;
  }

  void record(const ContactFeatures& features, const CcdResult& r) {
    ++primitive_queries_;
    primitive_evaluations_ += r.evaluations;
    budget_exhausted_ = budget_exhausted_ || r.budget_exhausted;
    if (!r.contact) return;
    MeshCcdContact contact;
    contact.features = features;
    contact.toi = r.toi;
    candidates_.push_back(contact);
    if (r.toi < best_) {
      best_ = r.toi;
      limit_ = std::min(limit_cap_, best_ + window_);
    }
  }

  MeshCcdResult finish() const {
    MeshCcdResult result;
    result.bv_tests = bv_tests_;
    result.primitive_queries = primitive_queries_;
    result.primitive_evaluations = primitive_evaluations_ + pretests_;
    result.budget_exhausted = budget_exhausted_;
    if (candidates_.empty()) return result;
    result.contact = true;
    result.toi = best_;
    for (const MeshCcdContact& c : candidates_)
      if (c.toi <= best_ + window_) result.contacts.push_back(c);
    std::stable_sort(
        result.contacts.begin(), result.contacts.end(),
        [](const MeshCcdContact& x, const MeshCcdContact& y) { return x.toi < y.toi; });
    return result;
  }

  const MeshFeatures& tool_;
  std::span<const MeshFeatures> scene_;
  const ScrewMotion& motion_;
  const FrameEnclosures frames_;
  const MeshCcdSettings& settings_;
  double limit_cap_ = 1;  // the settings' own time limit
  double limit_ = 1;      // no time after it is searched
  double window_ = 0;
  double best_ = std::numeric_limits<double>::infinity();
  std::vector<TimeNode> times_;
  std::priority_queue<Entry, std::vector<Entry>, Later> queue_;
  std::vector<Entry> ready_;  // entries no later than frontier_, taken last in first out
  double frontier_ = 0;       // the start of the entry last taken from queue_
  std::unordered_set<ContactFeatures, ContactFeaturesHash> done_;  // kernels run
  std::vector<MeshCcdContact> candidates_;
  std::int64_t bv_tests_ = 0, primitive_queries_ = 0, primitive_evaluations_ = 0, pretests_ = 0;
  bool budget_exhausted_ = false;
};

}  // namespace

MeshCcdResult search_first_contact(const MeshFeatures& tool, std::span<const MeshFeatures> scene,
                                   const ScrewMotion& motion, const MeshCcdSettings& settings) {
  return FirstContactSearch(tool, scene, motion, settings).run();
}

}  // namespace hb::ccd_detail
