#include "algorithms/ccd/interval_trig.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hb {

namespace {

/// Bound on |libm cos(x) − cos x| and |libm sin(x) − sin x| for |x| <= 1e6,
/// glibc documents errors below 1 ulp (at most 2^-53 for results in
/// [−1, 1]); this allows eight times that.
constexpr double kLibmTrigError = 0x1p-50;

/// Relative margin for locating multiples of π: the quotient x/π carries a
/// relative error of a few 1e-16, far below it.
constexpr double kMultipleMargin = 1e-9;

/// Beyond this |angle| (rad) the error bound above is not relied on.
constexpr double kLargestBoundedAngle = 1e6;

/// The range over `angle` of a function (`value`: cos or sin) whose extremes
/// lie at (j + shift)·π, maxima for even j and minima for odd j.
template <class Value>
Interval periodic_range(const Interval& angle, double shift, Value value) {
  if (!(angle.hi - angle.lo < 6.0) || !(std::abs(angle.lo) <= kLargestBoundedAngle) ||
      !(std::abs(angle.hi) <= kLargestBoundedAngle))
    return Interval(-1.0, 1.0);
  const double a = value(angle.lo), b = value(angle.hi);
  double lo = next_down(std::min(a, b) - kLibmTrigError);
  double hi = next_up(std::max(a, b) + kLibmTrigError);
  const double first = angle.lo / std::numbers::pi - shift;
  const double last = angle.hi / std::numbers::pi - shift;
  const double j_first = std::ceil(first - kMultipleMargin * (1 + std::abs(first)));
  const double j_last = std::floor(last + kMultipleMargin * (1 + std::abs(last)));
  for (double j = j_first; j <= j_last; ++j) {
    if (std::fmod(j, 2.0) == 0)
      hi = 1.0;
    else
      lo = -1.0;
  }
  return Interval(std::max(lo, -1.0), std::min(hi, 1.0));
}

}  // namespace

Interval interval_cos(const Interval& angle) {
  return periodic_range(angle, 0.0, [](double x) { return std::cos(x); });
}

Interval interval_sin(const Interval& angle) {
  return periodic_range(angle, 0.5, [](double x) { return std::sin(x); });
}

}  // namespace hb
