// Synthetic generators: determinism, valid samples, twists that agree with
// the poses, each motion's defining geometry, band limit, and parameter errors.
#include "harness/trace/generators.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <cstring>
#include <numbers>
#include <string>

#include "hapticbench/input_error.h"

namespace {

constexpr double kDt = 1e-3;

hb::Trace generate(const std::string& name, double duration_s, uint64_t seed = 1,
                   const hb::ParamSet& params = hb::ParamSet("/trace/params")) {
  return hb::generate_trace(name, hb::GeneratorRequest{duration_s, seed, params},
                            "/trace/generator");
}

/// Rotation vector (rad) of a unit quaternion, via Eigen's angle-axis.
hb::Vec3 rotation_of(const hb::Quat& q) {
  const Eigen::AngleAxisd aa(q);
  double angle = aa.angle();
  hb::Vec3 axis = aa.axis();
  if (angle > std::numbers::pi) {
    angle = 2 * std::numbers::pi - angle;
    axis = -axis;
  }
  return angle * axis;
}

double seconds(const hb::TraceSample& sample) { return static_cast<double>(sample.t_ns) * 1e-9; }

/// Samples k whose neighbours k-1, k+1 straddle `skip_ns` are not checked.
void check_twists_match_poses(const hb::Trace& trace, int64_t skip_ns = -1) {
  const auto& s = trace.samples;
  double error_squared = 0, speed_squared = 0;
  for (std::size_t k = 1; k + 1 < s.size(); ++k) {
    if (skip_ns >= 0 && s[k - 1].t_ns < skip_ns && s[k + 1].t_ns >= skip_ns) continue;
    const hb::Vec3 fd_v = (s[k + 1].pose.p - s[k - 1].pose.p) / (2 * kDt);
    const hb::Vec3 fd_w = rotation_of(s[k + 1].pose.q * s[k - 1].pose.q.conjugate()) / (2 * kDt);
    const hb::Twist& a = *s[k - 1].twist;
    const hb::Twist& b = *s[k].twist;
    const hb::Twist& c = *s[k + 1].twist;
    // A central difference is the mean velocity over [t-1, t+1]; for a
    // smooth motion it differs from v(t) by no more than v changes there.
    const double bound_v =
        std::max((c.v - b.v).norm(), (b.v - a.v).norm()) + 1e-9 + 1e-6 * b.v.norm();
    const double bound_w =
        std::max((c.w - b.w).norm(), (b.w - a.w).norm()) + 1e-9 + 1e-6 * b.w.norm();
    INFO("t_ns " << s[k].t_ns << " v " << b.v.transpose() << " fd " << fd_v.transpose() << " w "
                 << b.w.transpose() << " fd " << fd_w.transpose());
    REQUIRE((fd_v - b.v).norm() <= bound_v);
    REQUIRE((fd_w - b.w).norm() <= bound_w);
    error_squared += (fd_v - b.v).squaredNorm() + 1e-4 * (fd_w - b.w).squaredNorm();
    speed_squared += b.v.squaredNorm() + 1e-4 * b.w.squaredNorm();
  }
  CHECK(error_squared <= 1e-4 * speed_squared + 1e-24);
}

void check_valid_samples(const hb::Trace& trace, double duration_s) {
  const auto n = static_cast<std::size_t>(std::llround(duration_s * 1000)) + 1;
  REQUIRE(trace.samples.size() == n);
  for (std::size_t k = 0; k < n; ++k) {
    const hb::TraceSample& sample = trace.samples[k];
    REQUIRE(sample.t_ns == static_cast<int64_t>(k) * 1'000'000);
    REQUIRE(hb::is_finite(sample.pose));
    REQUIRE(std::abs(sample.pose.q.norm() - 1.0) < 1e-12);
    REQUIRE(sample.twist.has_value());
    REQUIRE(sample.twist->v.allFinite());
    REQUIRE(sample.twist->w.allFinite());
  }
}

bool identical(const hb::Trace& a, const hb::Trace& b) {
  if (a.samples.size() != b.samples.size()) return false;
  for (std::size_t k = 0; k < a.samples.size(); ++k) {
    const auto& x = a.samples[k];
    const auto& y = b.samples[k];
    if (x.t_ns != y.t_ns) return false;
    if (std::memcmp(x.pose.p.data(), y.pose.p.data(), 3 * sizeof(double)) != 0) return false;
    if (std::memcmp(x.pose.q.coeffs().data(), y.pose.q.coeffs().data(), 4 * sizeof(double)) != 0)
      return false;
    if (std::memcmp(x.twist->v.data(), y.twist->v.data(), 3 * sizeof(double)) != 0) return false;
    if (std::memcmp(x.twist->w.data(), y.twist->w.data(), 3 * sizeof(double)) != 0) return false;
  }
  return true;
}

/// Location of the InputError thrown by f, or "<none>".
template <typename F>
std::string error_location(F f) {
  try {
    f();
  } catch (const hb::InputError& error) {
    return error.location();
  }
  return "<none>";
}

/// Fraction of a signal's DFT energy (mean removed) at bins >= first_bin.
/// x holds exactly one period of N samples.
double energy_fraction_from(const std::vector<double>& x, std::size_t first_bin,
                            int* bins_with_energy) {
  const std::size_t n = x.size();
  double mean = 0;
  for (double v : x) mean += v;
  mean /= static_cast<double>(n);
  std::vector<std::complex<double>> twiddle(n);
  for (std::size_t j = 0; j < n; ++j)
    twiddle[j] =
        std::polar(1.0, -2.0 * std::numbers::pi * static_cast<double>(j) / static_cast<double>(n));
  double total = 0, above = 0, largest = 0;
  std::vector<double> energy(n / 2 + 1);
  for (std::size_t m = 1; m <= n / 2; ++m) {
    std::complex<double> sum = 0;
    for (std::size_t k = 0; k < n; ++k) sum += (x[k] - mean) * twiddle[(m * k) % n];
    energy[m] = std::norm(sum);
    total += energy[m];
    if (m >= first_bin) above += energy[m];
    largest = std::max(largest, energy[m]);
  }
  *bins_with_energy = 0;
  for (std::size_t m = 1; m < first_bin; ++m)
    if (energy[m] > 1e-6 * largest) ++*bins_with_energy;
  return above / total;
}

const std::vector<std::string> kAllGenerators = {"press",  "slide",       "rub",  "twist",
                                                 "turn",   "peg_in_hole", "path", "human_like",
                                                 "impact", "jump",        "rest"};

}  // namespace

TEST_CASE("the generator table lists every generator with a one-line summary") {
  std::vector<std::string> names;
  for (const hb::GeneratorEntry& entry : hb::generator_table()) {
    names.emplace_back(entry.name);
    CHECK_FALSE(entry.summary.empty());
    CHECK(entry.summary.find('\n') == std::string_view::npos);
    CHECK(entry.generate != nullptr);
  }
  CHECK(names == kAllGenerators);
}

TEST_CASE("every generator is deterministic, valid, and its twists match its poses") {
  for (const std::string& name : kAllGenerators) {
    for (const double duration : {2.0, 0.75}) {
      INFO(name << " over " << duration << " s");
      const hb::Trace first = generate(name, duration, 7);
      const hb::Trace second = generate(name, duration, 7);
      check_valid_samples(first, duration);
      CHECK(identical(first, second));
      CHECK(first.info.source == "generator:" + name);
      CHECK(first.info.rate_hz == 1000);
      // jump is discontinuous at at_s (default: half the duration).
      check_twists_match_poses(first, name == "jump" ? std::llround(duration * 0.5e9) : -1);
    }
  }
}

TEST_CASE("human_like depends on the seed, the scripted motions do not") {
  CHECK_FALSE(identical(generate("human_like", 2, 1), generate("human_like", 2, 2)));
  CHECK(identical(generate("press", 2, 1), generate("press", 2, 2)));
}

TEST_CASE("press: approach, press depth past the surface, hold >= 40%, release") {
  const hb::Trace trace = generate("press", 2.0);
  const auto& s = trace.samples;
  // Defaults: start z = 0.03, axis -z, surface 0.01 away, depth 0.005.
  CHECK(s.front().pose.p == hb::Vec3(0, 0, 0.03));
  CHECK(s.back().pose.p == hb::Vec3(0, 0, 0.03));
  double lowest = 1;
  int at_deepest = 0;
  for (const auto& sample : s) {
    lowest = std::min(lowest, sample.pose.p.z());
    if (std::abs(sample.pose.p.z() - 0.015) < 1e-12) ++at_deepest;
    CHECK(sample.pose.p.x() == 0);
    CHECK(sample.pose.q.isApprox(hb::Quat::Identity(), 0));
  }
  CHECK(lowest == Approx(0.015).epsilon(1e-14));
  CHECK((at_deepest - 1) * kDt >= 0.4 * 2.0);
  // Touches the surface (z = 0.02) at the end of the approach, 30% in.
  CHECK(s[600].pose.p.z() == Approx(0.02).epsilon(1e-14));
  CHECK(s[600].twist->v.norm() == 0);
}

TEST_CASE("press: cycles presses in a row, each the same press over duration / cycles") {
  hb::ParamSet params("/trace/params");
  params.set("cycles", 4.0);
  const hb::Trace trace = generate("press", 8.0, 1, params);
  const hb::Trace one = generate("press", 2.0);
  const auto& s = trace.samples;
  for (std::size_t k = 0; k < s.size(); ++k) {
    INFO("k " << k);
    const auto& match = one.samples[k == s.size() - 1 ? 2000 : k % 2000];
    CHECK(s[k].pose.p.isApprox(match.pose.p, 1e-13));
    CHECK((s[k].twist->v - match.twist->v).norm() < 1e-12);
  }
  // At rest at the start pose between presses.
  CHECK(s[4000].pose.p == hb::Vec3(0, 0, 0.03));
  CHECK(s[4000].twist->v.norm() == 0);
  check_twists_match_poses(trace);
  CHECK(identical(one, [] {
    hb::ParamSet single("/trace/params");
    single.set("cycles", 1.0);
    return generate("press", 2.0, 1, single);
  }()));
}

TEST_CASE("press follows its axis, distances and orientation parameters") {
  hb::ParamSet params("/trace/params");
  params.set("start", std::vector<double>{0.1, 0, 0});
  params.set("axis", std::vector<double>{2, 0, 0});  // normalised to +x
  params.set("surface_distance", 0.02);
  params.set("depth", 0.01);
  params.set("q", std::vector<double>{std::sqrt(0.5), std::sqrt(0.5), 0, 0});
  const hb::Trace trace = generate("press", 1.0, 1, params);
  double furthest = 0;
  for (const auto& sample : trace.samples) {
    furthest = std::max(furthest, sample.pose.p.x());
    CHECK(sample.pose.p.y() == 0);
    CHECK(sample.pose.p.z() == 0);
    CHECK(std::abs(sample.pose.q.x() - std::sqrt(0.5)) < 1e-15);
  }
  CHECK(furthest == Approx(0.13).epsilon(1e-14));
}

TEST_CASE("slide: press to depth, slide distance along direction, lift") {
  const hb::Trace trace = generate("slide", 2.0);
  const auto& s = trace.samples;
  // Defaults: surface at z = 0.02, depth 0.002, 0.05 m along +x.
  CHECK(s.back().pose.p.isApprox(hb::Vec3(0.05, 0, 0.03), 1e-15));
  for (const auto& sample : s) {
    const double t = seconds(sample);
    if (t >= 0.4 && t <= 1.6) CHECK(sample.pose.p.z() == Approx(0.018).epsilon(1e-14));
    CHECK(sample.pose.p.y() == 0);
  }
  CHECK(s[1600].pose.p.x() == Approx(0.05).epsilon(1e-14));
}

TEST_CASE("rub: circles of the given radius at depth, for the given turns") {
  hb::ParamSet params("/trace/params");
  params.set("turns", 1.5);
  params.set("radius", 0.02);
  const hb::Trace trace = generate("rub", 2.0, 1, params);
  const auto& s = trace.samples;
  CHECK(s.front().pose.p.isApprox(hb::Vec3(0.02, 0, 0.03), 1e-15));
  double swept = 0;
  double previous = 0;
  for (const auto& sample : s) {
    const double t = seconds(sample);
    if (t < 0.4 || t > 1.6) continue;
    const hb::Vec3& p = sample.pose.p;
    CHECK(p.z() == Approx(0.018).epsilon(1e-14));
    CHECK(std::hypot(p.x(), p.y()) == Approx(0.02).epsilon(1e-13));
    const double angle = std::atan2(p.y(), p.x());
    if (t > 0.4) swept += std::remainder(angle - previous, 2 * std::numbers::pi);
    previous = angle;
  }
  CHECK(swept == Approx(1.5 * 2 * std::numbers::pi).epsilon(1e-12));
  // Half a turn extra: the tool lifts on the far side of the circle.
  CHECK(s.back().pose.p.isApprox(hb::Vec3(-0.02, 0, 0.03), 1e-14));
  check_twists_match_poses(trace);
}

TEST_CASE("twist: oscillates by the amplitude about the press axis at depth") {
  const hb::Trace trace = generate("twist", 2.0);
  double largest = 0;
  for (const auto& sample : trace.samples) {
    const double t = seconds(sample);
    const hb::Quat& q = sample.pose.q;
    CHECK(std::abs(q.x()) < 1e-15);
    CHECK(std::abs(q.y()) < 1e-15);
    // About -z (the press axis): angle = -2 atan2(qz, qw).
    largest = std::max(largest, std::abs(2 * std::atan2(q.z(), q.w())));
    if (t >= 0.5 && t <= 1.5) CHECK(sample.pose.p.z() == Approx(0.015).epsilon(1e-14));
  }
  CHECK(largest <= 0.5 + 1e-12);
  CHECK(largest >= 0.5 - 1e-4);
  CHECK(trace.samples.back().pose.q.isApprox(hb::Quat::Identity(), 1e-15));

  // A fractional number of turns ends off zero and turns back while lifting.
  hb::ParamSet params("/trace/params");
  params.set("turns", 1.25);
  const hb::Trace quarter = generate("twist", 2.0, 1, params);
  const hb::Quat& q_end = quarter.samples[1500].pose.q;  // end of the oscillation
  CHECK(std::abs(2 * std::atan2(q_end.z(), q_end.w())) == Approx(0.5).epsilon(1e-12));
  CHECK(quarter.samples.back().pose.q.isApprox(hb::Quat::Identity(), 1e-15));
  check_twists_match_poses(quarter);
}

TEST_CASE("turn: pressed, then a constant turn about the axis through the tool frame's origin") {
  hb::ParamSet params("/trace/params");
  params.set("rate_rad_s", 3.0);
  const hb::Trace trace = generate("turn", 2.0, 1, params);
  // Defaults: start [0, 0, 0.03], 0.01 + 0.002 down -z, turn about +y from
  // 0.5 s, reaching the rate in 0.05 s (half that time's worth of angle).
  for (const auto& sample : trace.samples) {
    const double t = seconds(sample);
    if (t < 0.55) continue;
    CHECK(sample.pose.p.z() == Approx(0.018).epsilon(1e-14));
    const hb::Vec3 turned = hb::rotation_vector(sample.pose.q);
    CHECK(turned.y() == Approx(std::remainder(3.0 * (t - 0.525), 2 * M_PI)).margin(1e-9));
    CHECK(std::abs(turned.x()) + std::abs(turned.z()) < 1e-12);
    REQUIRE(sample.twist);
    CHECK(sample.twist->w.isApprox(hb::Vec3(0, 3.0, 0), 1e-15));
  }
  check_twists_match_poses(trace);
}

TEST_CASE("peg_in_hole: misalignment and tilt decay linearly with insertion depth") {
  const hb::Trace trace = generate("peg_in_hole", 2.0);
  const auto& s = trace.samples;
  // Defaults: hole at the origin, start 0.03 above, offset [0.001, 0],
  // tilt 0.05 rad about x, insert 0.02.
  CHECK(s.front().pose.p.isApprox(hb::Vec3(0.001, 0, 0.03), 1e-15));
  CHECK(rotation_of(s.front().pose.q).isApprox(hb::Vec3(0.05, 0, 0), 1e-12));
  CHECK(s[600].pose.p.isApprox(hb::Vec3(0.001, 0, 0), 1e-14));
  CHECK(s.back().pose.p.isApprox(hb::Vec3(0, 0, -0.02), 1e-15));
  CHECK(s.back().pose.q.isApprox(hb::Quat::Identity(), 1e-15));
  for (std::size_t k = 600; k <= 1600; ++k) {
    const double inserted = -s[k].pose.p.z() / 0.02;  // 0 at the entry, 1 fully in
    CHECK(s[k].pose.p.x() == Approx(0.001 * (1 - inserted)).margin(1e-15));
    CHECK(rotation_of(s[k].pose.q).x() == Approx(0.05 * (1 - inserted)).margin(1e-13));
  }

  // With the peg turned about z, the tilt axis (world x) is not a body axis:
  // the angular velocity must still be the world-frame one.
  hb::ParamSet params("/trace/params");
  params.set("q", std::vector<double>{std::sqrt(0.5), 0, 0, std::sqrt(0.5)});
  params.set("tilt_rad", 0.3);
  const hb::Trace turned = generate("peg_in_hole", 2.0, 1, params);
  check_twists_match_poses(turned);
  CHECK(turned.samples[1000].twist->w.y() == Approx(0).margin(1e-15));
  CHECK(turned.samples[1000].twist->w.x() < -0.1);
}

TEST_CASE("peg_in_hole: twist_rad turns the inserted peg once about the insertion axis") {
  hb::ParamSet params("/trace/params");
  params.set("twist_rad", 0.1);
  const hb::Trace trace = generate("peg_in_hole", 2.0, 1, params);
  const hb::Trace plain = generate("peg_in_hole", 2.0);
  const auto& s = trace.samples;
  double largest = 0, smallest = 0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (k <= 1600) {
      // Unchanged until the peg is in.
      CHECK(s[k].pose.p == plain.samples[k].pose.p);
      CHECK(s[k].pose.q.coeffs() == plain.samples[k].pose.q.coeffs());
      continue;
    }
    CHECK(s[k].pose.p.isApprox(hb::Vec3(0, 0, -0.02), 1e-15));
    const hb::Vec3 turned = rotation_of(s[k].pose.q);
    CHECK(std::hypot(turned.x(), turned.y()) < 1e-15);
    largest = std::max(largest, turned.z());
    smallest = std::min(smallest, turned.z());
    CHECK(s[k].twist->v.norm() == 0);
    CHECK(std::hypot(s[k].twist->w.x(), s[k].twist->w.y()) == 0);
  }
  CHECK(largest == Approx(0.1).epsilon(1e-3));
  CHECK(smallest == Approx(-0.1).epsilon(1e-3));
  CHECK(s.back().pose.q.isApprox(hb::Quat::Identity(), 1e-15));
  check_twists_match_poses(trace);
}

TEST_CASE("path: through the waypoints at speed_mps, at rest at each, then held") {
  hb::ParamSet params("/trace/params");
  // 0.02 m along x, a repeated point (no time), 0.01 m down z, 0.03 m back along x.
  params.set("points", std::vector<double>{0, 0, 0.03, 0.02, 0, 0.03, 0.02, 0, 0.03, 0.02, 0, 0.02,
                                           -0.01, 0, 0.02});
  params.set("speed_mps", 0.05);
  params.set("q", std::vector<double>{0, 1, 0, 0});
  const hb::Trace trace = generate("path", 2.0, 1, params);
  const auto& s = trace.samples;
  // Waypoints at 0, 0.4, 0.6 and 1.2 s, at rest.
  CHECK(s[0].pose.p == hb::Vec3(0, 0, 0.03));
  CHECK(s[400].pose.p.isApprox(hb::Vec3(0.02, 0, 0.03), 1e-15));
  CHECK(s[600].pose.p.isApprox(hb::Vec3(0.02, 0, 0.02), 1e-15));
  for (std::size_t k : {0, 400, 600}) CHECK(s[k].twist->v.norm() < 1e-15);
  for (std::size_t k = 1200; k < s.size(); ++k) {
    CHECK(s[k].pose.p.isApprox(hb::Vec3(-0.01, 0, 0.02), 1e-15));
    CHECK(s[k].twist->v.norm() == 0);
  }
  // On the segment lines in between; mean speed speed_mps on each.
  for (std::size_t k = 0; k <= 400; ++k) CHECK(s[k].pose.p.z() == 0.03);
  for (std::size_t k = 400; k <= 600; ++k) CHECK(s[k].pose.p.x() == Approx(0.02).epsilon(1e-15));
  double fastest = 0;
  for (const auto& sample : s) {
    fastest = std::max(fastest, sample.twist->v.norm());
    CHECK(sample.pose.q.x() == 1.0);
    CHECK(sample.twist->w.norm() == 0);
  }
  CHECK(fastest == Approx(1.875 * 0.05).epsilon(1e-6));  // minimum-jerk peak
  check_twists_match_poses(trace);

  SECTION("errors name the field") {
    hb::ParamSet bad("/trace/params");
    bad.set("points", std::vector<double>{0, 0, 0, 1, 1});
    CHECK(error_location([&] { generate("path", 2.0, 1, bad); }) == "/trace/params/points");
    hb::ParamSet one_point("/trace/params");
    one_point.set("points", std::vector<double>{0, 0, 0});
    CHECK(error_location([&] { generate("path", 2.0, 1, one_point); }) == "/trace/params/points");
    hb::ParamSet slow("/trace/params");
    slow.set("speed_mps", 0.01);  // the default 0.05 m path takes 5 s
    CHECK(error_location([&] { generate("path", 2.0, 1, slow); }) == "/trace/params/speed_mps");
  }
}

TEST_CASE("repeat_sample_at_s: one sample repeats the previous one, for every generator") {
  for (const std::string& name : kAllGenerators) {
    INFO(name);
    hb::ParamSet params("/trace/params");
    params.set("repeat_sample_at_s", 0.6004);  // tick 600
    const hb::Trace glitch = generate(name, 2.0, 3, params);
    const hb::Trace clean = generate(name, 2.0, 3);
    check_valid_samples(glitch, 2.0);
    const auto& g = glitch.samples;
    for (std::size_t k = 0; k < g.size(); ++k) {
      const auto& expected = clean.samples[k == 600 ? 599 : k];
      CHECK(g[k].t_ns == static_cast<int64_t>(k) * 1'000'000);
      CHECK(g[k].pose.p == expected.pose.p);
      CHECK(g[k].pose.q.coeffs() == expected.pose.q.coeffs());
      CHECK(g[k].twist->v == expected.twist->v);
      CHECK(g[k].twist->w == expected.twist->w);
    }
  }
  // Sliding at speed, the repeated tick stands still and the next one
  // catches up: two ticks' motion in one.
  hb::ParamSet params("/trace/params");
  params.set("repeat_sample_at_s", 1.0);
  const hb::Trace slide = generate("slide", 2.0, 1, params);
  const auto& s = slide.samples;
  CHECK(s[1000].pose.p == s[999].pose.p);
  CHECK(s[1000].twist->v == s[999].twist->v);
  CHECK(s[1000].twist->w == s[999].twist->w);
  const double step = (s[999].pose.p - s[998].pose.p).norm();
  CHECK(step > 0);
  CHECK((s[1001].pose.p - s[1000].pose.p).norm() == Approx(2 * step).epsilon(1e-3));

  SECTION("errors name the field") {
    hb::ParamSet bad("/trace/params");
    bad.set("repeat_sample_at_s", 0.0);  // tick 0 has no previous sample
    CHECK(error_location([&] { generate("press", 1.0, 1, bad); }) ==
          "/trace/params/repeat_sample_at_s");
    bad.set("repeat_sample_at_s", 1.5);
    CHECK(error_location([&] { generate("press", 1.0, 1, bad); }) ==
          "/trace/params/repeat_sample_at_s");
    hb::ParamSet unknown("/trace/params");
    unknown.set("repeat_sample_at_s", 0.5);
    unknown.set("dpeth", 0.01);
    CHECK(error_location([&] { generate("press", 1.0, 1, unknown); }) == "/trace/params/dpeth");
  }
}

TEST_CASE("human_like: no energy at or above the cutoff, peak excursion = amplitude") {
  struct Case {
    double duration_s;
    double cutoff_hz;
  };
  for (const Case c : {Case{2.0, 5.0}, Case{4.0, 2.5}, Case{3.0, 9.9}}) {
    INFO("duration " << c.duration_s << " cutoff " << c.cutoff_hz);
    hb::ParamSet params("/trace/params");
    params.set("cutoff_hz", c.cutoff_hz);
    params.set("amplitude_m", 0.02);
    params.set("amplitude_rad", 0.3);
    const hb::Trace trace = generate("human_like", c.duration_s, 11, params);
    // One period: the samples at t in [0, duration).
    const std::size_t n = trace.samples.size() - 1;
    std::vector<std::vector<double>> channels(6, std::vector<double>(n));
    for (std::size_t k = 0; k < n; ++k) {
      const auto& pose = trace.samples[k].pose;
      const hb::Vec3 offset = pose.p - hb::Vec3(0, 0, 0.03);
      const hb::Vec3 rotation = rotation_of(pose.q);
      for (int i = 0; i < 3; ++i) {
        channels[i][k] = offset[i];
        channels[3 + i][k] = rotation[i];
      }
    }
    // Bin m is m / duration Hz.
    const auto first_bin = static_cast<std::size_t>(std::ceil(c.cutoff_hz * c.duration_s - 1e-9));
    for (int i = 0; i < 6; ++i) {
      INFO("channel " << i);
      int bins_with_energy = 0;
      CHECK(energy_fraction_from(channels[i], first_bin, &bins_with_energy) < 1e-20);
      CHECK(bins_with_energy >= std::min<int>(3, static_cast<int>(first_bin) - 1));
      double peak = 0;
      for (double v : channels[i]) peak = std::max(peak, std::abs(v));
      CHECK(peak == Approx(i < 3 ? 0.02 : 0.3).epsilon(1e-12));
    }
  }
}

TEST_CASE("impact: crosses the surface at speed_mps and stops depth past it") {
  hb::ParamSet params("/trace/params");
  params.set("speed_mps", 0.8);
  const hb::Trace trace = generate("impact", 1.0, 1, params);
  const auto& s = trace.samples;
  double fastest = 0;
  for (const auto& sample : s) {
    fastest = std::max(fastest, sample.twist->v.norm());
    if (seconds(sample) <= 0.1) CHECK(sample.pose.p == hb::Vec3(0, 0, 0.03));
  }
  CHECK(fastest == Approx(0.8).epsilon(1e-14));
  // At the surface (z = 0.02) the tool is at full speed.
  for (std::size_t k = 1; k < s.size(); ++k)
    if (s[k - 1].pose.p.z() > 0.02 && s[k].pose.p.z() <= 0.02)
      CHECK(s[k].twist->v.z() == Approx(-0.8).epsilon(1e-3));
  CHECK(s.back().pose.p.z() == Approx(0.015).epsilon(1e-14));
  CHECK(s.back().twist->v.norm() == 0);
}

TEST_CASE("jump: hold, jump by jump and rotation at at_s with zero twist, hold") {
  hb::ParamSet params("/trace/params");
  params.set("at_s", 0.3005);
  params.set("jump", std::vector<double>{0.01, 0, 0});
  params.set("rotation", std::vector<double>{0, 0, 0.2});
  const hb::Trace trace = generate("jump", 1.0, 1, params);
  for (const auto& sample : trace.samples) {
    const bool jumped = sample.t_ns >= 300'500'000;
    CHECK(sample.pose.p.isApprox(hb::Vec3(jumped ? 0.01 : 0.0, 0, 0.03), 1e-15));
    CHECK(rotation_of(sample.pose.q).z() == Approx(jumped ? 0.2 : 0.0).margin(1e-15));
    CHECK(sample.twist->v.norm() == 0);
    CHECK(sample.twist->w.norm() == 0);
  }
  CHECK(trace.samples[300].pose.p.x() == 0.0);
  CHECK(trace.samples[301].pose.p.x() == Approx(0.01));
}

TEST_CASE("rest: one pose, at rest, for the whole duration") {
  hb::ParamSet params("/trace/params");
  params.set("p", std::vector<double>{0.1, 0.2, 0.3});
  params.set("q", std::vector<double>{0, 0, 1, 0});
  const hb::Trace trace = generate("rest", 1.0, 1, params);
  for (const auto& sample : trace.samples) {
    CHECK(sample.pose.p == hb::Vec3(0.1, 0.2, 0.3));
    CHECK(sample.pose.q.y() == 1.0);
    CHECK(sample.twist->v.norm() == 0);
  }
}

TEST_CASE("bad names, durations and parameters are InputErrors naming the field") {
  SECTION("unknown generator") {
    try {
      generate("wobble", 1.0);
      FAIL("expected an InputError");
    } catch (const hb::InputError& error) {
      CHECK(error.location() == "/trace/generator");
      const std::string message = error.what();
      CHECK(message.find("unknown generator \"wobble\"") != std::string::npos);
      CHECK(message.find(
                "press, slide, rub, twist, turn, peg_in_hole, path, human_like, impact, jump, "
                "rest") != std::string::npos);
    }
  }
  SECTION("unknown parameter, for every generator") {
    for (const std::string& name : kAllGenerators) {
      INFO(name);
      hb::ParamSet params("/trace/params");
      params.set("dpeth", 0.01);
      CHECK(error_location([&] { generate(name, 1.0, 1, params); }) == "/trace/params/dpeth");
    }
  }
  SECTION("durations") {
    CHECK(error_location([] { generate("press", 0.0); }) == "/trace/duration_s");
    CHECK(error_location([] { generate("press", -1.0); }) == "/trace/duration_s");
    CHECK(error_location([] { generate("press", 0.0004); }) == "/trace/duration_s");
    CHECK(error_location([] { generate("press", std::nan("")); }) == "/trace/duration_s");
  }
  SECTION("parameter values") {
    auto location_with = [](const std::string& name, const std::string& key, hb::ParamValue value,
                            double duration = 1.0) {
      hb::ParamSet params("/trace/params");
      params.set(key, std::move(value));
      return error_location([&] { generate(name, duration, 1, params); });
    };
    CHECK(location_with("press", "depth", -0.001) == "/trace/params/depth");
    CHECK(location_with("press", "depth", std::string("deep")) == "/trace/params/depth");
    CHECK(location_with("press", "start", std::vector<double>{0, 0}) == "/trace/params/start");
    CHECK(location_with("press", "axis", std::vector<double>{0, 0, 0}) == "/trace/params/axis");
    CHECK(location_with("press", "q", std::vector<double>{2, 0, 0, 0}) == "/trace/params/q");
    CHECK(location_with("press", "hold_fraction", 0.8) == "/trace/params/hold_fraction");
    CHECK(location_with("slide", "direction", std::vector<double>{0, 0, 1}) ==
          "/trace/params/direction");
    CHECK(location_with("human_like", "cutoff_hz", 10.0) == "/trace/params/cutoff_hz");
    CHECK(location_with("human_like", "cutoff_hz", 0.0) == "/trace/params/cutoff_hz");
    // 0.5 s holds no frequency below 1.5 Hz other than 0 (bins are 2 Hz apart).
    CHECK(location_with("human_like", "cutoff_hz", 1.5, 0.5) == "/trace/params/cutoff_hz");
    CHECK(location_with("human_like", "components", 2.5) == "/trace/params/components");
    CHECK(location_with("impact", "speed_mps", 0.01) == "/trace/params/speed_mps");
    CHECK(location_with("jump", "at_s", 1.5) == "/trace/params/at_s");
    CHECK(location_with("peg_in_hole", "offset", std::vector<double>{0, 0, 0}) ==
          "/trace/params/offset");
  }
}
