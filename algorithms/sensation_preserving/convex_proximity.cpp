// Proximity of two convex pieces: GJK decides overlap and measures gaps
// (gjk.h), the least-translation normal of an overlap comes from EPA and
// libccd (epa_penetration.h), and the contact point from the overlap of
// the pieces' extreme features along the normal (contact_features.h).
#include "algorithms/sensation_preserving/convex_proximity.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "algorithms/sensation_preserving/contact_features.h"
#include "algorithms/sensation_preserving/convex_body.h"
#include "algorithms/sensation_preserving/epa_penetration.h"
#include "algorithms/sensation_preserving/gjk.h"
#include "hapticbench/input_error.h"

namespace hb {

namespace {

using namespace convex_detail;

void fill_contact(const Body& a, const Body& b, const Vec3& n, double scale,
                  ConvexProximity& result) {
  const Vec3 na = a.rotation.transpose() * n, nb = b.rotation.transpose() * n;
  const double offset_a = n.dot(a.translation), offset_b = n.dot(b.translation);
  double a_max = -std::numeric_limits<double>::infinity();
  double b_min = std::numeric_limits<double>::infinity();
  for (const Vec3& v : a.vertices) a_max = std::max(a_max, na.dot(v) + offset_a);
  for (const Vec3& v : b.vertices) b_min = std::min(b_min, nb.dot(v) + offset_b);

  // An orthonormal basis (u, w) of the plane perpendicular to n.
  const Vec3 helper = std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 u = n.cross(helper).normalized();
  const Vec3 w = n.cross(u);
  const double feature_tolerance = kFeatureTolerance * scale;
  // Kept between calls (per thread): a warm query allocates nothing.
  thread_local std::vector<Vec2> pa, pb;
  thread_local Feature2 fa, fb;
  pa.clear();
  pb.clear();
  Vec3 mean_a = Vec3::Zero(), mean_b = Vec3::Zero();
  for (std::size_t i = 0; i < a.vertices.size(); ++i) {
    if (na.dot(a.vertices[i]) + offset_a < a_max - feature_tolerance) continue;
    const Vec3 x = a.world(i);
    pa.emplace_back(u.dot(x), w.dot(x));
    mean_a += x;
  }
  for (std::size_t i = 0; i < b.vertices.size(); ++i) {
    if (nb.dot(b.vertices[i]) + offset_b > b_min + feature_tolerance) continue;
    const Vec3 x = b.world(i);
    pb.emplace_back(u.dot(x), w.dot(x));
    mean_b += x;
  }
  const double planar_tolerance = kPlanarTolerance * scale;
  Vec2 centre;
  make_feature(pa, planar_tolerance, fa);
  make_feature(pb, planar_tolerance, fb);
  if (!overlap_centre(fa, fb, planar_tolerance, centre)) {
    const Vec3 mid =
        0.5 * (mean_a / static_cast<double>(pa.size()) + mean_b / static_cast<double>(pb.size()));
    centre = Vec2(u.dot(mid), w.dot(mid));
  }
  result.in_contact = true;
  result.normal = n;
  result.signed_depth = a_max - b_min;
  result.point = centre.x() * u + centre.y() * w + 0.5 * (a_max + b_min) * n;
}

void check_piece(const PlacedConvex& c, const char* name) {
  if (c.vertices.empty()) throw InputError("", name, "a convex piece needs at least one vertex");
  for (const Vec3& v : c.vertices)
    if (!v.allFinite()) throw InputError("", name, "non-finite vertex coordinate");
  if (!is_finite(c.pose)) throw InputError("", name, "non-finite pose");
}

double common_scale(const Body& a, const Body& b) {
  return std::max({a.extent(), b.extent(), std::numeric_limits<double>::min()});
}

}  // namespace

ConvexProximity convex_proximity(const PlacedConvex& a, const PlacedConvex& b, double margin_m) {
  check_piece(a, "convex piece a");
  check_piece(b, "convex piece b");
  if (!(margin_m >= 0) || !std::isfinite(margin_m))
    throw InputError("", "contact margin", "expected a finite margin >= 0 m");
  const Body body_a(a), body_b(b);
  const double scale = common_scale(body_a, body_b);
  ConvexProximity result;
  // Own GJK decides overlap (libccd's GJK misses some overlaps of thin
  // pieces) and measures the gap of separated pieces.
  const GjkResult g = gjk(body_a, body_b, scale, margin_m);
  if (g.distance > 0) {
    if (g.distance < margin_m)
      fill_contact(body_a, body_b, (g.on_b - g.on_a) / g.distance, scale, result);
    return result;
  }
  fill_contact(body_a, body_b, penetration_normal(body_a, body_b, g, scale), scale, result);
  return result;
}

bool convex_apart(const PlacedConvex& a, const PlacedConvex& b, double margin_m, Vec3* axis) {
  const Body body_a(a), body_b(b);
  const GjkResult g = gjk(body_a, body_b, common_scale(body_a, body_b), margin_m);
  const bool apart = g.distance > margin_m;
  if (apart && axis != nullptr) *axis = g.direction.normalized();
  return apart;
}

double separation_along(const PlacedConvex& a, const PlacedConvex& b, const Vec3& axis) {
  return -separating_translation(Body(a), Body(b), axis);
}

double convex_distance(const PlacedConvex& a, const PlacedConvex& b) {
  check_piece(a, "convex piece a");
  check_piece(b, "convex piece b");
  const Body body_a(a), body_b(b);
  return gjk(body_a, body_b, common_scale(body_a, body_b)).distance;
}

}  // namespace hb
