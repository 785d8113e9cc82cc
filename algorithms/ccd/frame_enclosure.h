// The pose of a body following a ScrewMotion, enclosed over an interval of
// t (an instant, for the chords of path_chord.h): the origin T(t) and every
// entry of R(t) as a midpoint and a radius (m, unitless), from interval
// arithmetic on the motion's doubles, so that every value the exact motion
// takes over the interval lies within them.
#pragma once

#include <algorithm>
#include <cmath>

#include "algorithms/ccd/interval.h"
#include "algorithms/ccd/screw_motion.h"
#include "hapticbench/pose.h"

namespace hb::ccd_detail {

/// An absolute bound added to error bounds against underflow (m or unitless).
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
