// The path of a point over an interval of t of a ScrewMotion, bounded by
// the chord between its two ends: every position along the path lies
// within `stray` of the segment [start, end]. For a long interval this is
// far tighter than a box around the path (the frame enclosed over the whole
// interval applied to the point): a box around a diagonal segment holds points up to its whole
// length away from it, and the box of a turning point grows with every coordinate of the point,
// where the chord's stray grows with the square of the angle turned.
//
// Why the stray bounds the path: with s ∈ [0, 1] the fraction of the
// interval [a, b] (h = b − a), the gap g(s) = p(a + s h) − ((1 − s) p(a) +
// s p(b)) vanishes at both ends, so |g(s)| <= s (1 − s) / 2 max|g''| <=
// max|g''| / 8 (in every direction, hence as a vector), and g'' = h² p''.
//  - A body point c in the world, p(t) = T(t) + R(t) c: T is linear and R(t)
//    c turns at rate ω about the axis, so |p''| = ω² ρ with ρ <= |c| its
//    distance from the axis: stray h² ω² |c| / 8.
//  - A world point x in body coordinates, p(t) = R(t)ᵀ (x − T(t)): p'' =
//    (R'')ᵀ w − 2 (R')ᵀ T' with w = x − T(t), so |p''| <= ω² |w| + 2 ω |T'|,
//    and |w| is largest at an end of the interval (T is linear): stray
//    h² (ω² max(|w(a)|, |w(b)|) + 2 ω |c1 − c0|) / 8.
// The ends come from FrameEnclosure's enclosures at the two times; the
// chord runs between their midpoints and the stray grows by their radii.
//
// Rounding: the tests below compute in double with round-to-nearest; every
// quantity they compare is a sum of a few products of numbers bounded by
// the magnitudes they carry as slack, so their error is below 20 u times
// those magnitudes (u = 2^-53), and the slack used is 1e-12 times them
// (kChordSlack), with 1e-300 absolute for underflow.
#pragma once

#include <algorithm>
#include <cmath>

#include "algorithms/ccd/frame_enclosure.h"
#include "algorithms/ccd/interval.h"
#include "hapticbench/pose.h"

namespace hb::ccd_detail {

inline constexpr double kChordSlack = 1e-12;

/// A point's path over an interval of t: within `stray` (m) of the segment
/// from `start` to `end` (m, the frame of the producer).
struct PathChord {
  Vec3 start = Vec3::Zero(), end = Vec3::Zero();
  double stray = 0;

  /// Upper bound (m) of how far apart two positions of the path can be:
  /// the chord's length plus twice the stray.
  double spread() const { return next_up((end - start).norm() * (1 + kChordSlack) + 2 * stray); }

  /// A fraction s ∈ [0, 1] of the interval before which every position of
  /// the path is farther than `reach` (m) from `centre` (a lower bound of
  /// the first time the path may come that near), or 2 when it never does.
  ///
  /// With f = start − centre, e = end − start and L = reach + stray, the
  /// chord is within L at the roots of |e|² s² + 2 (f · e) s + |f|² − L²;
  /// the smaller root comes from an upper bound of the discriminant (grown
  /// by the rounding of its terms), so it is never later than the exact
  /// one, and is moved earlier by the rounding of its last operations.
  double first_within(const Vec3& centre, double reach) const {
    const Vec3 f = start - centre, e = end - start;
    const double limit = next_up((reach + stray) * (1 + kChordSlack));
    const double a = e.squaredNorm(), b = f.dot(e), f2 = f.squaredNorm(), l2 = limit * limit;
    const double c = f2 - l2;
    const double c_slack = kChordSlack * (f2 + l2) + kAbsoluteSlack;
    if (c <= c_slack) return 0;      // may be within at the start
    if (b >= 0 || a == 0) return 2;  // moving away from the start, which is beyond
    const double b2 = b * b, ac = a * c;
    const double discriminant = b2 - ac + kChordSlack * (b2 + ac) + kAbsoluteSlack;
    if (discriminant < 0) return 2;
    const double root = std::sqrt(discriminant);
    const double s = (-b - root) / a - kChordSlack * (-b + root) / a;
    if (s > 1) return 2;
    return std::max(s, 0.0);
  }

  /// A box holding every position of the path.
  IntervalVec3 box() const {
    Interval b[3];
    for (int k = 0; k < 3; ++k) {
      const double margin = stray * (1 + kChordSlack) + kAbsoluteSlack;
      b[k] = Interval(next_down(std::min(start[k], end[k]) - margin),
                      next_up(std::max(start[k], end[k]) + margin));
    }
    return {b[0], b[1], b[2]};
  }

  /// Encloses n · (p − anchor) over the path, for n of length at most
  /// 1 + 1e-12 (a unit normal rounded).
  Interval side(const Vec3& n, const Vec3& anchor) const {
    const Vec3 from_start = start - anchor, from_end = end - anchor;
    const double a = n.dot(from_start), b = n.dot(from_end);
    const double magnitude = n.cwiseAbs().dot(from_start.cwiseAbs() + from_end.cwiseAbs());
    const double margin = stray * (1 + 2 * kChordSlack) + kChordSlack * magnitude + kAbsoluteSlack;
    return Interval(next_down(std::min(a, b) - margin), next_up(std::max(a, b) + margin));
  }
};

/// The tool frame at the two ends of an interval of t, in doubles with a
/// bound of their error, and the motion's numbers the strays need.
struct FrameChord {
  Mat3 rotation_start = Mat3::Identity(), rotation_end = Mat3::Identity();  ///< R, rounded
  Vec3 origin_start = Vec3::Zero(), origin_end = Vec3::Zero();              ///< T, rounded, m
  double rotation_error = 0;    ///< bound of |entry − exact| over both Rs
  double origin_error = 0;      ///< bound of |coordinate − exact| over both Ts, m
  double origin_magnitude = 0;  ///< the largest |coordinate| of both Ts, m
  double bend = 0;              ///< h² ω² / 8 rounded up (unitless)
  double drift = 0;             ///< h² ω |c1 − c0| / 4 rounded up (m)

  /// The path in the world of body point c (m). A coordinate of T + R c
  /// computed in double is off by at most the errors of T and R times |c|₁
  /// (<= 1.75 |c|) plus the rounding of a sum of four products (below 5e-16
  /// of |T|∞ + |c|₁).
  PathChord world_path(const Vec3& c) const {
    PathChord path;
    path.start = origin_start + rotation_start * c;
    path.end = origin_end + rotation_end * c;
    const double length = c.norm() * (1 + kChordSlack);
    const double coordinate_error = origin_error + kChordSlack * origin_magnitude +
                                    (rotation_error + kChordSlack) * 1.75 * length;
    path.stray = next_up(bend * length + 2 * coordinate_error + kAbsoluteSlack);
    return path;
  }

  /// The path in the world of body vector d (m): R d, turning only.
  PathChord world_vector(const Vec3& d) const {
    PathChord path;
    path.start = rotation_start * d;
    path.end = rotation_end * d;
    const double d1 = d.cwiseAbs().sum();
    const double coordinate_error = rotation_error * d1 + kChordSlack * d1;
    path.stray = next_up(bend * next_up(d.norm() * (1 + kChordSlack)) + 2 * coordinate_error +
                         kAbsoluteSlack);
    return path;
  }

  /// The path in body coordinates of world point x (m): Rᵀ (x − T), each
  /// coordinate off by at most |x − T|₁ times the error of R, plus √3 times
  /// that of T (a column of R has length 1), plus rounding.
  PathChord body_path(const Vec3& x) const {
    PathChord path;
    const Vec3 from_start = x - origin_start, from_end = x - origin_end;
    path.start = rotation_start.transpose() * from_start;
    path.end = rotation_end.transpose() * from_end;
    const double d1 = std::max(from_start.cwiseAbs().sum(), from_end.cwiseAbs().sum());
    const double magnitude = x.cwiseAbs().maxCoeff() + origin_magnitude + d1;
    const double coordinate_error =
        rotation_error * d1 + 2 * origin_error + kChordSlack * magnitude;
    const double w = std::max(from_start.norm(), from_end.norm()) * (1 + kChordSlack) +
                     2 * origin_error + kChordSlack * magnitude;
    path.stray =
        next_up(next_up(bend * next_up(w)) + drift + 2 * coordinate_error + kAbsoluteSlack);
    return path;
  }
};

/// The frame chord of `frames` over [lo, hi] ⊆ [0, 1] of `motion`.
inline FrameChord frame_chord(const FrameEnclosures& frames, const ScrewMotion& motion, double lo,
                              double hi) {
  FrameChord c;
  const FrameEnclosure at_start = frames.over(Interval(lo)), at_end = frames.over(Interval(hi));
  for (int i = 0; i < 3; ++i) {
    c.origin_start[i] = at_start.origin[i].mid;
    c.origin_end[i] = at_end.origin[i].mid;
    c.origin_error = std::max({c.origin_error, at_start.origin[i].rad, at_end.origin[i].rad});
    c.origin_magnitude =
        std::max({c.origin_magnitude, std::abs(c.origin_start[i]), std::abs(c.origin_end[i])});
    for (int j = 0; j < 3; ++j) {
      c.rotation_start(i, j) = at_start.rotation[i][j].mid;
      c.rotation_end(i, j) = at_end.rotation[i][j].mid;
      c.rotation_error =
          std::max({c.rotation_error, at_start.rotation[i][j].rad, at_end.rotation[i][j].rad});
    }
  }
  const Vec3 travel = motion.end_origin() - motion.start_origin();
  const double h = next_up(hi - lo), w = motion.angle();
  c.bend = next_up(next_up(h * h) * next_up(w * w)) / 8;
  c.drift = next_up(next_up(h * h) * next_up(w * next_up(travel.norm() * (1 + kChordSlack)))) / 4;
  return c;
}

}  // namespace hb::ccd_detail
