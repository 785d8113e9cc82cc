// The pose of a body following a ScrewMotion, enclosed over an interval of
// t, in the form the mesh CCD's hot loops use: the origin T(t) and every
// entry of R(t) as a midpoint and a radius (m, unitless). A world position
// T(t) + R(t) v or body coordinates R(t)ᵀ (x − T(t)) then cost one matrix
// product in doubles plus a bound of the radius and of the product's
// rounding, several times cheaper than the same product of Intervals, and
// the result is returned as an outward-rounded IntervalVec3.
//
// Rounding: a sum of n products computed in double with round-to-nearest
// differs from the exact sum by at most γ_n Σ|products|, γ_n = n u / (1 −
// n u), u = 2^-53 (Higham, Accuracy and Stability of Numerical Algorithms,
// 3.1); here n <= 4, γ_4 < 4.5e-16, and the bound used is 2e-15 Σ|products|
// (kProductSlack). The radii are sums of a few positive products, computed
// in double too: their own relative rounding error (below 20 u) is covered
// by enlarging them by 1e-13 relative (kRadiusSlack), and underflow by an
// absolute 1e-300 (kAbsoluteSlack). Both bounds of the result are finally
// moved outward by one ulp.
#pragma once

#include <algorithm>
#include <cmath>

#include "algorithms/ccd/interval.h"
#include "algorithms/ccd/screw_motion.h"
#include "hapticbench/pose.h"

namespace hb::ccd_detail {

inline constexpr double kProductSlack = 2e-15;
inline constexpr double kRadiusSlack = 1e-13;
inline constexpr double kAbsoluteSlack = 1e-300;

/// mid ± rad holding every value of an interval.
struct MidRad {
  double mid = 0, rad = 0;
};

/// The midpoint lies within [lo, hi] (a rounded value between two doubles
/// stays between them); the differences to the ends are rounded up by one
/// ulp, so rad bounds them.
inline MidRad mid_rad(const Interval& a) {
  const double mid = 0.5 * a.lo + 0.5 * a.hi;
  return {mid, next_up(std::max(mid - a.lo, a.hi - mid))};
}

/// The interval [mid − rad, mid + rad] with the radius enlarged by the
/// slacks above and both bounds rounded outward.
inline Interval enclose(double mid, double rad, double magnitude) {
  const double r = (rad + kProductSlack * magnitude) * (1 + kRadiusSlack) + kAbsoluteSlack;
  return Interval(next_down(mid - r), next_up(mid + r));
}

/// A body frame's pose over an interval of t (see the file comment).
struct FrameEnclosure {
  MidRad origin[3];       ///< T(t), world, m
  MidRad rotation[3][3];  ///< R(t), entry (row, column)

  FrameEnclosure() = default;
  FrameEnclosure(const IntervalVec3& origin_box, const Interval (&rotation_box)[3][3]) {
    for (int i = 0; i < 3; ++i) {
      origin[i] = mid_rad(origin_box[i]);
      for (int j = 0; j < 3; ++j) rotation[i][j] = mid_rad(rotation_box[i][j]);
    }
  }

  /// Encloses T(t) + R(t) v, the world position (m) of body point v (m).
  IntervalVec3 position(const Vec3& v) const {
    Interval p[3];
    for (int i = 0; i < 3; ++i) {
      double sum = origin[i].mid, magnitude = std::abs(origin[i].mid), rad = origin[i].rad;
      for (int j = 0; j < 3; ++j) {
        const double product = rotation[i][j].mid * v[j];
        sum += product;
        magnitude += std::abs(product);
        rad += rotation[i][j].rad * std::abs(v[j]);
      }
      p[i] = enclose(sum, rad, magnitude);
    }
    return {p[0], p[1], p[2]};
  }

  /// Encloses R(t)ᵀ n, the body coordinates of world direction n.
  IntervalVec3 body_direction(const Vec3& n) const {
    Interval b[3];
    for (int j = 0; j < 3; ++j) {
      double sum = 0, magnitude = 0, rad = 0;
      for (int i = 0; i < 3; ++i) {
        const double product = rotation[i][j].mid * n[i];
        sum += product;
        magnitude += std::abs(product);
        rad += rotation[i][j].rad * std::abs(n[i]);
      }
      b[j] = enclose(sum, rad, magnitude);
    }
    return {b[0], b[1], b[2]};
  }

  /// Encloses R(t)ᵀ (x − T(t)), the body coordinates (m) of world point x
  /// (m). d = x − T(t) is mid ± rad with the subtraction's rounding (at most
  /// u |d_mid|) added to the radius; each product M d of two mid ± rad
  /// values lies within M_mid d_mid ± (|M_mid| d_rad + M_rad (|d_mid| + d_rad)).
  IntervalVec3 body_coordinates(const Vec3& x) const {
    double d_mid[3], d_rad[3];
    for (int i = 0; i < 3; ++i) {
      d_mid[i] = x[i] - origin[i].mid;
      d_rad[i] = origin[i].rad + kProductSlack * std::abs(d_mid[i]);
    }
    Interval b[3];
    for (int j = 0; j < 3; ++j) {
      double sum = 0, magnitude = 0, rad = 0;
      for (int i = 0; i < 3; ++i) {
        const double product = rotation[i][j].mid * d_mid[i];
        sum += product;
        magnitude += std::abs(product);
        rad += std::abs(rotation[i][j].mid) * d_rad[i] +
               rotation[i][j].rad * (std::abs(d_mid[i]) + d_rad[i]);
      }
      b[j] = enclose(sum, rad, magnitude);
    }
    return {b[0], b[1], b[2]};
  }
};

/// Frame enclosures of one ScrewMotion: R(t) = cos(ωt) A + sin(ωt) B + K
/// with A = (I − uuᵀ)R0, B = [u]× R0, K = uuᵀ R0 enclosed once, then
/// combined with the interval cos(ωt), sin(ωt) and T(t) of each interval of
/// t.
class FrameEnclosures {
 public:
  explicit FrameEnclosures(const ScrewMotion& motion) : motion_(motion) {
    const Vec3& u = motion.axis();
    const Mat3& r0 = motion.start_rotation();
    const Mat3 u_cross = skew(u);  // exact: entries are ±u_k or 0
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        Interval along(0.0), across(0.0);
        for (int k = 0; k < 3; ++k) {
          along = along + (Interval(u[i]) * Interval(u[k])) * r0(k, j);
          across = across + Interval(u_cross(i, k)) * r0(k, j);
        }
        k_[i][j] = along;
        a_[i][j] = Interval(r0(i, j)) - along;
        b_[i][j] = across;
      }
  }

  /// The frame over t ⊆ [0, 1].
  FrameEnclosure over(const Interval& t) const {
    const ScrewMotionSample s = motion_.sample(t);
    Interval rotation[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        rotation[i][j] = (s.cos_wt * a_[i][j] + s.sin_wt * b_[i][j]) + k_[i][j];
    return FrameEnclosure(s.origin, rotation);
  }

 private:
  const ScrewMotion& motion_;
  Interval a_[3][3], b_[3][3], k_[3][3];
};

}  // namespace hb::ccd_detail
