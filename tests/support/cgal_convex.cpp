#include "tests/support/cgal_convex.h"

#include <CGAL/Gmpzf.h>
#include <CGAL/Homogeneous.h>
#include <CGAL/Polytope_distance_d.h>
#include <CGAL/Polytope_distance_d_traits_3.h>

#include <stdexcept>

namespace hb::test {

namespace {

using Kernel = CGAL::Homogeneous<double>;
using Traits = CGAL::Polytope_distance_d_traits_3<Kernel, CGAL::Gmpzf, double>;
using Distance = CGAL::Polytope_distance_d<Traits>;
using Point = Kernel::Point_3;

std::vector<Point> points(const std::vector<Vec3>& v) {
  std::vector<Point> out;
  out.reserve(v.size());
  for (const Vec3& x : v) out.emplace_back(x.x(), x.y(), x.z(), 1.0);
  return out;
}

Distance solve(const std::vector<Vec3>& p, const std::vector<Vec3>& q) {
  if (p.empty() || q.empty()) throw std::invalid_argument("empty point set");
  const std::vector<Point> pp = points(p), qq = points(q);
  return Distance(pp.begin(), pp.end(), qq.begin(), qq.end());
}

}  // namespace

double cgal_hull_squared_distance(const std::vector<Vec3>& p, const std::vector<Vec3>& q) {
  const Distance d = solve(p, q);
  return CGAL::to_double(d.squared_distance_numerator()) /
         CGAL::to_double(d.squared_distance_denominator());
}

bool cgal_hulls_intersect(const std::vector<Vec3>& p, const std::vector<Vec3>& q) {
  return CGAL::is_zero(solve(p, q).squared_distance_numerator());
}

}  // namespace hb::test
