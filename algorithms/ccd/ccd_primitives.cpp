#include "algorithms/ccd/ccd_primitives.h"

#include <algorithm>
#include <cmath>

#include "algorithms/ccd/ccd_bisection.h"
#include "algorithms/ccd/interval.h"
#include "algorithms/ccd/interval_cubic.h"

namespace hb {

namespace {

bool within_range(const LinearCcdQuery& query) {
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 3; ++k)
      if (!(std::abs(query.start[i][k]) <= kMaxCcdCoordinate) ||
          !(std::abs(query.end[i][k]) <= kMaxCcdCoordinate))
        return false;
  return true;
}

/// Whether the boxes swept over the whole step by points [0, split) and by
/// points [split, 4) overlap. A linearly moving point stays in the box of
/// its two end positions, so this compares input numbers only, exactly;
/// most queries of a broad phase end here.
bool swept_boxes_may_meet(const LinearCcdQuery& query, int split) {
  for (int k = 0; k < 3; ++k) {
    double lo_a = query.start[0][k], hi_a = lo_a;
    double lo_b = query.start[split][k], hi_b = lo_b;
    for (int i = 0; i < 4; ++i) {
      const double s = query.start[i][k], e = query.end[i][k];
      double& lo = i < split ? lo_a : lo_b;
      double& hi = i < split ? hi_a : hi_b;
      lo = std::min(lo, std::min(s, e));
      hi = std::max(hi, std::max(s, e));
    }
    if (hi_a < lo_b || hi_b < lo_a) return false;
  }
  return true;
}

/// x_i(t) − x0(t) = offset + t·velocity exactly (both points move
/// linearly), with offset and velocity enclosed once per query.
struct LinearRelativeVector {
  IntervalVec3 offset;    // x_i − x0 at t = 0, m
  IntervalVec3 velocity;  // its change over the step, m per unit t
};

LinearRelativeVector relative_vector(const LinearCcdQuery& query, int i) {
  Interval offset[3], velocity[3];
  for (int k = 0; k < 3; ++k) {
    offset[k] = Interval(query.start[i][k]) - Interval(query.start[0][k]);
    velocity[k] = (Interval(query.end[i][k]) - Interval(query.end[0][k])) - offset[k];
  }
  return {{offset[0], offset[1], offset[2]}, {velocity[0], velocity[1], velocity[2]}};
}

/// t·v for t ⊆ [0, 1]: with t >= 0 the extremes are t.lo·v.lo or t.hi·v.lo
/// below and t.lo·v.hi or t.hi·v.hi above.
Interval scaled_by_time(const Interval& t, const Interval& v) {
  return widened(std::min(t.lo * v.lo, t.hi * v.lo), std::max(t.lo * v.hi, t.hi * v.hi));
}

IntervalVec3 over(const LinearRelativeVector& v, const Interval& t) {
  return {v.offset.x + scaled_by_time(t, v.velocity.x),
          v.offset.y + scaled_by_time(t, v.velocity.y),
          v.offset.z + scaled_by_time(t, v.velocity.z)};
}

/// The coplanarity function f(t) = e1(t) · (e2(t) × e3(t)) expanded in
/// powers of t: with e_i = O_i + t V_i, e2 × e3 = C0 + C1 t + C2 t² where
/// C0 = O2 × O3, C1 = O2 × V3 + V2 × O3, C2 = V2 × V3, and
/// f = O1·C0 + (O1·C1 + V1·C0) t + (O1·C2 + V1·C1) t² + V1·C2 t³.
IntervalCubic coplanarity_cubic(const LinearRelativeVector& v1, const LinearRelativeVector& v2,
                                const LinearRelativeVector& v3) {
  const IntervalVec3 c0 = cross(v2.offset, v3.offset);
  const IntervalVec3 c1 = cross(v2.offset, v3.velocity) + cross(v2.velocity, v3.offset);
  const IntervalVec3 c2 = cross(v2.velocity, v3.velocity);
  IntervalCubic f;
  f.k[0] = dot(v1.offset, c0);
  f.k[1] = dot(v1.offset, c1) + dot(v1.velocity, c0);
  f.k[2] = dot(v1.offset, c2) + dot(v1.velocity, c1);
  f.k[3] = dot(v1.velocity, c2);
  return f;
}

/// The common frame of both kernels: quick rejection by the swept boxes,
/// then the bisection with the coplanarity cubic first and the
/// primitive-specific tests (`boxes_may_meet`, `sides_may_hold`) after.
template <class BoxesMayMeet, class SidesMayHold>
CcdResult linear_ccd(const LinearCcdQuery& query, const CcdSettings& settings, int split,
                     BoxesMayMeet&& boxes_may_meet, SidesMayHold&& sides_may_hold) {
  CcdResult result;
  if (!within_range(query)) {
    result.contact = true;
    result.toi = 0;
    result.input_out_of_range = true;
    return result;
  }
  if (!swept_boxes_may_meet(query, split)) return result;
  const LinearRelativeVector v1 = relative_vector(query, 1), v2 = relative_vector(query, 2),
                             v3 = relative_vector(query, 3);
  const IntervalCubic f = coplanarity_cubic(v1, v2, v3);
  return ccd_detail::first_contact_by_bisection(
      [&](const Interval& t) {
        if (f.range(t).excludes_zero()) return false;
        const IntervalVec3 e1 = over(v1, t), e2 = over(v2, t), e3 = over(v3, t);
        if (!boxes_may_meet(e1, e2, e3)) return false;
        return sides_may_hold(ccd_detail::relative_cross_products(e1, e2, e3));
      },
      settings);
}

}  // namespace

CcdResult vertex_face_ccd(const LinearCcdQuery& query, const CcdSettings& settings) {
  return linear_ccd(
      query, settings, 1,
      [](const auto&... e) { return ccd_detail::vertex_face_boxes_may_meet(e...); },
      [](const auto& c) { return ccd_detail::vertex_face_areas_may_hold(c); });
}

CcdResult edge_edge_ccd(const LinearCcdQuery& query, const CcdSettings& settings) {
  return linear_ccd(
      query, settings, 2,
      [](const auto&... e) { return ccd_detail::edge_edge_boxes_may_meet(e...); },
      [](const auto& c) { return ccd_detail::edge_edge_parameters_may_hold(c); });
}

}  // namespace hb
