// Synthetic device trajectories. Each generator is a closed-form motion
// (pose and its analytic twist as functions of time) sampled at 1 kHz.
// Smooth motions use minimum-jerk profiles, so position, velocity and
// acceleration are continuous and start and end at rest; only `jump` is
// discontinuous on purpose (`impact` stops within `depth`: smooth but sharp). All positions are the
// tool frame's origin in metres, world frame, z up; quaternion parameters are [w, x, y, z].
#include "harness/trace/generators.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <sstream>
#include <variant>

#include "hapticbench/input_error.h"

namespace hb {

namespace {

constexpr int64_t kSampleNs = 1'000'000;  // generators sample at 1 kHz
constexpr double kSamplesPerSecond = 1000.0;
constexpr double kMaxDurationS = kMaxRunDurationS;  // a longer trace could not be replayed
// The parameter every generator takes: the tick (s) whose sample repeats the previous one.
constexpr const char* kRepeatSampleKey = "repeat_sample_at_s";

struct MotionState {
  Pose pose;
  Twist twist;  // world frame
};

using Motion = std::function<MotionState(double t_s)>;

// ---------------------------------------------------------------------------
// Minimum-jerk profile s(u) = 10u^3 - 15u^4 + 6u^5 on u in [0, 1]: zero
// velocity and acceleration at both ends, so segments join with C2 continuity.

double min_jerk(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * u * (10.0 + u * (-15.0 + 6.0 * u));
}

/// ds/du.
double min_jerk_rate(double u) {
  if (u <= 0.0 || u >= 1.0) return 0.0;
  const double v = u * (1.0 - u);
  return 30.0 * v * v;
}

/// Integral of s from 0 to u (equals 1/2 at u = 1).
double min_jerk_integral(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * u * u * (2.5 + u * (-3.0 + u));
}

// ---------------------------------------------------------------------------
// Keyframed motion: between consecutive keyframes the origin moves on a
// straight line and the orientation turns about a fixed axis, both with the
// same minimum-jerk timing. Equal poses in a row make a hold.

struct Keyframe {
  double t_s;
  Pose pose;
};

MotionState keyframe_state(const std::vector<Keyframe>& keys, double t_s) {
  if (t_s <= keys.front().t_s) return {keys.front().pose, {}};
  if (t_s >= keys.back().t_s) return {keys.back().pose, {}};
  std::size_t i = 0;
  while (keys[i + 1].t_s <= t_s) ++i;
  const Keyframe& a = keys[i];
  const Keyframe& b = keys[i + 1];
  const double span = b.t_s - a.t_s;
  const double u = (t_s - a.t_s) / span;
  const double s = min_jerk(u);
  const double s_rate = min_jerk_rate(u) / span;  // ds/dt (1/s)

  Quat relative = a.pose.q.conjugate() * b.pose.q;
  if (relative.w() < 0) relative.coeffs() = -relative.coeffs();
  const Vec3 theta_body = rotation_vector(relative);  // fixed axis in a's frame

  MotionState state;
  state.pose.p = a.pose.p + s * (b.pose.p - a.pose.p);
  state.pose.q = (a.pose.q * quat_from_rotation_vector(s * theta_body)).normalized();
  state.twist.v = s_rate * (b.pose.p - a.pose.p);
  // The rotation axis is fixed in a's frame, so in the world it is
  // q_a * axis at every instant.
  state.twist.w = a.pose.q * (s_rate * theta_body);
  return state;
}

// ---------------------------------------------------------------------------
// SO(3) left Jacobian: the world-frame angular velocity of q(t) = exp(r(t)) q0
// is J_l(r) dr/dt.

Mat3 so3_left_jacobian(const Vec3& r) {
  const double angle = r.norm();
  const Mat3 s = skew(r);
  double linear;     // (1 - cos a) / a^2
  double quadratic;  // (a - sin a) / a^3
  if (angle < 1e-4) {
    const double a2 = angle * angle;
    linear = 0.5 - a2 / 24.0;
    quadratic = 1.0 / 6.0 - a2 / 120.0;
  } else {
    linear = (1.0 - std::cos(angle)) / (angle * angle);
    quadratic = (angle - std::sin(angle)) / (angle * angle * angle);
  }
  return Mat3::Identity() + linear * s + quadratic * s * s;
}

// ---------------------------------------------------------------------------
// Parameters.

std::string number_text(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

Vec3 point_param(const ParamSet& params, const std::string& key, const Vec3& fallback) {
  const std::vector<double> xyz =
      params.numbers(key, {fallback.x(), fallback.y(), fallback.z()}, 3);
  return Vec3(xyz[0], xyz[1], xyz[2]);
}

/// A direction, normalised; a zero vector has no direction.
Vec3 direction_param(const ParamSet& params, const std::string& key, const Vec3& fallback) {
  const Vec3 direction = point_param(params, key, fallback);
  if (!(direction.norm() > 1e-9))
    throw InputError("", params.field(key), "expected a non-zero direction [x, y, z]");
  return direction.normalized();
}

/// An orientation [w, x, y, z] within 1e-3 of unit length, renormalised.
Quat orientation_param(const ParamSet& params, const std::string& key) {
  const std::vector<double> wxyz = params.numbers(key, {1, 0, 0, 0}, 4);
  Quat q(wxyz[0], wxyz[1], wxyz[2], wxyz[3]);
  if (std::abs(q.norm() - 1.0) > 1e-3)
    throw InputError("", params.field(key),
                     "expected a unit quaternion [w, x, y, z] (|q| within 1e-3 of 1), got |q| = " +
                         number_text(q.norm()));
  return q.normalized();
}

/// A unit vector perpendicular to `axis`: world x projected onto the plane
/// normal to the axis, or world y when the axis is along x.
Vec3 perpendicular_unit(const Vec3& axis) {
  Vec3 candidate = Vec3::UnitX() - axis.dot(Vec3::UnitX()) * axis;
  if (candidate.norm() < 1e-6) candidate = Vec3::UnitY() - axis.dot(Vec3::UnitY()) * axis;
  return candidate.normalized();
}

/// Number of 1 ms intervals in the requested duration (samples = intervals + 1).
int64_t sample_intervals(double duration_s, const std::string& field) {
  if (!std::isfinite(duration_s) || duration_s <= 0 || duration_s > kMaxDurationS)
    throw InputError("", field,
                     "expected a duration in (0, " + number_text(kMaxDurationS) + "] s, got " +
                         number_text(duration_s));
  const int64_t intervals = std::llround(duration_s * kSamplesPerSecond);
  if (intervals < 1)
    throw InputError("", field,
                     "expected a duration of at least 0.001 s (two samples at 1 kHz), got " +
                         number_text(duration_s));
  return intervals;
}

/// The trace's length in seconds, as sampled (a whole number of ms).
double sampled_duration_s(const GeneratorRequest& request) {
  return static_cast<double>(sample_intervals(request.duration_s, "duration_s")) /
         kSamplesPerSecond;
}

GeneratedTrace sample_motion(std::string_view name, const GeneratorRequest& request,
                             Motion motion) {
  const int64_t intervals = sample_intervals(request.duration_s, "duration_s");
  GeneratedTrace trace;
  trace.info.source = "generator:" + std::string(name);
  trace.info.rate_hz = kSamplesPerSecond;
  trace.source.count = intervals + 1;
  trace.source.has_twists = true;
  trace.source.at = [motion = std::move(motion)](int64_t k) {
    const MotionState state = motion(static_cast<double>(k) / kSamplesPerSecond);
    return TraceSample{k * kSampleNs, state.pose, state.twist};
  };
  return trace;
}

/// Start pose, press axis and surface geometry shared by the generators that
/// press into a surface.
struct PressGeometry {
  Vec3 start;
  Vec3 axis;                // unit, direction of pressing
  double surface_distance;  // m from start to the surface along axis
  double depth;             // m past the surface
  Quat q;

  Vec3 at_surface() const { return start + surface_distance * axis; }
  Vec3 deepest() const { return start + (surface_distance + depth) * axis; }
};

PressGeometry press_geometry(const ParamSet& params, const std::string& start_key,
                             double default_depth) {
  PressGeometry geometry;
  geometry.start = point_param(params, start_key, Vec3(0, 0, 0.03));
  geometry.axis = direction_param(params, "axis", Vec3(0, 0, -1));
  geometry.surface_distance = params.number("surface_distance", 0.01, 0.0, 10.0);
  geometry.depth = params.number("depth", default_depth, 0.0, 1.0);
  geometry.q = orientation_param(params, "q");
  return geometry;
}

// ---------------------------------------------------------------------------
// The generators.

GeneratedTrace generate_press(const GeneratorRequest& request) {
  const ParamSet& params = request.params;
  const PressGeometry g = press_geometry(params, "start", 0.005);
  const double approach = params.number("approach_fraction", 0.3, 0.01, 0.97);
  const double press = params.number("press_fraction", 0.1, 0.01, 0.97);
  const double hold = params.number("hold_fraction", 0.4, 0.0, 0.97);
  // Presses in a row, each over duration / cycles (the fractions are of one
  // press).
  const long long cycles = params.integer("cycles", 1, 1, 100000);
  params.reject_unknown();
  if (approach + press + hold > 0.99)
    throw InputError("", params.field("hold_fraction"),
                     "expected approach_fraction + press_fraction + hold_fraction <= 0.99 "
                     "(time must be left to release), got " +
                         number_text(approach + press + hold));
  const double duration = sampled_duration_s(request);
  const double period = duration / static_cast<double>(cycles);  // s per press
  const std::vector<Keyframe> keys = {
      {0.0, {g.start, g.q}},
      {approach * period, {g.at_surface(), g.q}},
      {(approach + press) * period, {g.deepest(), g.q}},
      {(approach + press + hold) * period, {g.deepest(), g.q}},
      {period, {g.start, g.q}},
  };
  if (cycles == 1)
    return sample_motion("press", request, [=](double t) { return keyframe_state(keys, t); });
  // Each press starts and ends at rest at the start pose, so they join
  // smoothly.
  return sample_motion("press", request, [=](double t) {
    const double completed = std::min(std::floor(t / period), static_cast<double>(cycles - 1));
    return keyframe_state(keys, t - completed * period);
  });
}

GeneratedTrace generate_slide(const GeneratorRequest& request) {
  const ParamSet& params = request.params;
  const PressGeometry g = press_geometry(params, "start", 0.002);
  const Vec3 direction = direction_param(params, "direction", Vec3(1, 0, 0));
  const double distance = params.number("distance", 0.05, 0.0, 10.0);
  params.reject_unknown();
  if (std::abs(direction.dot(g.axis)) > 1e-6)
    throw InputError("", params.field("direction"),
                     "expected a direction perpendicular to axis (sliding along the surface)");
  const double duration = sampled_duration_s(request);
  const Vec3 slid = distance * direction;
  const std::vector<Keyframe> keys = {
      {0.0, {g.start, g.q}},
      {0.2 * duration, {g.deepest(), g.q}},
      {0.8 * duration, {g.deepest() + slid, g.q}},
      {duration, {g.start + slid, g.q}},
  };
  return sample_motion("slide", request, [=](double t) { return keyframe_state(keys, t); });
}

GeneratedTrace generate_rub(const GeneratorRequest& request) {
  const ParamSet& params = request.params;
  const PressGeometry g = press_geometry(params, "centre", 0.002);
  const double radius = params.number("radius", 0.01, 0.0, 10.0);
  const double turns = params.number("turns", 2.0, 0.0, 1000.0);
  params.reject_unknown();
  const double duration = sampled_duration_s(request);
  // The circle lies in the plane normal to the axis; the tool starts on it
  // at angle 0, above the surface, and is pressed, rubs and lifts there.
  const Vec3 e1 = perpendicular_unit(g.axis);
  const Vec3 e2 = e1.cross(g.axis);
  const double full_angle = 2.0 * std::numbers::pi * turns;
  const Vec3 rim_start = radius * e1;
  const Vec3 rim_end = radius * (std::cos(full_angle) * e1 + std::sin(full_angle) * e2);
  const double rub_begin = 0.2 * duration;
  const double rub_end = 0.8 * duration;
  const std::vector<Keyframe> press_in = {{0.0, {g.start + rim_start, g.q}},
                                          {rub_begin, {g.deepest() + rim_start, g.q}}};
  // Lift where the rub ended (turns need not be whole).
  const std::vector<Keyframe> lift = {{rub_end, {g.deepest() + rim_end, g.q}},
                                      {duration, {g.start + rim_end, g.q}}};
  return sample_motion("rub", request, [=](double t) {
    if (t <= rub_begin) return keyframe_state(press_in, t);
    if (t >= rub_end) return keyframe_state(lift, t);
    const double span = rub_end - rub_begin;
    const double u = (t - rub_begin) / span;
    const double phi = full_angle * min_jerk(u);
    const double phi_rate = full_angle * min_jerk_rate(u) / span;
    MotionState state;
    state.pose.p = g.deepest() + radius * (std::cos(phi) * e1 + std::sin(phi) * e2);
    state.pose.q = g.q;
    state.twist.v = radius * phi_rate * (-std::sin(phi) * e1 + std::cos(phi) * e2);
    return state;
  });
}

GeneratedTrace generate_twist(const GeneratorRequest& request) {
  const ParamSet& params = request.params;
  const PressGeometry g = press_geometry(params, "start", 0.005);
  const double amplitude = params.number("angle", 0.5, 0.0, std::numbers::pi);
  const double turns = params.number("turns", 2.0, 0.0, 1000.0);
  params.reject_unknown();
  const double duration = sampled_duration_s(request);
  const double twist_begin = 0.25 * duration;
  const double twist_end = 0.75 * duration;
  const std::vector<Keyframe> press_in = {{0.0, {g.start, g.q}}, {twist_begin, {g.deepest(), g.q}}};
  const double full_phase = 2.0 * std::numbers::pi * turns;
  // Release from wherever the oscillation ended (turns need not be whole)
  // back to the start pose.
  const Quat q_end =
      (quat_from_rotation_vector(amplitude * std::sin(full_phase) * g.axis) * g.q).normalized();
  const std::vector<Keyframe> release = {{twist_end, {g.deepest(), q_end}},
                                         {duration, {g.start, g.q}}};
  // Oscillation angle(t) = amplitude * sin(phase(t)) about the press axis,
  // with a minimum-jerk phase so it starts and ends at rest.
  return sample_motion("twist", request, [=](double t) {
    if (t <= twist_begin) return keyframe_state(press_in, t);
    if (t >= twist_end) return keyframe_state(release, t);
    const double span = twist_end - twist_begin;
    const double u = (t - twist_begin) / span;
    const double phase = full_phase * min_jerk(u);
    const double phase_rate = full_phase * min_jerk_rate(u) / span;
    const double angle = amplitude * std::sin(phase);
    const double angle_rate = amplitude * std::cos(phase) * phase_rate;
    MotionState state;
    state.pose.p = g.deepest();
    state.pose.q = (quat_from_rotation_vector(angle * g.axis) * g.q).normalized();
    state.twist.w = angle_rate * g.axis;
    return state;
  });
}

// Press to depth over the first press_fraction of the duration, then turn
// about turn_axis through the tool frame's origin, held pressed, to the end:
// a sustained rotation in contact. The rate rises to rate_rad_s along a
// minimum-jerk profile over the first kTurnRampS (or a tenth of the turn,
// if shorter), so that the motion starts from rest.
constexpr double kTurnRampS = 0.05;

GeneratedTrace generate_turn(const GeneratorRequest& request) {
  const ParamSet& params = request.params;
  const PressGeometry g = press_geometry(params, "start", 0.002);
  const Vec3 turn_axis = direction_param(params, "turn_axis", Vec3(0, 1, 0));
  const double rate = params.number("rate_rad_s", 4.0, 0.0, 100.0);
  const double press = params.number("press_fraction", 0.25, 0.01, 0.97);
  params.reject_unknown();
  const double duration = sampled_duration_s(request);
  const double turn_begin = press * duration;
  const double ramp = std::min(kTurnRampS, 0.1 * (duration - turn_begin));
  const std::vector<Keyframe> press_in = {{0.0, {g.start, g.q}}, {turn_begin, {g.deepest(), g.q}}};
  return sample_motion("turn", request, [=](double t) {
    if (t <= turn_begin) return keyframe_state(press_in, t);
    const double since = t - turn_begin;
    const double angle = since < ramp ? rate * ramp * min_jerk_integral(since / ramp)
                                      : rate * (0.5 * ramp + since - ramp);
    MotionState state;
    state.pose.p = g.deepest();
    state.pose.q = (quat_from_rotation_vector(angle * turn_axis) * g.q).normalized();
    state.twist.w = rate * (since < ramp ? min_jerk(since / ramp) : 1.0) * turn_axis;
    return state;
  });
}

GeneratedTrace generate_peg_in_hole(const GeneratorRequest& request) {
  const ParamSet& params = request.params;
  const Vec3 hole = point_param(params, "hole", Vec3(0, 0, 0));
  const double start_height = params.number("start_height", 0.03, 0.0, 10.0);
  const double insert_depth = params.number("insert_depth", 0.02, 0.0, 10.0);
  const std::vector<double> offset = params.numbers("offset", {0.001, 0.0}, 2);
  const double tilt = params.number("tilt_rad", 0.05, -1.5, 1.5);
  const Quat aligned = orientation_param(params, "q");
  // Inserted and twisted: amplitude (rad) of one oscillation about the
  // insertion axis (world z) during the final hold; 0 = no twist.
  const double twist = params.number("twist_rad", 0.0, -1.5, 1.5);
  params.reject_unknown();
  const double duration = sampled_duration_s(request);
  // Misaligned: shifted laterally by offset and tilted about world x; both
  // decay linearly with insertion depth until the peg is aligned.
  const Vec3 lateral(offset[0], offset[1], 0.0);
  const Quat tilted = (quat_from_rotation_vector(tilt * Vec3::UnitX()) * aligned).normalized();
  const std::vector<Keyframe> keys = {
      {0.0, {hole + lateral + start_height * Vec3::UnitZ(), tilted}},
      {0.3 * duration, {hole + lateral, tilted}},
      {0.8 * duration, {hole - insert_depth * Vec3::UnitZ(), aligned}},
      {duration, {hole - insert_depth * Vec3::UnitZ(), aligned}},
  };
  if (twist == 0.0)
    return sample_motion("peg_in_hole", request, [=](double t) { return keyframe_state(keys, t); });
  // angle(t) = twist * sin(2 pi s(u)) over the hold, with a minimum-jerk
  // phase s so that it starts and ends at rest, aligned.
  const double twist_begin = 0.8 * duration;
  return sample_motion("peg_in_hole", request, [=](double t) {
    if (t <= twist_begin) return keyframe_state(keys, t);
    const double span = duration - twist_begin;
    const double u = (t - twist_begin) / span;
    const double phase = 2.0 * std::numbers::pi * min_jerk(u);
    const double phase_rate = 2.0 * std::numbers::pi * min_jerk_rate(u) / span;
    const double angle = twist * std::sin(phase);
    MotionState state;
    state.pose.p = hole - insert_depth * Vec3::UnitZ();
    state.pose.q = (quat_from_rotation_vector(angle * Vec3::UnitZ()) * aligned).normalized();
    state.twist.w = twist * std::cos(phase) * phase_rate * Vec3::UnitZ();
    return state;
  });
}

GeneratedTrace generate_path(const GeneratorRequest& request) {
  const ParamSet& params = request.params;
  // points: [x0, y0, z0, x1, y1, z1, ...], two or more waypoints (m, world).
  std::size_t count = 6;
  if (params.has("points")) {
    const auto* list = std::get_if<std::vector<double>>(&params.values().at("points"));
    if (list != nullptr) count = list->size();
    if (count < 6 || count % 3 != 0)
      throw InputError("", params.field("points"),
                       "expected two or more waypoints [x0, y0, z0, x1, y1, z1, ...] (m), got " +
                           std::to_string(count) + " numbers");
  }
  const std::vector<double> xyz = params.numbers("points", {0, 0, 0.03, 0.05, 0, 0.03}, count);
  const Quat q = orientation_param(params, "q");
  const double speed = params.number("speed_mps", 0.1, 1e-4, 100.0);
  params.reject_unknown();
  const double duration = sampled_duration_s(request);
  // Each segment takes its length / speed_mps with a minimum-jerk profile
  // (at rest at every waypoint); then the last waypoint is held.
  std::vector<Keyframe> keys = {{0.0, {Vec3(xyz[0], xyz[1], xyz[2]), q}}};
  for (std::size_t i = 3; i < xyz.size(); i += 3) {
    const Vec3 point(xyz[i], xyz[i + 1], xyz[i + 2]);
    const double length = (point - keys.back().pose.p).norm();
    if (length == 0.0) continue;
    keys.push_back({keys.back().t_s + length / speed, {point, q}});
  }
  if (keys.back().t_s > duration)
    throw InputError("", params.field("speed_mps"),
                     "expected a speed that covers the path within the trace: the path takes " +
                         number_text(keys.back().t_s) + " s but the trace lasts " +
                         number_text(duration) + " s");
  if (keys.size() == 1) keys.push_back({duration, keys.front().pose});
  return sample_motion("path", request, [=](double t) { return keyframe_state(keys, t); });
}

GeneratedTrace generate_human_like(const GeneratorRequest& request) {
  const ParamSet& params = request.params;
  const Vec3 centre = point_param(params, "centre", Vec3(0, 0, 0.03));
  const Quat q_centre = orientation_param(params, "q");
  const double amplitude_m = params.number("amplitude_m", 0.01, 0.0, 1.0);
  const double amplitude_rad = params.number("amplitude_rad", 0.2, 0.0, 1.5);
  const double cutoff_hz = params.number("cutoff_hz", 5.0, 0.0, 10.0);
  const long long components = params.integer("components", 16, 1, 1000);
  params.reject_unknown();
  if (!(cutoff_hz > 0.0 && cutoff_hz < 10.0))
    throw InputError("", params.field("cutoff_hz"),
                     "expected a cutoff in (0, 10) Hz (human motion is below 10 Hz), got " +
                         number_text(cutoff_hz));
  const int64_t intervals = sample_intervals(request.duration_s, "duration_s");
  const double duration = static_cast<double>(intervals) / kSamplesPerSecond;
  // Frequencies are whole multiples of 1/duration, so every sinusoid fits
  // the trace a whole number of times: the trace is periodic and its DFT
  // has no energy at or above the cutoff (no leakage).
  const int64_t bins = static_cast<int64_t>(std::ceil(cutoff_hz * duration)) - 1;
  if (bins < 1)
    throw InputError("", params.field("cutoff_hz"),
                     "expected a cutoff above 1/duration = " + number_text(1.0 / duration) +
                         " Hz (the lowest frequency a " + number_text(duration) +
                         " s trace holds), got " + number_text(cutoff_hz));

  std::mt19937_64 rng(request.seed);
  // Uniform in [0, 1) from the top 53 bits: the same numbers on every
  // platform, unlike the standard distributions.
  auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };

  // Six channels: x, y, z offsets (m) and the rotation vector (rad), each a
  // sum of sinusoids. Kept as components, not samples, so that hour-long
  // traces cost no extra memory.
  struct Sinusoid {
    int64_t bin;       // frequency = bin / duration
    double amplitude;  // before scaling to the requested peak
    double phase;      // rad
  };
  constexpr int kChannels = 6;
  std::vector<Sinusoid> sinusoids[kChannels];
  for (auto& channel : sinusoids) {
    // Choose which bins 1..bins carry energy: all, or a random subset.
    std::vector<int64_t> chosen(static_cast<std::size_t>(bins));
    for (int64_t m = 0; m < bins; ++m) chosen[static_cast<std::size_t>(m)] = m + 1;
    const std::size_t count =
        std::min<std::size_t>(chosen.size(), static_cast<std::size_t>(components));
    for (std::size_t i = 0; i < count; ++i) {
      const std::size_t j =
          i + static_cast<std::size_t>(uniform() * static_cast<double>(chosen.size() - i));
      std::swap(chosen[i], chosen[std::min(j, chosen.size() - 1)]);
    }
    for (std::size_t i = 0; i < count; ++i) {
      const double frequency_hz = static_cast<double>(chosen[i]) / duration;
      // Amplitude falling as 1/f: hand motion is mostly slow.
      const double amplitude = (0.5 + 0.5 * uniform()) / frequency_hz;
      const double phase = 2.0 * std::numbers::pi * uniform();
      channel.push_back({chosen[i], amplitude, phase});
    }
  }
  // Value and time derivative of one channel at sample k (unscaled).
  auto evaluate = [=](int c, int64_t k, double& value, double& rate) {
    value = 0.0;
    rate = 0.0;
    for (const Sinusoid& sinusoid : sinusoids[c]) {
      // Phase from the integer sample index, reduced exactly modulo the
      // period, so long traces keep full precision.
      const int64_t cycle_index = (k * sinusoid.bin) % intervals;
      const double argument = 2.0 * std::numbers::pi * static_cast<double>(cycle_index) /
                                  static_cast<double>(intervals) +
                              sinusoid.phase;
      const double omega = 2.0 * std::numbers::pi * static_cast<double>(sinusoid.bin) / duration;
      value += sinusoid.amplitude * std::sin(argument);
      rate += sinusoid.amplitude * omega * std::cos(argument);
    }
  };
  // Scale each channel so that its largest excursion equals the amplitude.
  double scale[kChannels];
  for (int c = 0; c < kChannels; ++c) {
    double peak = 0.0;
    for (int64_t k = 0; k <= intervals; ++k) {
      double value, rate;
      evaluate(c, k, value, rate);
      peak = std::max(peak, std::abs(value));
    }
    const double target = c < 3 ? amplitude_m : amplitude_rad;
    scale[c] = peak > 0.0 ? target / peak : 0.0;
  }

  return sample_motion("human_like", request, [=](double t) {
    const int64_t k = std::llround(t * kSamplesPerSecond);
    double value[kChannels], rate[kChannels];
    for (int c = 0; c < kChannels; ++c) {
      evaluate(c, k, value[c], rate[c]);
      value[c] *= scale[c];
      rate[c] *= scale[c];
    }
    const Vec3 offset(value[0], value[1], value[2]);
    const Vec3 rotation(value[3], value[4], value[5]);
    const Vec3 rotation_rate(rate[3], rate[4], rate[5]);
    MotionState state;
    state.pose.p = centre + offset;
    state.pose.q = (quat_from_rotation_vector(rotation) * q_centre).normalized();
    state.twist.v = Vec3(rate[0], rate[1], rate[2]);
    state.twist.w = so3_left_jacobian(rotation) * rotation_rate;
    return state;
  });
}

GeneratedTrace generate_impact(const GeneratorRequest& request) {
  const ParamSet& params = request.params;
  const PressGeometry g = press_geometry(params, "start", 0.005);
  const double speed = params.number("speed_mps", 0.5, 1e-3, 100.0);
  params.reject_unknown();
  if (g.surface_distance <= 0.0 || g.depth <= 0.0)
    throw InputError("", params.field(g.depth <= 0.0 ? "depth" : "surface_distance"),
                     "expected a positive distance (m) for an impact");
  const double duration = sampled_duration_s(request);
  // Rest for 10% of the trace, reach speed_mps over the first half of the
  // way to the surface, cross the surface at that speed, and stop `depth`
  // past it with a minimum-jerk deceleration; then hold.
  const double accelerate_s = g.surface_distance / speed;
  const double cruise_s = 0.5 * g.surface_distance / speed;
  const double decelerate_s = 2.0 * g.depth / speed;
  const double begin = 0.1 * duration;
  const double impact = begin + accelerate_s + cruise_s;
  const double stop = impact + decelerate_s;
  if (stop > duration)
    throw InputError("", params.field("speed_mps"),
                     "expected a speed that reaches the surface and stops within the trace: "
                     "the motion takes " +
                         number_text(stop) + " s but the trace lasts " + number_text(duration) +
                         " s");
  return sample_motion("impact", request, [=](double t) {
    double travelled = 0.0;  // m along the axis
    double velocity = 0.0;   // m/s along the axis
    if (t >= stop) {
      travelled = g.surface_distance + g.depth;
    } else if (t >= impact) {
      const double u = (t - impact) / decelerate_s;
      travelled = g.surface_distance + speed * decelerate_s * (u - min_jerk_integral(u));
      velocity = speed * (1.0 - min_jerk(u));
    } else if (t >= begin + accelerate_s) {
      travelled = 0.5 * g.surface_distance + speed * (t - begin - accelerate_s);
      velocity = speed;
    } else if (t > begin) {
      const double u = (t - begin) / accelerate_s;
      travelled = speed * accelerate_s * min_jerk_integral(u);
      velocity = speed * min_jerk(u);
    }
    MotionState state;
    state.pose = Pose{g.start + travelled * g.axis, g.q};
    state.twist.v = velocity * g.axis;
    return state;
  });
}

GeneratedTrace generate_jump(const GeneratorRequest& request) {
  const ParamSet& params = request.params;
  const double duration = sampled_duration_s(request);
  const Vec3 p = point_param(params, "p", Vec3(0, 0, 0.03));
  const Quat q = orientation_param(params, "q");
  const Vec3 jump = point_param(params, "jump", Vec3(0, 0, -0.005));
  const Vec3 rotation = point_param(params, "rotation", Vec3::Zero());
  const double at_s = params.number("at_s", 0.5 * duration, 0.0, duration);
  params.reject_unknown();
  const Pose before{p, q};
  const Pose after{p + jump, (quat_from_rotation_vector(rotation) * q).normalized()};
  const int64_t jump_ns = std::llround(at_s * 1e9);
  // Twists stay zero: the discontinuity is the point of this trace.
  return sample_motion("jump", request, [=](double t) {
    const int64_t k = std::llround(t * kSamplesPerSecond);
    return MotionState{k * kSampleNs >= jump_ns ? after : before, {}};
  });
}

GeneratedTrace generate_rest(const GeneratorRequest& request) {
  const ParamSet& params = request.params;
  const Pose pose{point_param(params, "p", Vec3(0, 0, 0.015)), orientation_param(params, "q")};
  params.reject_unknown();
  return sample_motion("rest", request, [=](double) { return MotionState{pose, {}}; });
}

constexpr GeneratorEntry kGenerators[] = {
    {"press",
     "approach along axis, press depth past the surface, hold (>= 40%), release; cycles times",
     generate_press},
    {"slide", "press to depth, slide distance along direction on the surface, lift",
     generate_slide},
    {"rub", "press to depth and rub in circles of radius for turns, lift", generate_rub},
    {"twist", "press to depth and oscillate by angle about the press axis, release",
     generate_twist},
    {"turn",
     "press to depth, then turn at rate_rad_s (reached in 0.05 s) about turn_axis through the "
     "tool frame's origin, held pressed, to the end",
     generate_turn},
    {"peg_in_hole",
     "approach a hole misaligned by offset and tilt_rad, insert insert_depth along -z, twist "
     "by twist_rad",
     generate_peg_in_hole},
    {"path", "through waypoints points at speed_mps, at rest at each, hold the last",
     generate_path},
    {"human_like", "band-limited random motion below cutoff_hz (< 10 Hz) around centre",
     generate_human_like},
    {"impact", "reach speed_mps, cross the surface at that speed, stop depth past it, hold",
     generate_impact},
    {"jump", "hold, jump by jump (and rotation) at at_s with zero twist, hold", generate_jump},
    {"rest", "constant pose p, q for the whole duration", generate_rest},
};

}  // namespace

std::span<const GeneratorEntry> generator_table() { return kGenerators; }

GeneratedTrace make_generated_trace(const std::string& name, const GeneratorRequest& request,
                                    const std::string& field) {
  for (const GeneratorEntry& entry : kGenerators) {
    if (entry.name != name) continue;
    // Name the duration beside the generator field ("/trace/duration_s").
    const std::size_t slash = field.rfind('/');
    const std::string duration_field =
        (slash == std::string::npos ? std::string() : field.substr(0, slash + 1)) + "duration_s";
    const int64_t intervals = sample_intervals(request.duration_s, duration_field);
    if (!request.params.has(kRepeatSampleKey)) return entry.generate(request);
    // A device glitch, for every generator: the sample at repeat_sample_at_s
    // (to the nearest tick, not the first) repeats the one before it, pose
    // and twist, with its own time; the samples after it are unchanged.
    const double repeat_at_s =
        request.params.number(kRepeatSampleKey, 0.0, 1.0 / kSamplesPerSecond,
                              static_cast<double>(intervals) / kSamplesPerSecond);
    GeneratorRequest rest = request;
    rest.params = ParamSet(request.params.prefix());
    for (const auto& [key, value] : request.params.values())
      if (key != kRepeatSampleKey) rest.params.set(key, value);
    GeneratedTrace trace = entry.generate(rest);
    const int64_t repeated = std::llround(repeat_at_s * kSamplesPerSecond);
    trace.source.at = [at = std::move(trace.source.at), repeated](int64_t k) {
      if (k != repeated) return at(k);
      TraceSample sample = at(k - 1);
      sample.t_ns = k * kSampleNs;
      return sample;
    };
    return trace;
  }
  std::string known;
  for (const GeneratorEntry& entry : kGenerators)
    known += (known.empty() ? "" : ", ") + std::string(entry.name);
  throw InputError("", field, "unknown generator \"" + name + "\" (known: " + known + ")");
}

Trace generate_trace(const std::string& name, const GeneratorRequest& request,
                     const std::string& field) {
  return make_generated_trace(name, request, field).sampled();
}

Trace GeneratedTrace::sampled() const {
  Trace trace;
  trace.info = info;
  trace.samples.reserve(static_cast<std::size_t>(source.count));
  for (int64_t k = 0; k < source.count; ++k) trace.samples.push_back(source.at(k));
  return trace;
}

}  // namespace hb
