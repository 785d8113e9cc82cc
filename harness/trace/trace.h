// Device trajectories: samples of the device's tool-frame pose over time,
// as read from CSV, imported from TUM, or made by a generator, and the
// resampling of any of them onto the 1 kHz clock.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hapticbench/pose.h"
#include "hapticbench/renderer.h"

namespace hb {

/// One recorded device pose. t_ns: time since the trace's start (ns).
struct TraceSample {
  int64_t t_ns = 0;
  Pose pose;                   ///< tool frame in the world, m, qw,qx,qy,qz
  std::optional<Twist> twist;  ///< world frame; absent when the source has no velocity
};

/// The units a trace file's numbers are in, written "<length>, <time>,
/// <angle>" ("mm, s, deg") or as the length alone ("mm"). The reader
/// converts positions and velocities to metres and radians; times are
/// always the format's own (CSV t_ns in ns, TUM t in s), so the time unit
/// is "s" (the velocities' per second). Orientations are quaternions,
/// which have no unit: the angle unit applies to wx,wy,wz only.
struct TraceUnits {
  std::string length = "m";   ///< "m", "cm" or "mm"
  std::string angle = "rad";  ///< "rad" or "deg"
  double metres_per_unit() const;
  double radians_per_unit() const;
  bool is_si() const { return length == "m" && angle == "rad"; }
  std::string text() const { return length + ", s, " + angle; }
  bool operator==(const TraceUnits&) const = default;
};

/// What a units text may be, for error messages.
inline constexpr const char* kTraceUnitsExpected =
    "expected units \"<length>, s, <angle>\" with length m, cm or mm and angle rad or deg "
    "(\"mm, s, rad\"), or the length alone (\"mm\")";

/// Parses a units text (TraceUnits); nullopt for anything else.
std::optional<TraceUnits> parse_trace_units(std::string_view text);

/// Sidecar metadata (`<name>.json` beside `<name>.csv`), and what reading
/// the file did to its numbers.
struct TraceInfo {
  std::string source = "unknown";  ///< "generator:press", "recorded", "tum:<file>", ...
  std::string frame = "world";
  TraceUnits units;  ///< the units of the file's numbers (the samples are in m and rad)
  double rate_hz = 1000;
  std::string content_hash;  ///< hash of the CSV bytes (hex)
  /// Subtracted from the file's times so that the first sample is at t = 0
  /// (ns; device logs carry epoch stamps). 0 when the file starts at 0.
  int64_t start_shift_ns = 0;
};

struct Trace {
  std::vector<TraceSample> samples;  ///< strictly increasing t_ns
  TraceInfo info;
};

/// A trace's samples on request: a stored trace's rows or a generator's
/// samples, computed when asked for (an hour of them then costs no memory).
struct TraceSource {
  int64_t count = 0;        ///< samples
  bool has_twists = false;  ///< every sample carries a twist
  /// Sample `index` in [0, count); t_ns strictly increasing with the index.
  std::function<TraceSample(int64_t index)> at;
};

enum class TraceFileFormat {
  kHapticbenchCsv,  ///< header t_ns,px,py,pz,qw,qx,qy,qz[,vx,vy,vz,wx,wy,wz]
  kTum,             ///< "t tx ty tz qx qy qz qw" per line, t in seconds, '#' comments
};

/// Reads a trace file. Throws InputError naming the file and line for a
/// malformed row, a non-finite value, a non-unit quaternion (|q| off 1 by
/// more than 1e-3; otherwise renormalised) or non-increasing timestamps.
/// Times become relative to the first row (info.start_shift_ns; TUM:
/// t_ns = round((t - t0) * 1e9), exact for plain decimal stamps).
/// CSV: when the sidecar `<stem>.json` exists, source, frame, units and
/// rate come from it; a content_hash that is not the hash of the CSV bytes
/// (a stale sidecar) or units that parse_trace_units refuses are an
/// InputError naming the sidecar and the field. TUM: the sidecar is not read.
/// declared_units: the units the scenario gives the file (its /trace/units);
/// a sidecar that says otherwise is an InputError at its /units. Positions
/// and velocities are converted to m and rad from the units in force.
Trace read_trace_file(const std::string& path, TraceFileFormat format,
                      const std::optional<TraceUnits>& declared_units = std::nullopt);

/// What reading did to a file's numbers, for a description ("; mm, s, rad
/// converted to m, s, rad; times shifted by -1700000000.5 s to start at 0"),
/// or "" when it changed none.
std::string trace_reading_note(const TraceInfo& info);

/// A bound past which a trace is implausible for a desk device: most
/// likely its numbers are in other units than it says.
struct TracePlausibleLimit {
  std::string_view quantity;
  std::string_view unit;
  double high;  ///< in unit
  std::string_view why;
};

/// Every trace limit, in the order the warnings check them.
std::span<const TracePlausibleLimit> trace_plausible_limits();

/// Warnings for a trace beyond its plausible limits, each naming the value,
/// the bound and the units that would bring it within ("the trace may be in
/// mm"). Empty for a plausible trace.
std::vector<std::string> trace_plausibility_warnings(const Trace& trace);

/// Writes `<path>` (hapticbench CSV, full double precision) and the JSON
/// sidecar beside it (same stem, .json). Writes to temporary names first.
/// A path whose sidecar would be itself (`x.json`) is an InputError.
void write_trace_file(const std::string& path, const Trace& trace);

/// The sidecar of a trace file: same stem, extension .json.
std::string sidecar_path(const std::string& trace_path);

/// Whether `trace_path` and its sidecar are what `hapticbench generate`
/// wrote: the sidecar's source starts with "generator:" and its content
/// hash is the trace's (or the trace is gone). Only such a trace may be
/// overwritten by `generate`.
bool is_generated_trace(const std::string& trace_path);

/// The longest run hapticbench replays (s). A run's memory does not grow
/// with its length (device_trajectory.h, run_metrics.h), but its time and
/// its ticks log do (about 0.5 GB of log per hour and algorithm), so longer
/// traces are refused.
inline constexpr double kMaxRunDurationS = 3600;

/// Resamples onto the 1 kHz clock from t = 0 to the last sample: linear in
/// position, slerp in orientation (shorter arc). Tick k is at t_ns =
/// k * 1'000'000 exactly. Twists are interpolated when every sample has
/// one, otherwise estimated by central differences of the resampled poses
/// (one-sided at the ends; angular velocity in the world frame).
/// duration_ticks: number of ticks wanted (0 = as many as the trace covers,
/// floor(t_last / 1 ms) + 1). Ticks before the first or after the last
/// sample hold that sample's pose with zero twist. A trace that would give
/// more than kMaxRunDurationS of ticks throws InputError("", "samples", ...)
/// before anything is allocated. Every tick at once: runs use
/// DeviceTrajectory (device_trajectory.h), which computes them block by block.
std::vector<DeviceSample> resample_to_ticks(const Trace& trace, int64_t duration_ticks = 0);

}  // namespace hb
