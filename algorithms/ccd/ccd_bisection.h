// The engine shared by the linear and the screw-motion CCD kernels: the
// interval tests that can prove "no contact during this sub-interval of t",
// and the earliest-first bisection of [0, 1] built on them.
//
// Both kernels describe the four points x0..x3 of a primitive pair over a
// time interval T by three relative vectors e_i(T) ⊇ {x_i(t) − x0(t) : t ∈ T}
// (world frame, m). Each test below is a necessary condition of contact at
// some t ∈ T, evaluated in interval arithmetic, so when one is certainly
// violated no t ∈ T is a contact.
//
// With c1 = e1 × e2, c2 = e2 × e3, c3 = e3 × e1 (the slides' coplanarity
// function is f = (x1 − x0) · ((x2 − x0) × (x3 − x0)) = e1 · c2):
//
// Vertex x0 against triangle (x1, x2, x3). At a contact the vertex is
// αx1 + βx2 + γx3 with α, β, γ ≥ 0 summing to 1, i.e. αe1 + βe2 + γe3 = 0.
// Then f = 0, and with the face normal n = (x2 − x1) × (x3 − x1) =
// c1 + c2 + c3: c1 = γn, c2 = αn, c3 = βn (the barycentric areas), so each
// component of every c_i lies in hull(0, n_k); and the origin lies in the
// bounding box of e1, e2, e3.
//
// Edge (x0, x1) against edge (x2, x3). At a contact x0 + s e1 = x2 +
// u (x3 − x2) with s, u ∈ [0, 1]. Then f = 0, and with the normal of the two
// directions n = e1 × (e3 − e2) = −(c1 + c3): c1 = −u n, c3 = −(1 − u) n,
// c2 = s n and c1 + c2 + c3 = −(1 − s) n, so each component of −c1, c2, −c3
// and −(c1 + c2 + c3) lies in hull(0, n_k); and the segments' bounding
// boxes overlap.
//
// The sign conditions c_i · n ≥ 0 (and their edge–edge counterparts) follow
// from these componentwise conditions and are not tested. Degenerate input
// needs no special case: a degenerate triangle or parallel edges (n = 0)
// force every c_i to 0 (collinear points, whose overlap the box test then
// decides); a motion that keeps the points coplanar leaves f ≡ 0 and the
// other tests decide; what no test excludes is reported as a contact.
#pragma once

#include <algorithm>

#include "algorithms/ccd/ccd_settings.h"
#include "algorithms/ccd/interval.h"

namespace hb::ccd_detail {

/// Some c ∈ C equals λ n for some n ∈ N and λ ∈ [0, 1]: C meets hull(0, N).
/// Compares bounds only, so no rounding is involved.
inline bool may_be_fraction_of(const Interval& c, const Interval& n) {
  return c.lo <= std::max(0.0, n.hi) && c.hi >= std::min(0.0, n.lo);
}

/// As may_be_fraction_of for −c: C meets hull(0, −N).
inline bool may_be_negative_fraction_of(const Interval& c, const Interval& n) {
  return c.hi >= std::min(0.0, -n.hi) && c.lo <= std::max(0.0, -n.lo);
}

/// The three cross products of the relative vectors.
struct RelativeCrossProducts {
  IntervalVec3 c1, c2, c3;  // e1 × e2, e2 × e3, e3 × e1 (m²)
};

inline RelativeCrossProducts relative_cross_products(const IntervalVec3& e1, const IntervalVec3& e2,
                                                     const IntervalVec3& e3) {
  return {cross(e1, e2), cross(e2, e3), cross(e3, e1)};
}

/// Vertex–face: the origin (the vertex) may lie in the bounding box of the
/// triangle's relative vertices.
inline bool vertex_face_boxes_may_meet(const IntervalVec3& e1, const IntervalVec3& e2,
                                       const IntervalVec3& e3) {
  for (int k = 0; k < 3; ++k) {
    const Interval &a = e1[k], &b = e2[k], &c = e3[k];
    if (std::min(std::min(a.lo, b.lo), c.lo) > 0) return false;
    if (std::max(std::max(a.hi, b.hi), c.hi) < 0) return false;
  }
  return true;
}

/// Vertex–face: the barycentric-area conditions c_i ∈ hull(0, n).
inline bool vertex_face_areas_may_hold(const RelativeCrossProducts& c) {
  const IntervalVec3 n = c.c1 + c.c2 + c.c3;
  for (int k = 0; k < 3; ++k) {
    if (!may_be_fraction_of(c.c1[k], n[k]) || !may_be_fraction_of(c.c2[k], n[k]) ||
        !may_be_fraction_of(c.c3[k], n[k]))
      return false;
  }
  return true;
}

/// Edge–edge: the bounding boxes of segment (0, e1) and segment (e2, e3)
/// may overlap.
inline bool edge_edge_boxes_may_meet(const IntervalVec3& e1, const IntervalVec3& e2,
                                     const IntervalVec3& e3) {
  for (int k = 0; k < 3; ++k) {
    const Interval &a = e1[k], &b = e2[k], &c = e3[k];
    if (std::max(0.0, a.hi) < std::min(b.lo, c.lo)) return false;
    if (std::min(0.0, a.lo) > std::max(b.hi, c.hi)) return false;
  }
  return true;
}

/// Edge–edge: the segment-parameter conditions (u, 1 − u, s, 1 − s ∈ [0, 1]).
inline bool edge_edge_parameters_may_hold(const RelativeCrossProducts& c) {
  const IntervalVec3 n = -(c.c1 + c.c3);
  const IntervalVec3 sum = c.c1 + c.c2 + c.c3;
  for (int k = 0; k < 3; ++k) {
    if (!may_be_negative_fraction_of(c.c1[k], n[k]) || !may_be_fraction_of(c.c2[k], n[k]) ||
        !may_be_negative_fraction_of(c.c3[k], n[k]) || !may_be_negative_fraction_of(sum[k], n[k]))
      return false;
  }
  return true;
}

/// Every vertex–face test on relative vectors bounded over T, the
/// coplanarity function evaluated directly as e1 · (e2 × e3).
inline bool vertex_face_may_touch(const IntervalVec3& e1, const IntervalVec3& e2,
                                  const IntervalVec3& e3) {
  if (!vertex_face_boxes_may_meet(e1, e2, e3)) return false;
  const RelativeCrossProducts c = relative_cross_products(e1, e2, e3);
  if (dot(e1, c.c2).excludes_zero()) return false;
  return vertex_face_areas_may_hold(c);
}

/// Every edge–edge test on relative vectors bounded over T, the
/// coplanarity function evaluated directly as e1 · (e2 × e3).
inline bool edge_edge_may_touch(const IntervalVec3& e1, const IntervalVec3& e2,
                                const IntervalVec3& e3) {
  if (!edge_edge_boxes_may_meet(e1, e2, e3)) return false;
  const RelativeCrossProducts c = relative_cross_products(e1, e2, e3);
  if (dot(e1, c.c2).excludes_zero()) return false;
  return edge_edge_parameters_may_hold(c);
}

/// Earliest-first bisection of t ∈ [0, time_limit] (time_limit clamped to
/// [0, 1]). `may_touch(T)` returns false only when no t ∈ T can be a
/// contact.
///
/// First the whole searched range [0, time_limit] is tested, then the single
/// instant t = 0: primitives already touching are answered at once (toi = 0
/// is a lower bound of any contact time, so this is conservative whatever the
/// test says). Then the dyadic sub-intervals of [0, 1] are visited depth
/// first, left child first, which is in order of time, each tested only up
/// to time_limit: the first one that reaches the tolerance without being
/// excluded holds the earliest possible contact, and everything before it
/// has been excluded. Sub-intervals starting after time_limit are never
/// visited, so the bisection then ends with no contact.
template <class MayTouch>
CcdResult first_contact_by_bisection(MayTouch&& may_touch, const CcdSettings& settings) {
  // Clamped so the stack below cannot overflow whatever the caller passes.
  const double tolerance = std::clamp(settings.time_tolerance, 1e-12, 1.0);
  // A NaN limit searches the whole step.
  const double limit =
      !(settings.time_limit < 1) ? 1.0 : (settings.time_limit > 0 ? settings.time_limit : 0.0);
  CcdResult result;
  auto contact_at = [&](double toi, bool budget_exhausted) {
    result.contact = true;
    result.toi = toi;
    result.budget_exhausted = budget_exhausted;
    return result;
  };
  result.evaluations = 1;
  if (!may_touch(Interval(0.0, limit))) return result;
  if (limit == 0) return contact_at(0.0, false);  // the instant t = 0 was the test
  if (result.evaluations >= settings.max_evaluations) return contact_at(0.0, true);
  ++result.evaluations;
  if (may_touch(Interval(0.0)) || 1.0 < tolerance) return contact_at(0.0, false);

  struct Span {
    double lo, hi;
  };
  // Depth first with a 1e-12 floor: at most 41 levels, two entries per level.
  Span stack[96];
  int top = 0;
  if (0.5 <= limit) stack[top++] = {0.5, 1.0};
  stack[top++] = {0.0, 0.5};
  while (top > 0) {
    const Span span = stack[--top];
    if (result.evaluations >= settings.max_evaluations) return contact_at(span.lo, true);
    ++result.evaluations;
    if (!may_touch(Interval(span.lo, std::min(span.hi, limit)))) continue;
    const double mid = 0.5 * (span.lo + span.hi);
    if (span.hi - span.lo < tolerance || !(span.lo < mid && mid < span.hi))
      return contact_at(span.lo, false);
    if (mid <= limit) stack[top++] = {mid, span.hi};
    stack[top++] = {span.lo, mid};
  }
  return result;
}

}  // namespace hb::ccd_detail
