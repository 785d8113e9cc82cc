// A cubic polynomial in t with interval coefficients and its range over an
// interval of t. The linear CCD kernels expand the coplanarity function into
// one once per query: evaluating the expanded cubic in centred form costs a
// fraction of the cross and dot products of interval vectors, and its
// overestimation shrinks with the square of the interval's width instead of
// linearly, so the bisection excludes sub-intervals near a root sooner.
#pragma once

#include <algorithm>

#include "algorithms/ccd/interval.h"

namespace hb {

/// p(t) = k[0] + k[1] t + k[2] t² + k[3] t³; each coefficient an interval
/// holding the exact one. Unitless in t; p has the unit of its coefficients.
struct IntervalCubic {
  Interval k[4];

  /// An interval holding p(t) for every t ∈ t_range and every choice of the
  /// coefficients within k. Centred (Taylor) form about the midpoint m:
  /// p(m + h) = p(m) + p'(m) h + ½p''(m) h² + k3 h³ with |h| <= r.
  Interval range(const Interval& t_range) const {
    const double m = 0.5 * (t_range.lo + t_range.hi);
    // r, r², r³ bound |h| = |t − m| and its powers over t_range although m
    // and the products are rounded.
    const double r = next_up(std::max(m - t_range.lo, t_range.hi - m));
    const double r2 = next_up(r * r);
    const double r3 = next_up(r2 * r);
    const Interval value = ((k[3] * m + k[2]) * m + k[1]) * m + k[0];
    const Interval half_curvature = (k[3] * 3.0) * m + k[2];
    const Interval slope = (half_curvature + k[2]) * m + k[1];
    // The odd terms p'(m) h + k3 h³ lie in [−spread, spread]; the even term
    // ½p''(m) h² between min(0, ½p''.lo) r² and max(0, ½p''.hi) r².
    const double spread = next_up(next_up(r * magnitude(slope)) + next_up(r3 * magnitude(k[3])));
    const Interval curvature_term(next_down(std::min(0.0, half_curvature.lo) * r2),
                                  next_up(std::max(0.0, half_curvature.hi) * r2));
    return value + (curvature_term + Interval(-spread, spread));
  }
};

}  // namespace hb
