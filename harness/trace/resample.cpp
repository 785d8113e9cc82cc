// Resampling a trace onto the 1 kHz clock. Tick k is at t_ns = k * 1'000'000
// exactly: times stay integers, so no floating-point clock drifts.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "algorithms/core/input_error.h"
#include "harness/trace/trace.h"

namespace hb {

namespace {

constexpr int64_t kTickNs = 1'000'000;
constexpr double kTickS = 1e-3;

/// Spherical linear interpolation along the shorter arc: q0 and -q1 are the
/// same rotation, and the interpolant must not take the 2*pi - angle way.
Quat slerp_shortest(const Quat& q0, const Quat& q1, double alpha) {
  Quat relative = q0.conjugate() * q1;
  if (relative.w() < 0) relative.coeffs() = -relative.coeffs();
  const Vec3 theta = rotation_vector(relative);
  return (q0 * quat_from_rotation_vector(alpha * theta)).normalized();
}

/// Pose and (when the trace has one) twist at an exact time inside the trace.
struct Interpolated {
  Pose pose;
  Twist twist;
};

Interpolated interpolate(const TraceSample& a, const TraceSample& b, int64_t t_ns,
                         bool with_twist) {
  // Integer differences first: only the ratio is a double.
  const double alpha = static_cast<double>(t_ns - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  Interpolated out;
  out.pose.p = a.pose.p + alpha * (b.pose.p - a.pose.p);
  out.pose.q = slerp_shortest(a.pose.q, b.pose.q, alpha);
  if (with_twist) {
    out.twist.v = a.twist->v + alpha * (b.twist->v - a.twist->v);
    out.twist.w = a.twist->w + alpha * (b.twist->w - a.twist->w);
  }
  return out;
}

/// Velocity of the motion from pose `from` to pose `to` over `dt` seconds:
/// linear velocity of the origin and angular velocity in the world frame
/// (rotation vector of q_to * q_from^-1 divided by dt).
Twist finite_difference(const Pose& from, const Pose& to, double dt) {
  return Twist{(to.p - from.p) / dt, rotation_vector(to.q * from.q.conjugate()) / dt};
}

}  // namespace

std::vector<DeviceSample> resample_to_ticks(const Trace& trace, int64_t duration_ticks) {
  const std::vector<TraceSample>& samples = trace.samples;
  if (samples.empty()) throw InputError("", "samples", "expected a trace with at least 1 sample");
  if (duration_ticks < 0) throw std::invalid_argument("resample_to_ticks: negative duration");

  bool with_twist = true;
  for (const TraceSample& sample : samples) with_twist = with_twist && sample.twist.has_value();

  const int64_t first_ns = samples.front().t_ns;
  const int64_t last_ns = samples.back().t_ns;
  // Ticks the trace covers: 0 .. floor(last / 1 ms).
  const int64_t covered_ticks = last_ns < 0 ? 0 : last_ns / kTickNs + 1;
  const int64_t ticks = duration_ticks > 0 ? duration_ticks : covered_ticks;
  const auto max_ticks = static_cast<int64_t>(kMaxRunDurationS * 1e9) / kTickNs;
  if (ticks > max_ticks) {
    throw InputError("", "samples",
                     "the trace spans " + std::to_string(last_ns / 1'000'000'000) +
                         " s of ticks (from t = 0 to its last sample); a run is at most " +
                         std::to_string(static_cast<int64_t>(kMaxRunDurationS)) +
                         " s. Give \"duration_s\" or a shorter trace");
  }

  std::vector<DeviceSample> out(static_cast<std::size_t>(ticks));
  // Ticks [begin, end) lie inside the trace's time span; before it the first
  // pose is held, after it the last, at rest.
  int64_t begin = ticks;
  int64_t end = 0;
  std::size_t segment = 0;
  for (int64_t k = 0; k < ticks; ++k) {
    DeviceSample& tick = out[static_cast<std::size_t>(k)];
    tick.tick = k;
    tick.t_ns = k * kTickNs;
    if (tick.t_ns < first_ns) {
      tick.pose = samples.front().pose;
      continue;
    }
    if (tick.t_ns > last_ns) {
      tick.pose = samples.back().pose;
      continue;
    }
    begin = std::min(begin, k);
    end = k + 1;
    if (tick.t_ns == last_ns) {
      tick.pose = samples.back().pose;
      if (with_twist) tick.twist = *samples.back().twist;
      continue;
    }
    while (samples[segment + 1].t_ns <= tick.t_ns) ++segment;
    const Interpolated value =
        interpolate(samples[segment], samples[segment + 1], tick.t_ns, with_twist);
    tick.pose = value.pose;
    if (with_twist) tick.twist = value.twist;
  }

  if (!with_twist && end - begin >= 2) {
    // Central differences inside, one-sided at the two ends of the span.
    for (int64_t k = begin; k < end; ++k) {
      const int64_t before = std::max(begin, k - 1);
      const int64_t after = std::min(end - 1, k + 1);
      out[static_cast<std::size_t>(k)].twist = finite_difference(
          out[static_cast<std::size_t>(before)].pose, out[static_cast<std::size_t>(after)].pose,
          static_cast<double>(after - before) * kTickS);
    }
  }
  return out;
}

}  // namespace hb
