// What every primitive continuous collision query takes and returns, for
// linear vertex motion (ccd_primitives.h) and rigid screw motion
// (screw_ccd.h) alike. Time is normalised: t = 0 is the start pose of the
// step and t = 1 its end.
#pragma once

#include <string>

namespace hb {

/// How a query bisects t ∈ [0, 1].
struct CcdSettings {
  /// A sub-interval of t narrower than this that the tests cannot exclude is
  /// reported as a contact at its lower bound. Unitless (a fraction of the
  /// step), in [1e-12, 1].
  double time_tolerance = 1e-6;
  /// Most sub-intervals one query evaluates (the instant t = 0 counts as
  /// one). When it is used up the query answers, conservatively, "contact at
  /// the lower bound of the earliest sub-interval not yet excluded". A
  /// genuine contact bisected to 1e-6 takes 25–45 evaluations. At about
  /// 100 ns per linear evaluation (2.6 GHz core) the default bounds a linear
  /// query near 7 µs; a screw-motion evaluation costs about 200 ns, so its
  /// worst case is near 15 µs with the default.
  int max_evaluations = 64;
  /// Only times in [0, time_limit] are searched (unitless, in [0, 1]): a
  /// query whose earliest sub-interval not excluded starts after time_limit
  /// answers no contact, and a sub-interval reaching past it is tested only
  /// up to it. A caller that already knows a contact at time t passes about
  /// t here, so the query stops as soon as it cannot be earlier.
  double time_limit = 1;
};

/// Throws InputError naming `field_prefix` + ".time_tolerance",
/// ".max_evaluations" or ".time_limit" when a setting is out of range.
void validate_ccd_settings(const CcdSettings& settings, const std::string& field_prefix);

/// Answer of a primitive continuous collision query. Conservative: a contact
/// anywhere in [0, 1] is never missed (no false negatives); `contact` may be
/// true for primitives that pass within about the time tolerance's worth of
/// motion of each other, or when the budget ran out (false positives).
struct CcdResult {
  /// The primitives may touch at some t in [0, 1] (in [0, time_limit]).
  bool contact = false;
  /// When `contact`: a lower bound of the earliest time of contact, in
  /// [0, 1] (unitless fraction of the step); every earlier time is proven
  /// contact-free. 1 when there is no contact.
  double toi = 1;
  /// Sub-intervals of t evaluated (the cost of the query).
  int evaluations = 0;
  /// The evaluation budget ran out before the bisection finished; `contact`
  /// is then true and `toi` the earliest time not yet excluded.
  bool budget_exhausted = false;
  /// An input coordinate was not finite or exceeded kMaxCcdCoordinate, so
  /// interval bounds could overflow; answered as contact at t = 0.
  bool input_out_of_range = false;
};

/// Largest accepted magnitude of an input coordinate (any length unit).
/// Degree-4 products of differences of such numbers stay below 1e243, far
/// from overflow, so interval bounds never become inf or NaN.
inline constexpr double kMaxCcdCoordinate = 1e60;

}  // namespace hb
