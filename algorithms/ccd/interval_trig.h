// Cosine and sine over an interval, bounded conservatively, for the
// rotation part of screw motions.
#pragma once

#include "algorithms/ccd/interval.h"

namespace hb {

/// An interval holding cos(x) for every x in `angle` (rad). cos is monotonic
/// between consecutive multiples of π, so the range is the hull of the
/// endpoint values, widened by the libm error bound, plus 1 when the interval
/// holds an even multiple of π and −1 when it holds an odd one. Multiples
/// are located with a margin, so a bound sitting within rounding of one
/// counts as holding it (wider, never narrower). Any interval of width >= 6
/// gives [−1, 1].
Interval interval_cos(const Interval& angle);

/// An interval holding sin(x) for every x in `angle` (rad); as interval_cos
/// with the extremes at π/2 + jπ.
Interval interval_sin(const Interval& angle);

}  // namespace hb
