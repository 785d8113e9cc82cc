#include "algorithms/sensation_preserving/convex_hull.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Projection_traits_xy_3.h>
#include <CGAL/Projection_traits_xz_3.h>
#include <CGAL/Projection_traits_yz_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/convex_hull_3_to_face_graph.h>

#include <algorithm>
#include <cstddef>
#include <iterator>

namespace hb {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Surface = CGAL::Surface_mesh<Point>;

Point to_point(const Vec3& v) { return Point(v.x(), v.y(), v.z()); }
Vec3 to_vec(const Point& p) { return Vec3(p.x(), p.y(), p.z()); }

// The hull polygon of coplanar points in the coordinate plane where three
// of them (not collinear) do not project onto a line; boundary order.
template <class Traits>
std::vector<Point> polygon_in(const std::vector<Point>& points) {
  std::vector<Point> polygon;
  CGAL::convex_hull_2(points.begin(), points.end(), std::back_inserter(polygon), Traits());
  return polygon;
}

std::vector<Point> coplanar_hull(const std::vector<Point>& points, const Point& a, const Point& b,
                                 const Point& c) {
  using Xy = CGAL::Projection_traits_xy_3<Kernel>;
  using Yz = CGAL::Projection_traits_yz_3<Kernel>;
  using Xz = CGAL::Projection_traits_xz_3<Kernel>;
  if (!Xy().collinear_2_object()(a, b, c)) return polygon_in<Xy>(points);
  if (!Yz().collinear_2_object()(a, b, c)) return polygon_in<Yz>(points);
  return polygon_in<Xz>(points);
}

ConvexPolytope flat_polytope(const std::vector<Point>& polygon) {
  ConvexPolytope result;
  result.dimension = 2;
  for (const Point& p : polygon) result.vertices.push_back(to_vec(p));
  const int n = static_cast<int>(result.vertices.size());
  for (int i = 1; i + 1 < n; ++i) result.triangles.push_back({0, i, i + 1});
  for (int i = 1; i + 1 < n; ++i) result.triangles.push_back({0, i + 1, i});
  return result;
}

}  // namespace

ConvexPolytope convex_hull(std::span<const Vec3> points) {
  ConvexPolytope result;
  if (points.empty()) return result;
  // Exact repeats removed (quickhull is given distinct points only).
  std::vector<Point> input;
  input.reserve(points.size());
  for (const Vec3& v : points) input.push_back(to_point(v));
  std::sort(input.begin(), input.end());
  input.erase(std::unique(input.begin(), input.end()), input.end());

  // The dimension of the point set, by exact predicates.
  const Point& a = input[0];
  if (input.size() == 1) {
    result.dimension = 0;
    result.vertices.push_back(to_vec(a));
    return result;
  }
  const Point& b = input[1];
  std::size_t j = 2;
  while (j < input.size() && CGAL::collinear(a, b, input[j])) ++j;
  if (j == input.size()) {
    // A segment: the sorted order runs along the line.
    result.dimension = 1;
    result.vertices = {to_vec(input.front()), to_vec(input.back())};
    return result;
  }
  const Point& c = input[j];
  std::size_t k = j + 1;
  while (k < input.size() && CGAL::coplanar(a, b, c, input[k])) ++k;
  if (k == input.size()) return flat_polytope(coplanar_hull(input, a, b, c));

  // The hull of a Delaunay triangulation, not CGAL 5.5's quickhull
  // (convex_hull_3): on some of the nearly flat point sets a surface
  // decomposition produces, quickhull reads a list node it has freed (found
  // by valgrind's memcheck), so its hull depended on the heap's history.
  const CGAL::Delaunay_triangulation_3<Kernel> triangulation(input.begin(), input.end());
  Surface hull;
  CGAL::convex_hull_3_to_face_graph(triangulation, hull);
  result.dimension = 3;
  std::vector<int> index(hull.num_vertices(), -1);
  for (const Surface::Vertex_index v : hull.vertices()) {
    index[v.idx()] = static_cast<int>(result.vertices.size());
    result.vertices.push_back(to_vec(hull.point(v)));
  }
  result.triangles.reserve(hull.number_of_faces());
  std::vector<int> corners;
  for (const Surface::Face_index f : hull.faces()) {
    corners.clear();
    for (const Surface::Vertex_index v : CGAL::vertices_around_face(hull.halfedge(f), hull))
      corners.push_back(index[v.idx()]);
    for (std::size_t i = 1; i + 1 < corners.size(); ++i)
      result.triangles.push_back({corners[0], corners[i], corners[i + 1]});
  }
  return result;
}

}  // namespace hb
