// Reading and writing device traces: the hapticbench CSV with its JSON
// sidecar, and import of the TUM trajectory format. Every malformed input
// is an InputError naming the file, the line and what was expected.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "algorithms/core/replacing_file.h"
#include "hapticbench/content_hash.h"
#include "hapticbench/input_error.h"
#include "harness/process/input_file.h"
#include "harness/trace/trace.h"

namespace hb {

namespace {

constexpr std::string_view kPoseHeader = "t_ns,px,py,pz,qw,qx,qy,qz";
constexpr int64_t kOneTickNs = 1'000'000;  // the 1 kHz virtual clock
constexpr std::string_view kPoseTwistHeader = "t_ns,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz";
constexpr std::string_view kColumnNames[] = {"t_ns", "px", "py", "pz", "qw", "qx", "qy",
                                             "qz",   "vx", "vy", "vz", "wx", "wy", "wz"};
constexpr std::string_view kTumColumnNames[] = {"t", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};

/// A quaternion whose norm is further than this from 1 is rejected as a
/// corrupt row rather than silently fixed.
constexpr double kUnitQuaternionTolerance = 1e-3;
/// Below this a quaternion is already unit to working precision and is kept
/// bit for bit, so that writing and reading a trace returns the same doubles.
constexpr double kAlreadyUnitTolerance = 1e-14;

std::string line_location(int64_t line) { return "line " + std::to_string(line); }

std::string in_quotes(std::string_view text) {
  std::string out;
  out.reserve(text.size() + 2);
  out += '"';
  out += text;
  out += '"';
  return out;
}

std::string_view trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t");
  return text.substr(first, last - first + 1);
}

std::string read_file_bytes(const std::string& path) {
  require_regular_file(path, "a trace file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open the trace file for reading");
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// Splits file bytes into lines; a trailing '\r' (files written on Windows)
/// is dropped from each.
std::vector<std::string_view> split_lines(std::string_view bytes) {
  std::vector<std::string_view> lines;
  std::size_t start = 0;
  while (start < bytes.size()) {
    std::size_t end = bytes.find('\n', start);
    if (end == std::string_view::npos) end = bytes.size();
    std::string_view line = bytes.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    start = end + 1;
  }
  return lines;
}

/// Reads the rows of one file and reports errors at the current line.
class RowParser {
 public:
  explicit RowParser(const std::string& path) : path_(path) {}

  void set_line(int64_t line) { line_ = line; }
  int64_t line() const { return line_; }

  [[noreturn]] void fail(const std::string& message) const {
    throw InputError(path_, line_location(line_), message);
  }

  double finite_number(std::string_view field, std::string_view column) const {
    field = trim(field);
    double value = 0;
    const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
    if (error != std::errc() || end != field.data() + field.size() || field.empty())
      fail("expected a number in column " + std::string(column) + ", found " + in_quotes(field));
    if (!std::isfinite(value))
      fail("expected a finite number in column " + std::string(column) + ", found " +
           in_quotes(field));
    return value;
  }

  int64_t integer_ns(std::string_view field, std::string_view column) const {
    field = trim(field);
    int64_t value = 0;
    const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
    if (error != std::errc() || end != field.data() + field.size() || field.empty())
      fail("expected a whole number of nanoseconds in column " + std::string(column) + ", found " +
           in_quotes(field));
    return value;
  }

  /// Checks |q| is within kUnitQuaternionTolerance of 1 and renormalises.
  Quat unit_quaternion(double w, double x, double y, double z) const {
    Quat q(w, x, y, z);
    const double norm = q.norm();
    if (std::abs(norm - 1.0) > kUnitQuaternionTolerance) {
      std::ostringstream found;
      found.precision(17);
      found << norm;
      fail("expected a unit quaternion qw,qx,qy,qz (|q| within 1e-3 of 1), found |q| = " +
           found.str());
    }
    if (std::abs(norm - 1.0) > kAlreadyUnitTolerance) q.coeffs() /= norm;
    return q;
  }

  /// t_ns after `previous` (the row before's time, none for the first row).
  void check_increasing(std::optional<int64_t> previous, int64_t t_ns) const {
    if (previous && t_ns <= *previous)
      fail("expected t_ns to increase strictly from row to row, found " + std::to_string(t_ns) +
           " after " + std::to_string(*previous));
  }

  void check_enough_samples(const std::vector<TraceSample>& samples) const {
    if (samples.size() < 2)
      fail("expected at least 2 samples, found " + std::to_string(samples.size()));
    // Samples closer together than one 1 kHz tick in all: times in other
    // units than ns (a trace "sampled at 1 ns" replayed as one tick).
    const int64_t span_ns = samples.back().t_ns - samples.front().t_ns;
    if (span_ns < kOneTickNs)
      fail("the " + std::to_string(samples.size()) + " samples span " + std::to_string(span_ns) +
           " ns, less than one 1 kHz tick (1,000,000 ns): t_ns must be nanoseconds");
  }

  /// A row's time made relative to the first row's (t0_ns), which a trace
  /// may start at (device logs carry epoch stamps).
  int64_t relative_to_start(int64_t t_ns, int64_t t0_ns) const {
    int64_t relative = 0;
    if (__builtin_sub_overflow(t_ns, t0_ns, &relative))
      fail("expected times within 292 years of the first, found " + std::to_string(t_ns) +
           " ns after a first sample at " + std::to_string(t0_ns) + " ns");
    return relative;
  }

 private:
  const std::string& path_;
  int64_t line_ = 0;
};

std::vector<std::string_view> split(std::string_view line, char separator) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = line.find(separator, start);
    if (end == std::string_view::npos) {
      fields.push_back(line.substr(start));
      return fields;
    }
    fields.push_back(line.substr(start, end - start));
    start = end + 1;
  }
}

std::vector<std::string_view> split_whitespace(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = line.find_first_not_of(" \t");
  while (start != std::string_view::npos) {
    std::size_t end = line.find_first_of(" \t", start);
    if (end == std::string_view::npos) end = line.size();
    fields.push_back(line.substr(start, end - start));
    start = line.find_first_not_of(" \t", end);
  }
  return fields;
}

/// Room for the samples of a file of `line_count` lines and `byte_count`
/// bytes: a sample row holds at least 8 numbers and 7 separators (15
/// bytes), so blank or comment lines (one byte each, against a 120-byte
/// sample) cannot make the reservation outgrow the memory rule.
std::size_t row_capacity(std::size_t line_count, std::size_t byte_count) {
  constexpr std::size_t kMinRowBytes = 15;
  return std::min(line_count, byte_count / kMinRowBytes + 1);
}

/// Average sampling rate (Hz) of strictly increasing samples.
double average_rate_hz(const std::vector<TraceSample>& samples) {
  const double span_ns = static_cast<double>(samples.back().t_ns - samples.front().t_ns);
  return static_cast<double>(samples.size() - 1) * 1e9 / span_ns;
}

/// The rows of a hapticbench CSV, times relative to the first row's
/// (start_ns: the first row's time in the file).
std::vector<TraceSample> parse_hapticbench_csv(const std::string& path, std::string_view bytes,
                                               int64_t& start_ns) {
  const std::vector<std::string_view> lines = split_lines(bytes);
  RowParser parser(path);
  parser.set_line(1);
  const std::string expected_header =
      "expected the header " + in_quotes(kPoseHeader) + " or " + in_quotes(kPoseTwistHeader);
  if (lines.empty()) parser.fail(expected_header + ", found an empty file");
  const std::string_view header = trim(lines[0]);
  if (header != kPoseHeader && header != kPoseTwistHeader)
    parser.fail(expected_header + ", found " + in_quotes(header));
  const bool has_twist = header == kPoseTwistHeader;
  const std::size_t columns = has_twist ? 14 : 8;

  std::vector<TraceSample> samples;
  samples.reserve(row_capacity(lines.size(), bytes.size()));
  std::optional<int64_t> previous_file_t_ns;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    parser.set_line(static_cast<int64_t>(i) + 1);
    if (trim(lines[i]).empty()) continue;
    const std::vector<std::string_view> fields = split(lines[i], ',');
    if (fields.size() != columns)
      parser.fail("expected " + std::to_string(columns) + " comma-separated values (" +
                  std::string(header) + "), found " + std::to_string(fields.size()));
    TraceSample sample;
    const int64_t file_t_ns = parser.integer_ns(fields[0], kColumnNames[0]);
    double value[14];
    for (std::size_t c = 1; c < columns; ++c)
      value[c] = parser.finite_number(fields[c], kColumnNames[c]);
    if (samples.empty()) start_ns = file_t_ns;
    parser.check_increasing(previous_file_t_ns, file_t_ns);
    previous_file_t_ns = file_t_ns;
    sample.t_ns = parser.relative_to_start(file_t_ns, start_ns);
    sample.pose.p = Vec3(value[1], value[2], value[3]);
    sample.pose.q = parser.unit_quaternion(value[4], value[5], value[6], value[7]);
    if (has_twist)
      sample.twist =
          Twist{Vec3(value[8], value[9], value[10]), Vec3(value[11], value[12], value[13])};
    samples.push_back(sample);
  }
  parser.set_line(static_cast<int64_t>(lines.size()) + 1);
  parser.check_enough_samples(samples);
  return samples;
}

/// Time stamps beyond this (s) would overflow int64 nanoseconds.
constexpr double kMaxTumSeconds = 9e9;

/// Nanoseconds of a plain decimal number of seconds ("1305031102.175304"),
/// rounded to the nearest ns (halves away from zero), computed exactly with
/// integers; nullopt for any other spelling (exponents, "inf", ...).
std::optional<int64_t> decimal_seconds_to_ns(std::string_view text) {
  bool negative = false;
  if (!text.empty() && (text.front() == '-' || text.front() == '+')) {
    negative = text.front() == '-';
    text.remove_prefix(1);
  }
  const std::size_t point = text.find('.');
  const std::string_view whole = text.substr(0, point);
  const std::string_view fraction =
      point == std::string_view::npos ? std::string_view() : text.substr(point + 1);
  auto all_digits = [](std::string_view digits) {
    return digits.find_first_not_of("0123456789") == std::string_view::npos;
  };
  if (whole.empty() && fraction.empty()) return std::nullopt;
  if (!all_digits(whole) || !all_digits(fraction) || whole.size() > 10) return std::nullopt;
  int64_t seconds = 0;
  for (char c : whole) seconds = seconds * 10 + (c - '0');
  int64_t nanoseconds = 0;
  for (std::size_t i = 0; i < 9; ++i)
    nanoseconds = nanoseconds * 10 + (i < fraction.size() ? fraction[i] - '0' : 0);
  if (fraction.size() > 9 && fraction[9] >= '5') ++nanoseconds;
  const int64_t total = seconds * 1'000'000'000 + nanoseconds;
  return negative ? -total : total;
}

/// The poses of a TUM file, times relative to the first pose's (t0_ns: the
/// first pose's time in the file, ns).
std::vector<TraceSample> parse_tum(const std::string& path, std::string_view bytes,
                                   int64_t& t0_ns) {
  const std::vector<std::string_view> lines = split_lines(bytes);
  RowParser parser(path);
  std::vector<TraceSample> samples;
  samples.reserve(row_capacity(lines.size(), bytes.size()));
  for (std::size_t i = 0; i < lines.size(); ++i) {
    parser.set_line(static_cast<int64_t>(i) + 1);
    const std::string_view line = trim(lines[i]);
    if (line.empty() || line.front() == '#') continue;
    const std::vector<std::string_view> fields = split_whitespace(line);
    if (fields.size() != 8)
      parser.fail("expected 8 whitespace-separated values \"t tx ty tz qx qy qz qw\", found " +
                  std::to_string(fields.size()));
    double value[8];
    for (std::size_t c = 0; c < 8; ++c)
      value[c] = parser.finite_number(fields[c], kTumColumnNames[c]);
    if (!(std::abs(value[0]) < kMaxTumSeconds))
      parser.fail("expected a time in seconds of magnitude below 9e9 in column t, found " +
                  in_quotes(fields[0]));
    // Epoch stamps (~1.3e9 s) have a double resolution of ~240 ns, so a
    // plain decimal is converted to ns exactly with integers instead.
    const std::optional<int64_t> exact_ns = decimal_seconds_to_ns(fields[0]);
    const int64_t absolute_ns = exact_ns ? *exact_ns : std::llround(value[0] * 1e9);
    if (samples.empty()) t0_ns = absolute_ns;
    TraceSample sample;
    sample.t_ns = absolute_ns - t0_ns;
    parser.check_increasing(samples.empty() ? std::nullopt : std::optional(samples.back().t_ns),
                            sample.t_ns);
    sample.pose.p = Vec3(value[1], value[2], value[3]);
    sample.pose.q = parser.unit_quaternion(value[7], value[4], value[5], value[6]);
    samples.push_back(sample);
  }
  parser.set_line(static_cast<int64_t>(lines.size()) + 1);
  parser.check_enough_samples(samples);
  return samples;
}

/// Reads the sidecar's metadata into info and checks that its hash is the
/// hash of the trace bytes: a stale sidecar describes another trace.
void read_sidecar(const std::string& path, const std::string& trace_path, TraceInfo& info) {
  const std::string bytes = read_file_bytes(path);
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(bytes);
  } catch (const nlohmann::json::parse_error& error) {
    throw InputError(path, "", std::string("expected a JSON object: ") + error.what());
  }
  if (!json.is_object()) throw InputError(path, "", "expected a JSON object");
  auto text = [&](const char* key, std::string& out) {
    if (!json.contains(key)) return;
    if (!json[key].is_string()) throw InputError(path, std::string("/") + key, "expected a string");
    out = json[key].get<std::string>();
  };
  text("source", info.source);
  text("frame", info.frame);
  std::string units = info.units.text();
  text("units", units);
  const std::optional<TraceUnits> parsed = parse_trace_units(units);
  if (!parsed)
    throw InputError(path, "/units",
                     std::string(kTraceUnitsExpected) + ", found " + in_quotes(units));
  info.units = *parsed;
  if (json.contains("rate_hz")) {
    const auto& rate = json["rate_hz"];
    if (!rate.is_number() || !(rate.get<double>() > 0))
      throw InputError(path, "/rate_hz", "expected a positive number (Hz)");
    info.rate_hz = rate.get<double>();
  }
  if (!json.contains("content_hash") || !json["content_hash"].is_string()) {
    // Most likely a file of another kind that happens to share the trace's
    // name: say what the name makes it and how to get out of the way.
    const bool scenario_like = json.contains("trace") || json.contains("scene");
    throw InputError(
        path, "/content_hash",
        "expected the hex hash of " + trace_path +
            ": a .json file with a trace's name beside it is read as the trace's sidecar "
            "(its metadata, with the hash that ties it to the trace's bytes)" +
            (scenario_like ? std::string(", and this one looks like a scenario: rename the "
                                         "scenario or the trace so that their names differ")
                           : std::string("; rename or remove it if it is not the sidecar")));
  }
  const std::string recorded = json["content_hash"].get<std::string>();
  if (recorded != info.content_hash)
    throw InputError(path, "/content_hash",
                     "expected " + in_quotes(info.content_hash) + ", the hash of " + trace_path +
                         ", found " + in_quotes(recorded) +
                         ": the sidecar is stale (regenerate it or delete it)");
}

void append_double(std::string& out, double value) {
  char text[32];
  const int length = std::snprintf(text, sizeof text, "%.17g", value);
  out.append(text, static_cast<std::size_t>(length));
}

std::string format_csv(const Trace& trace, bool with_twist) {
  std::string out(with_twist ? kPoseTwistHeader : kPoseHeader);
  out += '\n';
  out.reserve(trace.samples.size() * (with_twist ? 300 : 170));
  for (const TraceSample& sample : trace.samples) {
    out += std::to_string(sample.t_ns);
    const Pose& pose = sample.pose;
    double values[13] = {pose.p.x(), pose.p.y(), pose.p.z(), pose.q.w(), pose.q.x(),
                         pose.q.y(), pose.q.z(), 0,          0,          0,
                         0,          0,          0};
    if (with_twist) {
      for (int i = 0; i < 3; ++i) {
        values[7 + i] = sample.twist->v[i];
        values[10 + i] = sample.twist->w[i];
      }
    }
    const int count = with_twist ? 13 : 7;
    for (int i = 0; i < count; ++i) {
      out += ',';
      append_double(out, values[i]);
    }
    out += '\n';
  }
  return out;
}

/// Positions and velocities from `units` to m and rad (in place).
void convert_to_si(std::vector<TraceSample>& samples, const TraceUnits& units) {
  if (units.is_si()) return;
  const double metres = units.metres_per_unit(), radians = units.radians_per_unit();
  for (TraceSample& sample : samples) {
    sample.pose.p *= metres;
    if (sample.twist) {
      sample.twist->v *= metres;
      sample.twist->w *= radians;
    }
  }
}

constexpr TracePlausibleLimit kTraceLimits[] = {
    {"span of the positions along an axis", "m", 2, "desk devices reach 0.1 to 1 m"},
    {"distance from the world's origin", "m", 10, "scenes are built in metres about the origin"},
    {"speed between consecutive samples", "m/s", 5, "a hand moves at up to 2 to 3 m/s"},
    {"angular velocity wx,wy,wz", "rad/s", 50, "a wrist turns at up to 20 to 30 rad/s"},
};

/// The largest value of each limit's quantity over a trace.
std::array<double, std::size(kTraceLimits)> trace_extremes(const Trace& trace) {
  const auto& samples = trace.samples;
  Vec3 low = samples.front().pose.p, high = low;
  double distance = 0, speed = 0, angular_speed = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Vec3& p = samples[i].pose.p;
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
    distance = std::max(distance, p.norm());
    if (i > 0) {
      const double dt_s = static_cast<double>(samples[i].t_ns - samples[i - 1].t_ns) * 1e-9;
      speed = std::max(speed, (p - samples[i - 1].pose.p).norm() / dt_s);
    }
    if (samples[i].twist) angular_speed = std::max(angular_speed, samples[i].twist->w.norm());
  }
  return {(high - low).maxCoeff(), distance, speed, angular_speed};
}

}  // namespace

double TraceUnits::metres_per_unit() const {
  return length == "mm" ? 1e-3 : length == "cm" ? 1e-2 : 1.0;
}

double TraceUnits::radians_per_unit() const {
  return angle == "deg" ? std::numbers::pi / 180 : 1.0;
}

std::optional<TraceUnits> parse_trace_units(std::string_view text) {
  std::vector<std::string_view> fields = split(text, ',');
  for (std::string_view& field : fields) field = trim(field);
  if (fields.size() != 1 && fields.size() != 3) return std::nullopt;
  TraceUnits units;
  if (fields[0] != "m" && fields[0] != "cm" && fields[0] != "mm") return std::nullopt;
  units.length = std::string(fields[0]);
  if (fields.size() == 3) {
    if (fields[1] != "s" || (fields[2] != "rad" && fields[2] != "deg")) return std::nullopt;
    units.angle = std::string(fields[2]);
  }
  return units;
}

std::string trace_reading_note(const TraceInfo& info) {
  std::ostringstream note;
  note.precision(15);
  if (!info.units.is_si())
    note << "; " << info.units.text() << " converted to " << TraceUnits{}.text();
  if (info.start_shift_ns != 0)
    note << "; times shifted by " << -static_cast<double>(info.start_shift_ns) * 1e-9
         << " s to start at 0";
  return note.str();
}

std::span<const TracePlausibleLimit> trace_plausible_limits() { return kTraceLimits; }

std::vector<std::string> trace_plausibility_warnings(const Trace& trace) {
  std::vector<std::string> warnings;
  if (trace.samples.empty()) return warnings;
  const auto extremes = trace_extremes(trace);
  const std::string declare =
      ": declare the units (\"units\" in the trace's sidecar or at the scenario's /trace/units; "
      "docs/limits.md)";
  // One warning for the lengths, one for the angles, each listing every
  // quantity past its limit and the units that would bring all within.
  auto warn = [&](std::size_t first, std::size_t last, const std::string& guess) {
    std::ostringstream text;
    for (std::size_t i = first; i < last; ++i) {
      const TracePlausibleLimit& limit = kTraceLimits[i];
      if (!(extremes[i] > limit.high)) continue;
      text << (text.tellp() == 0 ? "" : ", ") << limit.quantity << " " << extremes[i] << " "
           << limit.unit << " (plausible up to " << limit.high << " " << limit.unit << ": "
           << limit.why << ")";
    }
    if (text.tellp() == 0) return;
    warnings.push_back("implausible for a desk device when read as " + trace.info.units.text() +
                       ": " + text.str() + (guess.empty() ? "" : "; the trace may be in " + guess) +
                       declare);
  };
  auto fits = [&](std::size_t first, std::size_t last, double scale) {
    for (std::size_t i = first; i < last; ++i)
      if (extremes[i] * scale > kTraceLimits[i].high) return false;
    return true;
  };
  std::string length_guess;
  for (const auto& [name, scale] : {std::pair{"mm", 1e-3}, std::pair{"cm", 1e-2}})
    if (fits(0, 3, scale)) length_guess += (length_guess.empty() ? "" : " or ") + std::string(name);
  warn(0, 3, length_guess);
  warn(3, 4, fits(3, 4, std::numbers::pi / 180) ? "deg (its velocities wx,wy,wz in deg/s)" : "");
  return warnings;
}

std::string sidecar_path(const std::string& trace_path) {
  return std::filesystem::path(trace_path).replace_extension(".json").string();
}

bool is_generated_trace(const std::string& trace_path) {
  // A sidecar is a few hundred bytes and a trace of a day at 1 kHz some
  // 15 GB; larger files are not read to decide.
  constexpr std::uintmax_t kMaxSidecarBytes = 1 << 20, kMaxTraceBytes = std::uintmax_t{1} << 34;
  const std::string sidecar = sidecar_path(trace_path);
  std::error_code error;
  if (!std::filesystem::is_regular_file(sidecar, error) ||
      std::filesystem::file_size(sidecar, error) > kMaxSidecarBytes || error)
    return false;
  std::ifstream in(sidecar, std::ios::binary);
  const nlohmann::json json = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!json.is_object() || !json.contains("source") || !json["source"].is_string() ||
      json["source"].get<std::string>().rfind("generator:", 0) != 0 ||
      !json.contains("content_hash") || !json["content_hash"].is_string())
    return false;
  const std::filesystem::file_status trace = std::filesystem::symlink_status(trace_path, error);
  if (trace.type() == std::filesystem::file_type::not_found) return true;
  if (trace.type() != std::filesystem::file_type::regular ||
      std::filesystem::file_size(trace_path, error) > kMaxTraceBytes || error)
    return false;
  return json["content_hash"].get<std::string>() ==
         ContentHash().add(read_file_bytes(trace_path)).hex();
}

Trace read_trace_file(const std::string& path, TraceFileFormat format,
                      const std::optional<TraceUnits>& declared_units) {
  const std::string bytes = read_file_bytes(path);
  Trace trace;
  trace.info.content_hash = ContentHash().add(bytes).hex();
  if (format == TraceFileFormat::kTum) {
    trace.samples = parse_tum(path, bytes, trace.info.start_shift_ns);
    trace.info.source = "tum:" + path;
  } else {
    trace.samples = parse_hapticbench_csv(path, bytes, trace.info.start_shift_ns);
    trace.info.source = "csv:" + path;
  }
  trace.info.rate_hz = average_rate_hz(trace.samples);
  const std::string sidecar = sidecar_path(path);
  const bool has_sidecar =
      format == TraceFileFormat::kHapticbenchCsv && std::filesystem::exists(sidecar);
  if (has_sidecar) {
    read_sidecar(sidecar, path, trace.info);
    if (declared_units && *declared_units != trace.info.units)
      throw InputError(sidecar, "/units",
                       "the sidecar says the trace is in " + in_quotes(trace.info.units.text()) +
                           " and the scenario (/trace/units) says " +
                           in_quotes(declared_units->text()) + ": make them agree");
  } else if (declared_units) {
    trace.info.units = *declared_units;
  }
  convert_to_si(trace.samples, trace.info.units);
  return trace;
}

void write_trace_file(const std::string& path, const Trace& trace) {
  if (sidecar_path(path) == path)
    throw InputError(path, "",
                     "the trace's sidecar would have the same name (<stem>.json); name the "
                     "trace something.csv");
  const auto& samples = trace.samples;
  if (samples.size() < 2) throw std::invalid_argument("write_trace_file: fewer than 2 samples");
  std::size_t with_twist = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (samples[i].twist) ++with_twist;
    if (i > 0 && samples[i].t_ns <= samples[i - 1].t_ns)
      throw std::invalid_argument("write_trace_file: t_ns not strictly increasing");
  }
  if (with_twist != 0 && with_twist != samples.size())
    throw std::invalid_argument("write_trace_file: twists on some samples only");

  const std::string csv = format_csv(trace, with_twist != 0);
  nlohmann::ordered_json sidecar;
  sidecar["units"] = TraceUnits{}.text();  // the samples are in m and rad
  sidecar["frame"] = trace.info.frame;
  sidecar["rate_hz"] = trace.info.rate_hz;
  sidecar["source"] = trace.info.source;
  sidecar["content_hash"] = ContentHash().add(csv).hex();
  sidecar["samples"] = samples.size();
  sidecar["duration_s"] = static_cast<double>(samples.back().t_ns - samples.front().t_ns) * 1e-9;

  // Both files go through temporary files of their own (never a name of
  // the user's); a crash between the two renames leaves a sidecar whose
  // hash does not match the CSV, which read_trace_file reports: never a
  // silent mismatch.
  TemporarySibling csv_file(path);
  TemporarySibling json_file(sidecar_path(path));
  csv_file.write(csv);
  json_file.write(sidecar.dump(2) + "\n");
  csv_file.commit();
  json_file.commit();
}

}  // namespace hb
