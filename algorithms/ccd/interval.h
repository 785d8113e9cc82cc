// Interval arithmetic with outward rounding, the number type of the
// continuous collision detection: a result interval always contains every
// value the exact real operation can take on the operand intervals.
//
// Rounding: each operation is computed in double with the default
// round-to-nearest mode, then its lower bound is moved one ulp towards -inf
// and its upper bound one ulp towards +inf: the value of
// std::nextafter(x, ∓inf), computed by next_down/next_up below without the
// libm call, which would dominate the cost (below 1e-40 in magnitude the step
// is up to 2^-200 instead, never less than one ulp).
// Why one ulp is enough: a correctly rounded result r of an exact value x is
// one of the two doubles adjacent to x, so the double below r is <= x and the
// double above r is >= x. This holds for +, −, × and ÷ (IEEE 754 requires
// them correctly rounded), through gradual underflow, and on overflow (the
// rounded bound is ±inf or ±DBL_MAX on the correct side). It assumes the
// default floating-point environment (round to nearest, no flush to zero),
// and operands without NaN: callers bound their inputs so that no overflow
// to inf − inf or 0 × inf can happen.
#pragma once

#include <algorithm>
#include <cmath>

namespace hb {

/// next_down and next_up follow Rump, Zimmermann, Boldo & Melquiond,
/// "Computing predecessor and successor in rounding to nearest", BIT 49
/// (2009): for finite x, x ∓ (φ|x| + η) rounded to nearest is never closer
/// to x than its neighbouring double, and is exactly that neighbour while φ|x|
/// dominates η. φ = 2^-53 (1 + 2^-52) is a little more than half an ulp
/// relative to |x|. η covers x = 0 and tiny x; it is 2^-200 (6e-61, far
/// below any length of interest) rather than the smallest subnormal so that
/// a widened 0 and products of a few of them stay normal numbers: subnormal
/// operands and results take a microcoded path 100 times slower, and exact
/// zeros are common in degenerate geometry.
inline constexpr double kNeighbourRelativeStep = 0x1p-53 * (1 + 0x1p-52);
inline constexpr double kNeighbourAbsoluteStep = 0x1p-200;

/// A double <= the largest double below x (std::nextafter(x, -inf)); equal
/// to it for finite |x| > 1e-40, otherwise at most 2^-200 further.
inline double next_down(double x) {
  return x - (std::abs(x) * kNeighbourRelativeStep + kNeighbourAbsoluteStep);
}

/// A double >= the smallest double above x (std::nextafter(x, +inf)); equal
/// to it for finite |x| > 1e-40, otherwise at most 2^-200 further.
inline double next_up(double x) {
  return x + (std::abs(x) * kNeighbourRelativeStep + kNeighbourAbsoluteStep);
}

/// Closed interval [lo, hi] of reals, lo <= hi. Unitless: it bounds
/// whatever quantity it stands for (a time, a coordinate in m, a volume).
struct Interval {
  double lo = 0;
  double hi = 0;

  constexpr Interval() = default;
  /// The single point x, exact.
  constexpr explicit Interval(double x) : lo(x), hi(x) {}
  constexpr Interval(double lower, double upper) : lo(lower), hi(upper) {}

  /// Every value is > 0.
  constexpr bool certainly_positive() const { return lo > 0; }
  /// Every value is < 0.
  constexpr bool certainly_negative() const { return hi < 0; }
  /// Some value may be 0: neither certainly positive nor certainly negative
  /// (also true for an interval with a NaN bound, which proves nothing).
  constexpr bool contains_zero() const { return !(lo > 0) && !(hi < 0); }
  /// Certainly nonzero: the interval excludes 0.
  constexpr bool excludes_zero() const { return lo > 0 || hi < 0; }
  constexpr bool contains(double x) const { return lo <= x && x <= hi; }
  constexpr double width() const { return hi - lo; }
};

/// The interval from an exactly known lower and upper bound that were
/// rounded to nearest: widened by one ulp on each side.
inline Interval widened(double lo, double hi) { return Interval(next_down(lo), next_up(hi)); }

/// The largest absolute value in the interval, exact.
inline double magnitude(const Interval& a) { return std::max(-a.lo, a.hi); }

/// The smallest interval holding both.
inline Interval hull(const Interval& a, const Interval& b) {
  return Interval(std::min(a.lo, b.lo), std::max(a.hi, b.hi));
}

/// Negation is exact.
inline Interval operator-(const Interval& a) { return Interval(-a.hi, -a.lo); }

inline Interval operator+(const Interval& a, const Interval& b) {
  return widened(a.lo + b.lo, a.hi + b.hi);
}

inline Interval operator-(const Interval& a, const Interval& b) {
  return widened(a.lo - b.hi, a.hi - b.lo);
}

inline Interval operator*(const Interval& a, const Interval& b) {
  const double p1 = a.lo * b.lo, p2 = a.lo * b.hi, p3 = a.hi * b.lo, p4 = a.hi * b.hi;
  return widened(std::min(std::min(p1, p2), std::min(p3, p4)),
                 std::max(std::max(p1, p2), std::max(p3, p4)));
}

/// Product with an exactly known double.
inline Interval operator*(const Interval& a, double s) {
  const double p1 = a.lo * s, p2 = a.hi * s;
  return widened(std::min(p1, p2), std::max(p1, p2));
}
inline Interval operator*(double s, const Interval& a) { return a * s; }

/// Quotient; defined only when b excludes 0 (b.excludes_zero()). Division is
/// monotonic in each argument there, so the bounds are among the four
/// endpoint quotients.
inline Interval operator/(const Interval& a, const Interval& b) {
  const double q1 = a.lo / b.lo, q2 = a.lo / b.hi, q3 = a.hi / b.lo, q4 = a.hi / b.hi;
  return widened(std::min(std::min(q1, q2), std::min(q3, q4)),
                 std::max(std::max(q1, q2), std::max(q3, q4)));
}

/// a², tighter than a * a when a straddles 0 (the two factors are the same
/// number, so the result is never negative).
inline Interval sqr(const Interval& a) {
  const double l2 = a.lo * a.lo, h2 = a.hi * a.hi;
  if (a.lo >= 0) return widened(l2, h2);
  if (a.hi <= 0) return widened(h2, l2);
  return Interval(0, next_up(std::max(l2, h2)));
}

inline Interval& operator+=(Interval& a, const Interval& b) { return a = a + b; }
inline Interval& operator-=(Interval& a, const Interval& b) { return a = a - b; }

/// A 3-vector of intervals: a box bounding a point or a vector (m, or the
/// unit of what it bounds), in whatever frame its producer states.
struct IntervalVec3 {
  Interval x, y, z;

  const Interval& operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};

inline IntervalVec3 operator+(const IntervalVec3& a, const IntervalVec3& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline IntervalVec3 operator-(const IntervalVec3& a, const IntervalVec3& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline IntervalVec3 operator-(const IntervalVec3& a) { return {-a.x, -a.y, -a.z}; }
inline IntervalVec3 operator*(const Interval& s, const IntervalVec3& a) {
  return {s * a.x, s * a.y, s * a.z};
}
inline IntervalVec3 hull(const IntervalVec3& a, const IntervalVec3& b) {
  return {hull(a.x, b.x), hull(a.y, b.y), hull(a.z, b.z)};
}

inline Interval dot(const IntervalVec3& a, const IntervalVec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

inline IntervalVec3 cross(const IntervalVec3& a, const IntervalVec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

}  // namespace hb
