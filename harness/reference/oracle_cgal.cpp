// The CGAL ground-truth backend: exact-predicate inside/outside
// (Side_of_triangle_mesh), AABB-tree closest points, and the exact volume of
// a tool's intersection with the scene by corefinement. Every CGAL header of
// the reference stays in this file. Coordinates are metres, world frame.
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Intersections_3/Bbox_3_Iso_cuboid_3.h>
#include <CGAL/Intersections_3/Iso_cuboid_3_Triangle_3.h>
#include <CGAL/Intersections_3/Segment_3_Segment_3.h>
#include <CGAL/Intersections_3/Segment_3_Triangle_3.h>
#include <CGAL/Intersections_3/Triangle_3_Triangle_3.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <exception>
#include <iterator>
#include <limits>
#include <sstream>
#include <utility>

#include "algorithms/core/build_progress.h"
#include "hapticbench/closest_points.h"
#include "hapticbench/input_error.h"
#include "harness/reference/oracle.h"

namespace hb {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;

// Exact predicates, inexact (double) constructions: every decision
// (inside/outside, which side of a plane, whether triangles cross) is exact;
// constructed points (closest points, corefinement vertices) are rounded to
// double.
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Box = Kernel::Iso_cuboid_3;
using Mesh = CGAL::Surface_mesh<Point>;
using SideOfMesh = CGAL::Side_of_triangle_mesh<Mesh, Kernel>;
using FaceTree = SideOfMesh::AABB_tree;
using SoupIterator = std::vector<Triangle>::const_iterator;
using SoupTree =
    CGAL::AABB_tree<CGAL::AABB_traits<Kernel, CGAL::AABB_triangle_primitive<Kernel, SoupIterator>>>;

Point to_point(const Vec3& v) { return Point(v.x(), v.y(), v.z()); }
Vec3 to_vec3(const Point& p) { return Vec3(p.x(), p.y(), p.z()); }

// The mesh as a CGAL halfedge mesh, or nullopt when a face cannot be added
// (a non-manifold edge or vertex). Every vertex is added, in order, so vertex
// i of the mesh is vertex i of the result.
std::optional<Mesh> to_surface_mesh(const TriangleMesh& mesh) {
  Mesh result;
  result.reserve(static_cast<Mesh::size_type>(mesh.vertices.size()),
                 static_cast<Mesh::size_type>(mesh.triangles.size() * 3 / 2),
                 static_cast<Mesh::size_type>(mesh.triangles.size()));
  for (const Vec3& v : mesh.vertices) result.add_vertex(to_point(v));
  for (const auto& [a, b, c] : mesh.triangles) {
    const auto face = result.add_face(Mesh::Vertex_index(static_cast<Mesh::size_type>(a)),
                                      Mesh::Vertex_index(static_cast<Mesh::size_type>(b)),
                                      Mesh::Vertex_index(static_cast<Mesh::size_type>(c)));
    if (face == Mesh::null_face()) return std::nullopt;
  }
  return result;
}

// How the triangles use the mesh's undirected edges.
struct EdgeCounts {
  int64_t border = 0;        // used by one triangle
  int64_t non_manifold = 0;  // used by more than two
  int64_t inconsistent = 0;  // used by two that traverse it in the same direction
};

EdgeCounts count_edges(const TriangleMesh& mesh) {
  // One entry per triangle corner: the undirected edge it starts, in the
  // high bits, and whether the triangle traverses it from the smaller to
  // the larger index, in the lowest bit. Sorting groups the uses of an edge.
  std::vector<uint64_t> uses;
  uses.reserve(mesh.triangles.size() * 3);
  for (const auto& triangle : mesh.triangles) {
    for (int corner = 0; corner < 3; ++corner) {
      const auto a = static_cast<uint64_t>(triangle[corner]);
      const auto b = static_cast<uint64_t>(triangle[(corner + 1) % 3]);
      const uint64_t edge = (std::min(a, b) << 32) | std::max(a, b);
      uses.push_back((edge << 1) | (a < b ? 1 : 0));
    }
  }
  std::sort(uses.begin(), uses.end());
  EdgeCounts counts;
  for (std::size_t first = 0; first < uses.size();) {
    std::size_t last = first;
    int forward = 0;
    while (last < uses.size() && (uses[last] >> 1) == (uses[first] >> 1)) {
      forward += static_cast<int>(uses[last] & 1);
      ++last;
    }
    const std::size_t count = last - first;
    if (count == 1) ++counts.border;
    if (count > 2) ++counts.non_manifold;
    if (count == 2 && forward != 1) ++counts.inconsistent;
    first = last;
  }
  return counts;
}

// Vertices where two or more sheets of surface touch (e.g. two cones tip to
// tip). Assumes every edge is shared by exactly two consistently oriented
// triangles: then the triangles around a vertex v map each neighbour to the
// next (triangle (v, a, b) maps a to b), this map is a permutation of the
// neighbours, and v is manifold exactly when it is a single cycle.
int64_t count_non_manifold_vertices(const TriangleMesh& mesh) {
  const std::size_t n = mesh.vertices.size();
  std::vector<std::size_t> start(n + 1, 0);
  for (const auto& triangle : mesh.triangles)
    for (int v : triangle) ++start[static_cast<std::size_t>(v) + 1];
  for (std::size_t v = 0; v < n; ++v) start[v + 1] += start[v];
  std::vector<std::pair<int, int>> next(start[n]);  // (neighbour, next neighbour) around v
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (const auto& [a, b, c] : mesh.triangles) {
    next[fill[static_cast<std::size_t>(a)]++] = {b, c};
    next[fill[static_cast<std::size_t>(b)]++] = {c, a};
    next[fill[static_cast<std::size_t>(c)]++] = {a, b};
  }
  int64_t non_manifold = 0;
  for (std::size_t v = 0; v < n; ++v) {
    const auto first = next.begin() + static_cast<std::ptrdiff_t>(start[v]);
    const auto last = next.begin() + static_cast<std::ptrdiff_t>(start[v + 1]);
    if (first == last) continue;
    std::sort(first, last);
    const std::size_t degree = start[v + 1] - start[v];
    std::size_t cycle_length = 1;
    int current = first->second;
    while (current != first->first && cycle_length <= degree) {
      const auto step =
          std::lower_bound(first, last, std::make_pair(current, 0),
                           [](const auto& x, const auto& y) { return x.first < y.first; });
      if (step == last || step->first != current) break;  // not a permutation: counted elsewhere
      current = step->second;
      ++cycle_length;
    }
    if (cycle_length != degree) ++non_manifold;
  }
  return non_manifold;
}

// Enclosed volume (m³) of a closed, consistently oriented mesh, from
// tetrahedra on the bounding-box centre so a mesh far from the origin keeps
// its precision.
double enclosed_volume(const TriangleMesh& mesh) {
  const Vec3 origin = mesh.bounds().center();
  double six_volume = 0;
  for (const auto& [a, b, c] : mesh.triangles) {
    six_volume += (mesh.vertices[a] - origin)
                      .dot((mesh.vertices[b] - origin).cross(mesh.vertices[c] - origin));
  }
  return six_volume / 6;
}

std::string count_text(int64_t count, const std::string& singular, const std::string& plural) {
  return std::to_string(count) + " " + (count == 1 ? singular : plural);
}

std::string format_number(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

std::string with_advice(const std::string& why) {
  return why +
         "; inside/outside would be meaningless (mark the object \"distance_only\": true to use "
         "it for distances only)";
}

// Indices in range and finite coordinates: what the mesh must have before
// CGAL may read it.
bool is_readable(const TriangleMesh& mesh) {
  const auto vertex_count = static_cast<long long>(mesh.vertices.size());
  for (const auto& triangle : mesh.triangles)
    for (int v : triangle)
      if (v < 0 || v >= vertex_count) return false;
  return std::all_of(mesh.vertices.begin(), mesh.vertices.end(),
                     [](const Vec3& v) { return v.allFinite(); });
}

// A closed scene object: its world-frame mesh, the AABB tree of its faces,
// and the exact inside/outside classifier on that tree. Never moved once
// built: the tree points into the mesh and the classifier into the tree.
struct SolidObject {
  explicit SolidObject(Mesh world_mesh)
      : mesh(std::move(world_mesh)), tree(faces(mesh).first, faces(mesh).second, mesh) {
    tree.build();
    side = std::make_unique<SideOfMesh>(tree);
  }
  Mesh mesh;
  FaceTree tree;
  std::unique_ptr<SideOfMesh> side;
};

class CgalOracle final : public Oracle {
 public:
  explicit CgalOracle(const std::vector<SceneObject>& scene) {
    std::size_t triangle_count = 0;
    for (const SceneObject& object : scene) triangle_count += object.mesh.triangles.size();
    soup_.reserve(triangle_count);
    soup_object_.reserve(triangle_count);
    soup_normal_.reserve(triangle_count);
    solids_.resize(scene.size());
    object_bounds_.resize(scene.size());

    for (std::size_t i = 0; i < scene.size(); ++i) {
      const SceneObject& object = scene[i];
      const std::string location = "/scene/" + std::to_string(i);
      const TriangleMesh world = transformed(object.mesh, object.pose);
      if (object.distance_only) {
        // Open or self-intersecting is allowed, but the triangles must still
        // be readable: indices in range, finite, not degenerate.
        if (auto defect = find_mesh_defect(world, MeshRequirement::kSurface))
          throw InputError(object.name, location, defect->location + ": " + defect->message);
        distance_only_.push_back(object.name);
      } else {
        if (auto why = inside_outside_defect(world))
          throw InputError(object.name, location, with_advice(*why));
        check_build_stop();
        std::optional<Mesh> mesh = to_surface_mesh(world);
        if (!mesh) throw InputError(object.name, location, with_advice("non-manifold"));
        check_build_stop();
        solids_[i] = std::make_unique<SolidObject>(std::move(*mesh));
        check_build_stop();
      }
      object_bounds_[i] = world.bounds();
      bounds_.extend(object_bounds_[i]);
      for (std::size_t t = 0; t < world.triangles.size(); ++t) {
        const auto& [a, b, c] = world.triangles[t];
        soup_.emplace_back(to_point(world.vertices[a]), to_point(world.vertices[b]),
                           to_point(world.vertices[c]));
        soup_object_.push_back(static_cast<int32_t>(i));
        soup_normal_.push_back(world.face_normal(t));
      }
    }
    // One tree over the triangles of every object: the nearest triangle of
    // the whole scene in one traversal, which is the minimum over objects.
    if (!soup_.empty()) {
      soup_tree_.insert(soup_.begin(), soup_.end());
      check_build_stop();
      soup_tree_.build();
      check_build_stop();
      soup_tree_.accelerate_distance_queries();
    }
  }

  std::string_view name() const override { return "cgal"; }

  void query_points(const PointQueryRequest& request, PointQueryResult& result) const override {
    const std::size_t n = request.points.size();
    if (request.want_inside) {
      result.inside.assign(n, 0);
      for (std::size_t k = 0; k < n; ++k) {
        // A non-finite point (a diverged proxy) is inside nothing; exact
        // predicates must never see it.
        const Vec3& p = request.points[k];
        result.inside[k] = p.allFinite() && is_inside(p) ? 1 : 0;
      }
    }
    if (request.want_closest) {
      result.resize_closest(n);
      for (std::size_t k = 0; k < n; ++k) {
        const Vec3& p = request.points[k];
        if (soup_.empty() || !p.allFinite()) {  // nothing to be close to, or no point
          result.distance[k] = soup_.empty() ? std::numeric_limits<double>::infinity()
                                             : std::numeric_limits<double>::quiet_NaN();
          result.closest[k] = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
          result.normal[k] = Vec3::Zero();
          result.object[k] = -1;
          continue;
        }
        const auto [closest, triangle] = soup_tree_.closest_point_and_primitive(to_point(p));
        const auto t = static_cast<std::size_t>(triangle - soup_.begin());
        result.closest[k] = to_vec3(closest);
        result.distance[k] = (p - result.closest[k]).norm();
        result.normal[k] = soup_normal_[t];
        result.object[k] = soup_object_[t];
      }
    }
  }

  bool triangles_within(const Vec3& point, double radius_m,
                        std::vector<NearTriangle>& out) const override {
    out.clear();
    if (soup_.empty() || !point.allFinite() || !(radius_m >= 0)) return true;
    // The triangles meeting the sphere's bounding box (exact predicates),
    // then the sphere itself by the distance in double.
    const Vec3 reach = Vec3::Constant(radius_m);
    const Box box(to_point(point - reach), to_point(point + reach));
    std::vector<SoupIterator> candidates;
    soup_tree_.all_intersected_primitives(box, std::back_inserter(candidates));
    for (const SoupIterator triangle : candidates) {
      const std::array<Vec3, 3> corners = {
          to_vec3(triangle->vertex(0)), to_vec3(triangle->vertex(1)), to_vec3(triangle->vertex(2))};
      const Vec3 closest = closest_point_on_triangle(point, corners[0], corners[1], corners[2]);
      const double distance = (closest - point).norm();
      if (!(distance <= radius_m)) continue;
      const auto t = static_cast<std::size_t>(triangle - soup_.begin());
      out.push_back({closest, distance, soup_object_[t], corners});
    }
    return true;
  }

  std::optional<double> intersection_volume(const TriangleMesh& tool_in_world) const override {
    if (!is_readable(tool_in_world)) return std::nullopt;
    const Eigen::AlignedBox3d tool_bounds = tool_in_world.bounds();
    // Corefinement can throw on degenerate or self-intersecting input
    // (CGAL::Failure_exception, Corefinement::Self_intersection_exception):
    // that is "cannot compute" (nullopt), never a crash.
    try {
      std::optional<Mesh> tool;
      double volume = 0;
      // Scene objects are assumed not to overlap one another, so the volume
      // inside their union is the sum of the volumes inside each.
      for (std::size_t i = 0; i < solids_.size(); ++i) {
        if (!object_bounds_[i].intersects(tool_bounds)) continue;  // contributes 0
        if (!solids_[i]) return std::nullopt;                      // distance-only object
        if (!tool) {
          tool = to_surface_mesh(tool_in_world);
          if (!tool || !CGAL::is_closed(*tool)) return std::nullopt;
        }
        // Corefinement cuts both inputs: work on copies.
        Mesh tool_copy = *tool;
        Mesh object_copy = solids_[i]->mesh;
        Mesh intersection;
        if (!PMP::corefine_and_compute_intersection(
                tool_copy, object_copy, intersection,
                CGAL::parameters::throw_on_self_intersection(true))) {
          return std::nullopt;
        }
        volume += PMP::volume(intersection);
      }
      return volume;
    } catch (const std::exception&) {
      return std::nullopt;
    }
  }

  const std::vector<std::string>& distance_only_objects() const override { return distance_only_; }

  Eigen::AlignedBox3d bounds() const override { return bounds_; }

 private:
  // Inside any closed object. A point on an object's surface (ON_BOUNDARY)
  // counts as inside: a tool touching the scene is in contact.
  bool is_inside(const Vec3& p) const {
    const Point point = to_point(p);
    for (const auto& solid : solids_) {
      if (solid && (*solid->side)(point) != CGAL::ON_UNBOUNDED_SIDE) return true;
    }
    return false;
  }

  std::vector<std::unique_ptr<SolidObject>> solids_;  // null for distance-only objects
  std::vector<Eigen::AlignedBox3d> object_bounds_;    // world frame, m
  std::vector<Triangle> soup_;                        // every scene triangle, world frame
  std::vector<int32_t> soup_object_;                  // object of each soup triangle
  std::vector<Vec3> soup_normal_;                     // outward unit normal of each
  SoupTree soup_tree_;
  std::vector<std::string> distance_only_;
  Eigen::AlignedBox3d bounds_;
};

}  // namespace

std::optional<std::string> inside_outside_defect(const TriangleMesh& mesh) {
  // Readable triangles first: indices in range, finite coordinates, no
  // degenerate or duplicate triangles.
  if (auto defect = find_mesh_defect(mesh, MeshRequirement::kSurface))
    return defect->location + ": " + defect->message;

  // A stop request is heeded between the stages (each a pass over the mesh;
  // the self-intersection test of a million triangles takes seconds).
  check_build_stop();
  const EdgeCounts edges = count_edges(mesh);
  if (edges.border > 0)
    return "open boundary (" + count_text(edges.border, "border edge", "border edges") + ")";
  if (edges.non_manifold > 0) {
    return "non-manifold (" + count_text(edges.non_manifold, "edge", "edges") +
           " shared by more than two triangles)";
  }
  if (edges.inconsistent > 0) {
    return "inconsistently oriented (" + count_text(edges.inconsistent, "edge", "edges") +
           " traversed in the same direction by both its triangles)";
  }
  if (const int64_t vertices = count_non_manifold_vertices(mesh); vertices > 0) {
    return "non-manifold (" + count_text(vertices, "vertex", "vertices") +
           " where separate sheets of surface touch)";
  }
  if (const double volume = enclosed_volume(mesh); !(volume > 0)) {
    return "inside-out (enclosed volume " + format_number(volume) +
           " m^3; triangles must be counter-clockwise seen from outside)";
  }

  check_build_stop();
  std::optional<Mesh> surface = to_surface_mesh(mesh);
  if (!surface) return "non-manifold";
  check_build_stop();
  // Exact predicates: triangles that merely share an edge or a vertex do
  // not count; any other contact or crossing does.
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
  PMP::self_intersections(*surface, std::back_inserter(pairs));
  if (!pairs.empty()) {
    return "self-intersecting (" +
           count_text(static_cast<int64_t>(pairs.size()), "intersecting triangle pair",
                      "intersecting triangle pairs") +
           ")";
  }
  return std::nullopt;
}

bool triangles_intersect(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) {
  if (!(a[0].allFinite() && a[1].allFinite() && a[2].allFinite() && b[0].allFinite() &&
        b[1].allFinite() && b[2].allFinite()))
    return false;  // exact predicates must never see a non-finite coordinate
  const Triangle first(to_point(a[0]), to_point(a[1]), to_point(a[2]));
  const Triangle second(to_point(b[0]), to_point(b[1]), to_point(b[2]));
  // A degenerate triangle is a segment or a point: CGAL's triangle test
  // requires proper triangles, so those go through their edges.
  const auto as_segments = [](const Triangle& t) {
    return std::array<Kernel::Segment_3, 3>{Kernel::Segment_3(t.vertex(0), t.vertex(1)),
                                            Kernel::Segment_3(t.vertex(1), t.vertex(2)),
                                            Kernel::Segment_3(t.vertex(2), t.vertex(0))};
  };
  const bool first_degenerate = first.is_degenerate(), second_degenerate = second.is_degenerate();
  if (!first_degenerate && !second_degenerate) return CGAL::do_intersect(first, second);
  if (first_degenerate && second_degenerate) {
    for (const auto& s : as_segments(first))
      for (const auto& t : as_segments(second))
        if (CGAL::do_intersect(s, t)) return true;
    return false;
  }
  const Triangle& proper = first_degenerate ? second : first;
  for (const auto& s : as_segments(first_degenerate ? first : second))
    if (CGAL::do_intersect(s, proper)) return true;
  return false;
}

std::unique_ptr<Oracle> make_cgal_oracle(const std::vector<SceneObject>& scene) {
  return std::make_unique<CgalOracle>(scene);
}

}  // namespace hb
