// Resampling a trace onto the 1 kHz clock, one block of ticks at a time.
// Tick k is at t_ns = k * 1'000'000 exactly: times stay integers, so no
// floating-point clock drifts.
#include "harness/trace/device_trajectory.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "hapticbench/input_error.h"

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

/// Velocity of the motion from pose `from` to pose `to` over `dt` seconds:
/// linear velocity of the origin and angular velocity in the world frame
/// (rotation vector of q_to * q_from^-1 divided by dt).
Twist finite_difference(const Pose& from, const Pose& to, double dt) {
  return Twist{(to.p - from.p) / dt, rotation_vector(to.q * from.q.conjugate()) / dt};
}

int64_t floor_div(int64_t a, int64_t b) { return a / b - (a % b != 0 && (a < 0) != (b < 0)); }

}  // namespace

/// Pose and twist of one tick before any finite differences.
struct DeviceTrajectory::Interpolated {
  Pose pose;
  Twist twist;  ///< the source's (interpolated) twist, zero outside its span or without one
};

DeviceTrajectory::DeviceTrajectory(TraceSource source, int64_t duration_ticks)
    : source_(std::move(source)) {
  if (source_.count < 1 || !source_.at)
    throw InputError("", "samples", "expected a trace with at least 1 sample");
  if (duration_ticks < 0) throw std::invalid_argument("DeviceTrajectory: negative duration");
  first_ = source_.at(0);
  last_ = source_.at(source_.count - 1);
  // Ticks the trace covers: 0 .. floor(last / 1 ms).
  const int64_t covered_ticks = last_.t_ns < 0 ? 0 : last_.t_ns / kTickNs + 1;
  ticks_ = duration_ticks > 0 ? duration_ticks : covered_ticks;
  const auto max_ticks = static_cast<int64_t>(kMaxRunDurationS * 1e9) / kTickNs;
  if (ticks_ > max_ticks) {
    throw InputError("", "samples",
                     "the trace spans " + std::to_string(last_.t_ns / 1'000'000'000) +
                         " s of ticks (from t = 0 to its last sample); a run is at most " +
                         std::to_string(static_cast<int64_t>(kMaxRunDurationS)) +
                         " s. Give \"duration_s\" or a shorter trace");
  }
  // Ticks inside [first, last] of the source; before it the first pose is
  // held, after it the last, at rest.
  span_begin_ = std::max<int64_t>(0, -floor_div(-first_.t_ns, kTickNs));
  span_end_ = last_.t_ns < 0 ? 0 : std::min(ticks_, last_.t_ns / kTickNs + 1);
  if (span_begin_ >= span_end_) span_begin_ = span_end_ = 0;
}

DeviceTrajectory DeviceTrajectory::of_trace(Trace trace, int64_t duration_ticks) {
  auto rows = std::make_shared<const std::vector<TraceSample>>(std::move(trace.samples));
  TraceSource source;
  source.count = static_cast<int64_t>(rows->size());
  source.has_twists = std::all_of(rows->begin(), rows->end(),
                                  [](const TraceSample& s) { return s.twist.has_value(); });
  source.at = [rows](int64_t index) { return (*rows)[static_cast<std::size_t>(index)]; };
  return DeviceTrajectory(std::move(source), duration_ticks);
}

DeviceTrajectory DeviceTrajectory::of_samples(std::vector<DeviceSample> samples) {
  DeviceTrajectory trajectory;
  trajectory.ticks_ = static_cast<int64_t>(samples.size());
  trajectory.given_ = std::make_shared<const std::vector<DeviceSample>>(std::move(samples));
  return trajectory;
}

DeviceTrajectory::Interpolated DeviceTrajectory::interpolated(int64_t tick, int64_t& segment,
                                                              TraceSample& a,
                                                              TraceSample& b) const {
  const int64_t t_ns = tick * kTickNs;
  Interpolated out;
  if (t_ns < first_.t_ns) {
    out.pose = first_.pose;
    return out;
  }
  if (t_ns >= last_.t_ns) {
    out.pose = last_.pose;
    if (t_ns == last_.t_ns && source_.has_twists) out.twist = *last_.twist;
    return out;
  }
  // The segment [a, b) holding t: a sequential step from the last one, or
  // a binary search when t is not in the next few.
  if (segment < 0 || t_ns < a.t_ns || t_ns >= b.t_ns) {
    int64_t steps = 0;
    while (segment >= 0 && t_ns >= b.t_ns && steps < 4 && segment + 2 < source_.count) {
      ++segment;
      a = b;
      b = source_.at(segment + 1);
      ++steps;
    }
    if (segment < 0 || t_ns < a.t_ns || t_ns >= b.t_ns) {
      int64_t lo = 0, hi = source_.count - 1;  // at(lo).t <= t < at(hi).t
      while (hi - lo > 1) {
        const int64_t mid = lo + (hi - lo) / 2;
        (source_.at(mid).t_ns <= t_ns ? lo : hi) = mid;
      }
      segment = lo;
      a = source_.at(lo);
      b = source_.at(lo + 1);
    }
  }
  // Integer differences first: only the ratio is a double.
  const double alpha = static_cast<double>(t_ns - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  out.pose.p = a.pose.p + alpha * (b.pose.p - a.pose.p);
  out.pose.q = slerp_shortest(a.pose.q, b.pose.q, alpha);
  if (source_.has_twists) {
    out.twist.v = a.twist->v + alpha * (b.twist->v - a.twist->v);
    out.twist.w = a.twist->w + alpha * (b.twist->w - a.twist->w);
  }
  return out;
}

void DeviceTrajectory::fill(int64_t first, std::span<DeviceSample> out) const {
  const auto count = static_cast<int64_t>(out.size());
  if (first < 0 || first + count > ticks_)
    throw std::out_of_range("DeviceTrajectory::fill: ticks outside the trajectory");
  if (given_) {
    std::copy_n(given_->begin() + first, count, out.begin());
    return;
  }
  // Without twists in the source, a tick inside the span gets central
  // differences of its neighbours' poses (one-sided at the span's ends), so
  // the poses of one tick either side of the block are needed too.
  const bool differences = !source_.has_twists && span_end_ - span_begin_ >= 2;
  const int64_t lo = differences ? std::max<int64_t>(0, first - 1) : first;
  const int64_t hi = differences ? std::min(ticks_, first + count + 1) : first + count;
  std::vector<Interpolated> values(static_cast<std::size_t>(hi - lo));
  int64_t segment = -1;
  TraceSample a, b;
  for (int64_t k = lo; k < hi; ++k)
    values[static_cast<std::size_t>(k - lo)] = interpolated(k, segment, a, b);
  auto value = [&](int64_t k) -> const Interpolated& {
    return values[static_cast<std::size_t>(k - lo)];
  };
  for (int64_t k = first; k < first + count; ++k) {
    DeviceSample& sample = out[static_cast<std::size_t>(k - first)];
    sample.tick = k;
    sample.t_ns = k * kTickNs;
    sample.pose = value(k).pose;
    sample.twist = value(k).twist;
    if (differences && k >= span_begin_ && k < span_end_) {
      const int64_t before = std::max(span_begin_, k - 1);
      const int64_t after = std::min(span_end_ - 1, k + 1);
      sample.twist = finite_difference(value(before).pose, value(after).pose,
                                       static_cast<double>(after - before) * kTickS);
    }
  }
}

DeviceSample DeviceTrajectory::at(int64_t tick) const {
  DeviceSample sample;
  fill(tick, std::span<DeviceSample>(&sample, 1));
  return sample;
}

std::vector<DeviceSample> DeviceTrajectory::all() const {
  std::vector<DeviceSample> samples(static_cast<std::size_t>(ticks_));
  fill(0, samples);
  return samples;
}

}  // namespace hb
