// Device trajectories: samples of the device's tool-frame pose over time,
// as read from CSV, imported from TUM, or made by a generator, and the
// resampling of any of them onto the 1 kHz clock.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
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

/// Sidecar metadata (`<name>.json` beside `<name>.csv`).
struct TraceInfo {
  std::string source = "unknown";  ///< "generator:press", "recorded", "tum:<file>", ...
  std::string frame = "world";
  std::string units = "m, s, rad";
  double rate_hz = 1000;
  std::string content_hash;  ///< hash of the CSV bytes (hex)
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
/// CSV: when the sidecar `<stem>.json` exists, source, frame, units and
/// rate come from it, and a content_hash that is not the hash of the CSV
/// bytes is an InputError (sidecar path, "/content_hash"): a stale sidecar.
/// TUM: times become relative to the first row (t_ns = round((t - t0) * 1e9),
/// exact for plain decimal stamps); the sidecar is not read.
Trace read_trace_file(const std::string& path, TraceFileFormat format);

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
