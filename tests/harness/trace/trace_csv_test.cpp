// Trace files: bit-exact round trip, the sidecar and its hash, every kind of
// malformed row reported with file and line, and TUM import.
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <random>
#include <string>

#include "hapticbench/content_hash.h"
#include "hapticbench/input_error.h"
#include "harness/trace/trace.h"

namespace {

namespace fs = std::filesystem;

/// A fresh directory for one test case, removed afterwards.
class ScratchDirectory {
 public:
  explicit ScratchDirectory(const std::string& tag)
      : path_(fs::temp_directory_path() /
              ("hb_trace_csv_test_" + std::to_string(::getpid()) + "_" + tag)) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchDirectory() { fs::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& entry : fs::directory_iterator(path_))
      out.push_back(entry.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  }

 private:
  fs::path path_;
};

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

bool same_bits(const hb::Vec3& a, const hb::Vec3& b) {
  return same_bits(a.x(), b.x()) && same_bits(a.y(), b.y()) && same_bits(a.z(), b.z());
}

/// Awkward doubles: thirds, signed zero, extremes, subnormals, random values.
hb::Trace awkward_trace(bool with_twist) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const double specials[] = {1.0 / 3.0,
                             -0.0,
                             1e-300,
                             std::numeric_limits<double>::denorm_min(),
                             std::numeric_limits<double>::max(),
                             -std::numeric_limits<double>::min(),
                             0.1,
                             123456.789e-12};
  hb::Trace trace;
  trace.info.source = "recorded";
  trace.info.rate_hz = 250;
  for (int i = 0; i < 50; ++i) {
    hb::TraceSample sample;
    sample.t_ns = int64_t{4'000'000} * i + (i % 3);
    sample.pose.p = hb::Vec3(specials[i % 8], uniform(rng) * 1e3, uniform(rng) * 1e-7);
    sample.pose.q =
        hb::Quat(uniform(rng), uniform(rng), uniform(rng), uniform(rng) + 2.0).normalized();
    if (with_twist)
      sample.twist = hb::Twist{hb::Vec3(uniform(rng), specials[(i + 3) % 8], -uniform(rng)),
                               hb::Vec3(uniform(rng) * 1e5, uniform(rng), specials[(i + 5) % 8])};
    trace.samples.push_back(sample);
  }
  return trace;
}

/// Runs read_trace_file and returns the InputError's what(), or "" if none.
std::string read_error(const std::string& path,
                       hb::TraceFileFormat format = hb::TraceFileFormat::kHapticbenchCsv) {
  try {
    hb::read_trace_file(path, format);
  } catch (const hb::InputError& error) {
    return error.what();
  }
  return "";
}

const std::string kHeader = "t_ns,px,py,pz,qw,qx,qy,qz\n";

}  // namespace

TEST_CASE("trace CSV round trip is bit-exact, with and without twists") {
  for (const bool with_twist : {true, false}) {
    ScratchDirectory dir(with_twist ? "roundtrip_twist" : "roundtrip_pose");
    const hb::Trace written = awkward_trace(with_twist);
    const std::string path = dir.file("awkward.csv");
    hb::write_trace_file(path, written);

    // Nothing half-written remains: only the CSV and its sidecar.
    CHECK(dir.names() == std::vector<std::string>{"awkward.csv", "awkward.json"});

    const hb::Trace read = hb::read_trace_file(path, hb::TraceFileFormat::kHapticbenchCsv);
    REQUIRE(read.samples.size() == written.samples.size());
    for (std::size_t i = 0; i < read.samples.size(); ++i) {
      const auto& a = written.samples[i];
      const auto& b = read.samples[i];
      INFO("sample " << i);
      CHECK(a.t_ns == b.t_ns);
      CHECK(same_bits(a.pose.p, b.pose.p));
      CHECK(std::memcmp(a.pose.q.coeffs().data(), b.pose.q.coeffs().data(), 4 * sizeof(double)) ==
            0);
      REQUIRE(b.twist.has_value() == with_twist);
      if (with_twist) {
        CHECK(same_bits(a.twist->v, b.twist->v));
        CHECK(same_bits(a.twist->w, b.twist->w));
      }
    }
    CHECK(std::signbit(read.samples[1].pose.p.x()));  // -0.0 survives
    CHECK(read.info.source == "recorded");
    CHECK(read.info.rate_hz == 250);
    CHECK(read.info.frame == "world");
    CHECK(read.info.content_hash == hb::file_content_hash(path));
  }
}

TEST_CASE("the sidecar holds units, frame, rate, source, hash, samples and duration") {
  ScratchDirectory dir("sidecar");
  hb::Trace trace = awkward_trace(false);
  trace.info.source = "generator:test";
  const std::string path = dir.file("t.csv");
  hb::write_trace_file(path, trace);
  const nlohmann::json sidecar = nlohmann::json::parse(read_text(dir.file("t.json")));
  CHECK(sidecar.at("units") == "m, s, rad");
  CHECK(sidecar.at("frame") == "world");
  CHECK(sidecar.at("rate_hz") == 250.0);
  CHECK(sidecar.at("source") == "generator:test");
  CHECK(sidecar.at("content_hash") == hb::file_content_hash(path));
  CHECK(sidecar.at("samples") == 50);
  // Last sample at 49 * 4 ms + (49 % 3) ns.
  CHECK(sidecar.at("duration_s").get<double>() == Approx(0.196000001).epsilon(1e-15));
  // The first line is the header, full precision after it.
  CHECK(read_text(path).rfind(kHeader, 0) == 0);
}

TEST_CASE("a CSV without sidecar gets its rate from the samples") {
  ScratchDirectory dir("no_sidecar");
  const std::string path = dir.file("plain.csv");
  write_text(path, kHeader + "0,0,0,0,1,0,0,0\n2000000,0,0,0,1,0,0,0\n4000000,0,0,0,1,0,0,0\n");
  const hb::Trace trace = hb::read_trace_file(path, hb::TraceFileFormat::kHapticbenchCsv);
  REQUIRE(trace.samples.size() == 3);
  CHECK(trace.info.rate_hz == Approx(500.0));
  CHECK_FALSE(trace.samples[0].twist.has_value());
  CHECK(trace.info.content_hash == hb::file_content_hash(path));
}

TEST_CASE("Windows line endings and a trailing blank line are accepted") {
  ScratchDirectory dir("crlf");
  const std::string path = dir.file("crlf.csv");
  write_text(path, "t_ns,px,py,pz,qw,qx,qy,qz\r\n0,1,2,3,1,0,0,0\r\n1000000,4,5,6,0,1,0,0\r\n\r\n");
  const hb::Trace trace = hb::read_trace_file(path, hb::TraceFileFormat::kHapticbenchCsv);
  REQUIRE(trace.samples.size() == 2);
  CHECK(trace.samples[1].pose.p == hb::Vec3(4, 5, 6));
  CHECK(trace.samples[1].pose.q.x() == 1.0);
}

TEST_CASE("a near-unit quaternion is renormalised") {
  ScratchDirectory dir("near_unit");
  const std::string path = dir.file("near.csv");
  // |q| = 1.0005: within the 1e-3 tolerance.
  write_text(path, kHeader + "0,0,0,0,0.6003,0.8004,0,0\n1000000,0,0,0,1,0,0,0\n");
  const hb::Trace trace = hb::read_trace_file(path, hb::TraceFileFormat::kHapticbenchCsv);
  const hb::Quat& q = trace.samples[0].pose.q;
  CHECK(q.norm() == Approx(1.0).epsilon(1e-15));
  CHECK(q.w() == Approx(0.6).epsilon(1e-14));
  CHECK(q.x() == Approx(0.8).epsilon(1e-14));
}

TEST_CASE("malformed trace CSV files name the file and the line") {
  ScratchDirectory dir("bad");
  struct BadInput {
    const char* name;
    std::string text;
    std::string location;  // "line N"
    std::string says;      // part of the message
  };
  const std::vector<BadInput> cases = {
      {"bad_header", "t,px,py,pz,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n", "line 1",
       "expected the header \"t_ns,px,py,pz,qw,qx,qy,qz\""},
      {"half_velocity_header", "t_ns,px,py,pz,qw,qx,qy,qz,vx,vy,vz\n0,0,0,0,1,0,0,0,0,0,0\n",
       "line 1", "found \"t_ns,px,py,pz,qw,qx,qy,qz,vx,vy,vz\""},
      {"empty", "", "line 1", "found an empty file"},
      {"nan", kHeader + "0,0,0,0,1,0,0,0\n1000000,0,nan,0,1,0,0,0\n", "line 3",
       "expected a finite number in column py, found \"nan\""},
      {"inf", kHeader + "0,0,0,0,1,0,0,0\n1000000,0,0,inf,1,0,0,0\n", "line 3",
       "expected a finite number in column pz"},
      {"unparsable", kHeader + "0,0,0,0,1,0,0,0\n1000000,0,0,0.0.1,1,0,0,0\n", "line 3",
       "expected a number in column pz, found \"0.0.1\""},
      {"fractional_time", kHeader + "0,0,0,0,1,0,0,0\n1.5,0,0,0,1,0,0,0\n", "line 3",
       "expected a whole number of nanoseconds in column t_ns"},
      {"non_unit_quaternion", kHeader + "0,0,0,0,1.01,0,0,0\n1000000,0,0,0,1,0,0,0\n", "line 2",
       "expected a unit quaternion qw,qx,qy,qz"},
      {"non_monotonic", kHeader + "0,0,0,0,1,0,0,0\n1000,0,0,0,1,0,0,0\n1000,0,0,0,1,0,0,0\n",
       "line 4", "expected t_ns to increase strictly from row to row, found 1000 after 1000"},
      {"decreasing", kHeader + "5,0,0,0,1,0,0,0\n3,0,0,0,1,0,0,0\n", "line 3", "found 3 after 5"},
      {"short_row", kHeader + "0,0,0,0,1,0,0,0\n1000,0,0,0,1,0,0\n", "line 3",
       "expected 8 comma-separated values"},
      {"long_row", kHeader + "0,0,0,0,1,0,0,0,9\n1000,0,0,0,1,0,0,0\n", "line 2", "found 9"},
      {"one_row", kHeader + "0,0,0,0,1,0,0,0\n", "line 3", "expected at least 2 samples, found 1"},
      // Samples 1 ns apart made a one-tick run without a word.
      {"nanosecond_steps", kHeader + "0,0,0,0,1,0,0,0\n1,0,0,0,1,0,0,0\n2,0,0,0,1,0,0,0\n",
       "line 5", "span 2 ns, less than one 1 kHz tick"},
  };
  for (const BadInput& bad : cases) {
    INFO(bad.name);
    const std::string path = dir.file(std::string(bad.name) + ".csv");
    write_text(path, bad.text);
    const std::string message = read_error(path);
    CHECK(message.find(path + ": " + bad.location + ": ") == 0);
    CHECK(message.find(bad.says) != std::string::npos);
    INFO(message);
  }
}

TEST_CASE("a stale sidecar is an error naming the sidecar and /content_hash") {
  ScratchDirectory dir("stale");
  const std::string path = dir.file("trace.csv");
  hb::write_trace_file(path, awkward_trace(true));
  std::string bytes = read_text(path);
  // Change one sample's time so the CSV is still valid but different.
  const std::size_t second_row = bytes.find('\n', bytes.find('\n') + 1) + 1;
  REQUIRE(bytes.substr(second_row, 7) == "4000001");
  bytes.replace(second_row, 7, "4000002");
  write_text(path, bytes);
  try {
    hb::read_trace_file(path, hb::TraceFileFormat::kHapticbenchCsv);
    FAIL("expected an InputError");
  } catch (const hb::InputError& error) {
    CHECK(error.source() == dir.file("trace.json"));
    CHECK(error.location() == "/content_hash");
    CHECK(std::string(error.what()).find("stale") != std::string::npos);
    CHECK(std::string(error.what()).find(hb::file_content_hash(path)) != std::string::npos);
  }
}

TEST_CASE("a sidecar field of the wrong type names its JSON path") {
  ScratchDirectory dir("sidecar_type");
  const std::string path = dir.file("trace.csv");
  hb::write_trace_file(path, awkward_trace(false));
  nlohmann::json sidecar = nlohmann::json::parse(read_text(dir.file("trace.json")));
  sidecar["rate_hz"] = "fast";
  write_text(dir.file("trace.json"), sidecar.dump());
  try {
    hb::read_trace_file(path, hb::TraceFileFormat::kHapticbenchCsv);
    FAIL("expected an InputError");
  } catch (const hb::InputError& error) {
    CHECK(error.source() == dir.file("trace.json"));
    CHECK(error.location() == "/rate_hz");
  }
}

TEST_CASE("a missing file is an InputError naming it") {
  const std::string message = read_error("/nonexistent/dir/trace.csv");
  CHECK(message.find("/nonexistent/dir/trace.csv") == 0);
}

TEST_CASE("TUM import: seconds to ns exactly, qw last, comments and blank lines skipped") {
  ScratchDirectory dir("tum");
  const std::string path = dir.file("tum.txt");
  write_text(path,
             "# ground truth trajectory\n"
             "# timestamp tx ty tz qx qy qz qw\n"
             "1305031102.175304 1.0 2.0 3.0 0 0 0 1\n"
             "\n"
             "1305031102.211214 1.5 2.0 3.0 0 0 0.38268343236508978 0.92387953251128674\n"
             "  1305031102.243211\t1.5 2.5 -3.0 0.5 0.5 0.5 0.5\n");
  const hb::Trace trace = hb::read_trace_file(path, hb::TraceFileFormat::kTum);
  REQUIRE(trace.samples.size() == 3);
  // Differences of the decimal stamps, exact to the nanosecond (double
  // arithmetic on 1.3e9 s stamps would be off by up to ~240 ns).
  CHECK(trace.samples[0].t_ns == 0);
  CHECK(trace.samples[1].t_ns == 35'910'000);
  CHECK(trace.samples[2].t_ns == 67'907'000);
  CHECK(trace.samples[1].pose.p == hb::Vec3(1.5, 2.0, 3.0));
  // 45 degrees about z: qw is the last TUM column.
  CHECK(trace.samples[1].pose.q.w() == Approx(std::cos(std::numbers::pi / 8)).epsilon(1e-15));
  CHECK(trace.samples[1].pose.q.z() == Approx(std::sin(std::numbers::pi / 8)).epsilon(1e-15));
  CHECK(trace.samples[2].pose.q.x() == 0.5);
  CHECK(trace.samples[2].pose.p.z() == -3.0);
  CHECK_FALSE(trace.samples[0].twist.has_value());
  CHECK(trace.info.source == "tum:" + path);
  CHECK(trace.info.rate_hz == Approx(2.0 / 0.067907).epsilon(1e-12));
}

TEST_CASE("malformed TUM files name the file and the line") {
  ScratchDirectory dir("tum_bad");
  struct BadInput {
    const char* name;
    std::string text;
    std::string location;
    std::string says;
  };
  const std::vector<BadInput> cases = {
      {"seven_values", "# c\n0.0 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 1\n", "line 3",
       "expected 8 whitespace-separated values"},
      {"nan", "0.0 0 0 0 0 0 0 1\n0.1 0 nan 0 0 0 0 1\n", "line 2",
       "expected a finite number in column ty"},
      {"not_unit", "0.0 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 0 2\n", "line 2", "unit quaternion"},
      {"backwards", "0.2 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 0 1\n", "line 2", "increase strictly"},
      {"one_sample", "# only one\n0.0 0 0 0 0 0 0 1\n", "line 3", "at least 2 samples"},
  };
  for (const BadInput& bad : cases) {
    INFO(bad.name);
    const std::string path = dir.file(std::string(bad.name) + ".txt");
    write_text(path, bad.text);
    const std::string message = read_error(path, hb::TraceFileFormat::kTum);
    INFO(message);
    CHECK(message.find(path + ": " + bad.location + ": ") == 0);
    CHECK(message.find(bad.says) != std::string::npos);
  }
}

TEST_CASE("the example traces in traces/ load, with sidecars that match") {
  const std::string dir = std::string(HAPTICBENCH_SOURCE_DIR) + "/traces/";
  const hb::Trace press =
      hb::read_trace_file(dir + "press_sphere.csv", hb::TraceFileFormat::kHapticbenchCsv);
  CHECK(press.info.source == "generator:press");
  CHECK(press.samples.size() == 2001);
  const hb::Trace human =
      hb::read_trace_file(dir + "human_like.csv", hb::TraceFileFormat::kHapticbenchCsv);
  CHECK(human.info.source == "generator:human_like");
  REQUIRE(human.samples.size() == 1001);
  // The TUM example is human_like.csv every 10 ms, printed to 9 decimals.
  const hb::Trace tum = hb::read_trace_file(dir + "example_tum.txt", hb::TraceFileFormat::kTum);
  REQUIRE(tum.samples.size() == 101);
  for (std::size_t i = 0; i < tum.samples.size(); ++i) {
    const hb::TraceSample& original = human.samples[10 * i];
    CHECK(tum.samples[i].t_ns == original.t_ns);
    CHECK((tum.samples[i].pose.p - original.pose.p).norm() < 1e-9);
    CHECK((tum.samples[i].pose.q.coeffs() - original.pose.q.coeffs()).norm() < 2e-9);
  }
}

TEST_CASE("CSV times start at 0: an epoch or negative start is shifted and the shift stated") {
  ScratchDirectory dir("shift");
  for (const int64_t start : {int64_t{1'700'000'000'123'456'789}, int64_t{-5'000'000}}) {
    INFO(start);
    const std::string path = dir.file("shifted.csv");
    write_text(path, kHeader + std::to_string(start) + ",0,0,0,1,0,0,0\n" +
                         std::to_string(start + 2'000'000) + ",0.001,0,0,1,0,0,0\n");
    const hb::Trace trace = hb::read_trace_file(path, hb::TraceFileFormat::kHapticbenchCsv);
    REQUIRE(trace.samples.size() == 2);
    CHECK(trace.samples[0].t_ns == 0);
    CHECK(trace.samples[1].t_ns == 2'000'000);
    CHECK(trace.info.start_shift_ns == start);
    const std::string note = hb::trace_reading_note(trace.info);
    CHECK(note.find("times shifted by") != std::string::npos);
    CHECK(note.find(start > 0 ? "-1700000000.12346 s" : "0.005 s") != std::string::npos);
  }
}

namespace {

/// A 1 kHz press written in `scale` units of a metre (1000: mm), with
/// velocities, the sidecar saying `units` (none when empty).
std::string write_press(const ScratchDirectory& dir, double scale, const std::string& units) {
  const std::string path = dir.file("press.csv");
  std::string text = "t_ns,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n";
  for (int i = 0; i <= 200; ++i) {
    const double z = (0.03 - 0.01 * i / 200.0) * scale;  // 3 cm down to 2 cm in 0.2 s
    text += std::to_string(i * 1'000'000) + "," + std::to_string(0.01 * scale) + "," +
            std::to_string(0.12 * scale) + "," + std::to_string(z) + ",1,0,0,0,0,0," +
            std::to_string(-0.05 * scale) + ",0,0,0.5\n";
  }
  write_text(path, text);
  fs::remove(dir.file("press.json"));
  if (!units.empty())
    write_text(
        dir.file("press.json"),
        nlohmann::json{{"units", units}, {"content_hash", hb::file_content_hash(path)}}.dump());
  return path;
}

std::string read_units_error(const std::string& path, const std::optional<hb::TraceUnits>& units) {
  try {
    hb::read_trace_file(path, hb::TraceFileFormat::kHapticbenchCsv, units);
  } catch (const hb::InputError& error) {
    return error.what();
  }
  return "";
}

}  // namespace

TEST_CASE("units: the sidecar's or the scenario's mm, cm and deg are converted to m and rad") {
  ScratchDirectory dir("units");
  const auto csv = hb::TraceFileFormat::kHapticbenchCsv;
  const hb::Trace metres = hb::read_trace_file(write_press(dir, 1, ""), csv);
  CHECK(metres.info.units.is_si());
  CHECK(hb::trace_plausibility_warnings(metres).empty());
  CHECK(metres.samples[200].pose.p.z() == Approx(0.02));

  struct Case {
    double scale;
    std::string sidecar;                  // the sidecar's units ("" none)
    std::optional<std::string> scenario;  // the scenario's /trace/units
    double angle_scale;                   // the velocities' wz per rad/s
  };
  for (const Case& c : std::vector<Case>{{1000, "mm, s, rad", std::nullopt, 1},
                                         {100, "", "cm", 1},
                                         {1000, "mm, s, rad", "mm, s, rad", 1},
                                         {1000, "", "mm, s, deg", 180 / std::numbers::pi}}) {
    INFO(c.sidecar << " / " << c.scenario.value_or("-"));
    const std::string path = write_press(dir, c.scale, c.sidecar);
    std::optional<hb::TraceUnits> declared;
    if (c.scenario) declared = hb::parse_trace_units(*c.scenario);
    const hb::Trace trace = hb::read_trace_file(path, csv, declared);
    for (int i : {0, 100, 200}) {
      CHECK(trace.samples[i].pose.p.isApprox(metres.samples[i].pose.p, 1e-12));
      CHECK(trace.samples[i].twist->v.isApprox(metres.samples[i].twist->v, 1e-12));
    }
    CHECK(trace.samples[0].twist->w.z() == Approx(0.5 / c.angle_scale));
    CHECK(hb::trace_plausibility_warnings(trace).empty());
    CHECK(hb::trace_reading_note(trace.info).find("converted to m, s, rad") != std::string::npos);
  }
}

TEST_CASE("units: an unknown value or a scenario that contradicts the sidecar is refused") {
  ScratchDirectory dir("units_bad");
  const std::string bad = read_units_error(write_press(dir, 1000, "millimetres"), std::nullopt);
  CHECK(bad.find(dir.file("press.json") + ": /units: expected units") == 0);
  CHECK(bad.find("found \"millimetres\"") != std::string::npos);

  const std::string conflict =
      read_units_error(write_press(dir, 1000, "mm, s, rad"), hb::parse_trace_units("m"));
  CHECK(conflict.find(dir.file("press.json") + ": /units: ") == 0);
  CHECK(conflict.find("\"mm, s, rad\" and the scenario (/trace/units) says \"m, s, rad\"") !=
        std::string::npos);

  for (const char* text : {"", "inch", "mm, s", "mm, ms, rad", "m, s, grad", "MM"})
    CHECK_FALSE(hb::parse_trace_units(text).has_value());
  CHECK(hb::parse_trace_units(" mm , s , deg ")->text() == "mm, s, deg");
}

TEST_CASE("units: a trace in mm or deg/s read as metres and radians is a warning naming the unit") {
  ScratchDirectory dir("units_warn");
  const auto csv = hb::TraceFileFormat::kHapticbenchCsv;
  const hb::Trace millimetres = hb::read_trace_file(write_press(dir, 1000, ""), csv);
  const auto warnings = hb::trace_plausibility_warnings(millimetres);
  REQUIRE(warnings.size() == 1);
  INFO(warnings[0]);
  CHECK(warnings[0].find("when read as m, s, rad") != std::string::npos);
  CHECK(warnings[0].find("distance from the world's origin 124.097 m") != std::string::npos);
  CHECK(warnings[0].find("speed between consecutive samples 50 m/s") != std::string::npos);
  // 12.4 cm from the origin: in cm it would be 1.24 m away, which is plausible
  // too; in mm only the speed (50 mm/s) and the span fit either way.
  CHECK(warnings[0].find("the trace may be in mm or cm") != std::string::npos);
  CHECK(warnings[0].find("/trace/units") != std::string::npos);

  // Velocities in deg/s: 0.5 rad/s logged as 28.6 deg/s is still plausible,
  // so a fast one: 60 deg/s read as rad/s.
  std::string text = "t_ns,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n";
  for (int i = 0; i < 3; ++i)
    text += std::to_string(i * 1'000'000) + ",0,0,0.03,1,0,0,0,0,0,0,0,0,60\n";
  write_text(dir.file("spin.csv"), text);
  const auto spin = hb::trace_plausibility_warnings(hb::read_trace_file(dir.file("spin.csv"), csv));
  REQUIRE(spin.size() == 1);
  CHECK(spin[0].find("angular velocity wx,wy,wz 60 rad/s") != std::string::npos);
  CHECK(spin[0].find("may be in deg") != std::string::npos);
}
