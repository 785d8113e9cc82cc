// Interval arithmetic, the linear and screw-motion primitive CCD kernels:
// hand-built queries with closed-form times of contact, degenerate cases,
// the budget fallback, and random queries against an independent dense
// sampling of the motion.
#include "algorithms/ccd/ccd_primitives.h"

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "algorithms/ccd/interval.h"
#include "algorithms/ccd/interval_cubic.h"
#include "algorithms/ccd/interval_trig.h"
#include "algorithms/ccd/screw_ccd.h"
#include "algorithms/ccd/screw_motion.h"
#include "hapticbench/closest_points.h"
#include "hapticbench/input_error.h"
#include "tests/support/shape_fixtures.h"

namespace hb {
namespace {

using test::pose;

constexpr double kTolerance = 1e-6;  // the default time tolerance
// The screw kernels bound positions to first order in the width of the time
// interval, so the last excluded interval can end a few tolerances before
// the contact (the linear kernels' centred form excludes up to it).
constexpr double kScrewTimeSlack = 5 * kTolerance;

LinearCcdQuery static_and_moving(const std::array<Vec3, 4>& start, const std::array<Vec3, 4>& end) {
  return LinearCcdQuery{start, end};
}

/// Vertex moving from p0 to p1 against the static triangle (a, b, c).
LinearCcdQuery vertex_against_static_face(const Vec3& p0, const Vec3& p1, const Vec3& a,
                                          const Vec3& b, const Vec3& c) {
  return static_and_moving({p0, a, b, c}, {p1, a, b, c});
}

// The triangle of most hand-built vertex-face cases: in the plane z = 0,
// holding the origin well inside.
const Vec3 kA(-1, -1, 0), kB(1, -1, 0), kC(0, 1, 0);

// ---------------------------------------------------------------------------
// Interval arithmetic

TEST_CASE("next_down and next_up step exactly one ulp for ordinary magnitudes", "[interval]") {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> mantissa(1.0, 2.0);
  std::uniform_int_distribution<int> exponent(-130, 130);
  for (int i = 0; i < 100000; ++i) {
    const double x = std::ldexp(mantissa(rng), exponent(rng)) * (i % 2 ? -1 : 1);
    REQUIRE(next_down(x) == std::nextafter(x, -std::numeric_limits<double>::infinity()));
    REQUIRE(next_up(x) == std::nextafter(x, std::numeric_limits<double>::infinity()));
  }
  // Powers of two: the step below is half the step above.
  for (int e = -100; e <= 100; ++e) {
    const double x = std::ldexp(1.0, e);
    CHECK(next_down(x) == std::nextafter(x, 0.0));
    CHECK(next_up(-x) == std::nextafter(-x, 0.0));
  }
}

TEST_CASE("next_down and next_up never step less than one ulp for tiny values", "[interval]") {
  const double tiny[] = {0.0,
                         -0.0,
                         std::numeric_limits<double>::denorm_min(),
                         std::numeric_limits<double>::min(),
                         1e-300,
                         1e-100,
                         3e-45};
  for (const double x : tiny) {
    for (const double v : {x, -x}) {
      CHECK(next_down(v) < v);
      CHECK(next_up(v) > v);
      CHECK(next_down(v) <= std::nextafter(v, -1.0));
      CHECK(next_up(v) >= std::nextafter(v, 1.0));
      CHECK(next_up(v) - v <= 0x1p-199);  // the documented absolute step
    }
  }
}

// Exact error terms of a rounded sum and product (TwoSum, and fma for the
// product): the exact value is rounded + error.
double two_sum_error(double a, double b, double s) {
  const double bb = s - a;
  return (a - (s - bb)) + (b - bb);
}

TEST_CASE("interval sums and products of points hold the exact result", "[interval]") {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-60, 60);
  for (int i = 0; i < 100000; ++i) {
    const double a = std::ldexp(mantissa(rng), exponent(rng));
    const double b = std::ldexp(mantissa(rng), exponent(rng));
    const double s = a + b, s_err = two_sum_error(a, b, s);
    const Interval sum = Interval(a) + Interval(b);
    // lo <= s + s_err, written so that the comparison is exact.
    REQUIRE(sum.lo - s <= s_err);
    REQUIRE(sum.hi - s >= s_err);
    const double d = a - b, d_err = two_sum_error(a, -b, d);
    const Interval difference = Interval(a) - Interval(b);
    REQUIRE(difference.lo - d <= d_err);
    REQUIRE(difference.hi - d >= d_err);
    const double p = a * b, p_err = std::fma(a, b, -p);
    const Interval product = Interval(a) * Interval(b);
    REQUIRE(product.lo - p <= p_err);
    REQUIRE(product.hi - p >= p_err);
    REQUIRE(product.lo < product.hi);
  }
}

TEST_CASE("interval operations hold every combination of operand values", "[interval]") {
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> value(-3.0, 3.0);
  std::uniform_real_distribution<double> fraction(0.0, 1.0);
  for (int i = 0; i < 2000; ++i) {
    double a0 = value(rng), a1 = value(rng), b0 = value(rng), b1 = value(rng);
    if (a0 > a1) std::swap(a0, a1);
    if (b0 > b1) std::swap(b0, b1);
    const Interval a(a0, a1), b(b0, b1);
    const Interval sum = a + b, difference = a - b, product = a * b, square = sqr(a);
    for (int k = 0; k < 50; ++k) {
      const double x = a0 + fraction(rng) * (a1 - a0), y = b0 + fraction(rng) * (b1 - b0);
      REQUIRE(sum.contains(x + y));
      REQUIRE(difference.contains(x - y));
      REQUIRE(product.contains(x * y));
      REQUIRE(square.contains(x * x));
      REQUIRE(square.lo >= 0);
      if (b.excludes_zero()) REQUIRE((a / b).contains(x / y));
    }
  }
  CHECK(sqr(Interval(-2, 3)).lo == 0);
  CHECK(sqr(Interval(-2, 3)).contains(9));
  CHECK((Interval(1, 2) / Interval(-4, -2)).contains(-0.25));
  CHECK((Interval(1, 2) / Interval(-4, -2)).contains(-1));
}

TEST_CASE("interval predicates", "[interval]") {
  CHECK(Interval(1e-300, 1).certainly_positive());
  CHECK_FALSE(Interval(0, 1).certainly_positive());
  CHECK(Interval(-1, -1e-300).certainly_negative());
  CHECK(Interval(0, 0).contains_zero());
  CHECK(Interval(-1, 1).contains_zero());
  CHECK_FALSE(Interval(-1, 1).excludes_zero());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(Interval(nan, nan).contains_zero());  // proves nothing, excludes nothing
}

double cubic_value(const IntervalCubic& p, long double t) {
  return static_cast<double>(
      ((static_cast<long double>(p.k[3].lo) * t + p.k[2].lo) * t + p.k[1].lo) * t + p.k[0].lo);
}

TEST_CASE("a cubic's range holds its values and tightens quadratically", "[interval]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> coefficient(-5.0, 5.0);
  std::uniform_real_distribution<double> fraction(0.0, 1.0);
  for (int i = 0; i < 2000; ++i) {
    IntervalCubic p;
    for (Interval& k : p.k) k = Interval(coefficient(rng));
    double t0 = fraction(rng), t1 = fraction(rng);
    if (t0 > t1) std::swap(t0, t1);
    const Interval range = p.range(Interval(t0, t1));
    for (int k = 0; k <= 100; ++k) {
      const long double t = t0 + (t1 - t0) * (k / 100.0L);
      REQUIRE(range.contains(cubic_value(p, t)));
    }
  }
  // p(t) = t³ on [0.5, 0.5 + w]: true width ≈ 0.75 w; the centred form's
  // excess is O(w²).
  IntervalCubic cube;
  cube.k[3] = Interval(1.0);
  for (const double w : {1e-2, 1e-4, 1e-6}) {
    const Interval range = cube.range(Interval(0.5, 0.5 + w));
    const double true_width = std::pow(0.5 + w, 3) - 0.125;
    CHECK(range.width() <= true_width + 4 * w * w + 1e-15);
  }
}

TEST_CASE("interval cosine and sine hold the function and its extremes", "[interval]") {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> start(-10.0, 10.0);
  std::uniform_real_distribution<double> width(0.0, 7.0);
  std::uniform_real_distribution<double> fraction(0.0, 1.0);
  for (int i = 0; i < 5000; ++i) {
    const double lo = start(rng), hi = lo + (i % 3 == 0 ? 1e-3 : 1.0) * width(rng);
    const Interval c = interval_cos(Interval(lo, hi)), s = interval_sin(Interval(lo, hi));
    double c_min = 2, c_max = -2, s_min = 2, s_max = -2;
    for (int k = 0; k <= 200; ++k) {
      const double x = lo + (hi - lo) * (k / 200.0);
      REQUIRE(c.contains(std::cos(x)));
      REQUIRE(s.contains(std::sin(x)));
      c_min = std::min(c_min, std::cos(x));
      c_max = std::max(c_max, std::cos(x));
      s_min = std::min(s_min, std::sin(x));
      s_max = std::max(s_max, std::sin(x));
    }
    REQUIRE(c.lo >= -1);
    REQUIRE(c.hi <= 1);
    // Not much wider than the sampled range (sampling misses at most
    // (π/200)²/2 of an extreme).
    if (hi - lo < 6) {
      REQUIRE(c.width() <= (c_max - c_min) + 2 * std::pow((hi - lo) / 200, 2) + 1e-14);
      REQUIRE(s.width() <= (s_max - s_min) + 2 * std::pow((hi - lo) / 200, 2) + 1e-14);
    }
  }
  constexpr double pi = std::numbers::pi;
  CHECK(interval_cos(Interval(3.0, 3.3)).lo == -1);    // holds π
  CHECK(interval_cos(Interval(-0.1, 0.2)).hi == 1);    // holds 0
  CHECK(interval_sin(Interval(1.5, 1.6)).hi == 1);     // holds π/2
  CHECK(interval_sin(Interval(-1.6, -1.5)).lo == -1);  // holds −π/2
  CHECK(interval_cos(Interval(pi, pi)).lo == -1);      // an endpoint within rounding of π
  CHECK(interval_cos(Interval(0.5, 1.0)).hi < 0.88);   // monotonic piece: no extreme
  CHECK(interval_cos(Interval(0, 100)).lo == -1);
}

// ---------------------------------------------------------------------------
// Linear vertex-face and edge-edge

TEST_CASE("a vertex crossing a face at t = 0.25", "[ccd]") {
  // z(t) = 1 − 4t reaches the plane z = 0 at t = 0.25, above the origin.
  const CcdResult r =
      vertex_face_ccd(vertex_against_static_face(Vec3(0, 0, 1), Vec3(0, 0, -3), kA, kB, kC));
  REQUIRE(r.contact);
  CHECK(r.toi <= 0.25);
  CHECK(r.toi >= 0.25 - kTolerance);
  CHECK_FALSE(r.budget_exhausted);
  // The same with the face moving and the vertex still: only relative motion counts.
  const CcdResult moving_face = vertex_face_ccd(static_and_moving(
      {Vec3(0, 0, 0), kA - Vec3(0, 0, 1), kB - Vec3(0, 0, 1), kC - Vec3(0, 0, 1)},
      {Vec3(0, 0, 0), kA + Vec3(0, 0, 3), kB + Vec3(0, 0, 3), kC + Vec3(0, 0, 3)}));
  REQUIRE(moving_face.contact);
  CHECK(moving_face.toi <= 0.25);
  CHECK(moving_face.toi >= 0.25 - kTolerance);
}

TEST_CASE("a vertex crossing the plane beside the face is no contact", "[ccd]") {
  // Crosses z = 0 at (0.6, 0.3), outside the edge from (1,−1) to (0,1) (at
  // y = 0.3 the triangle ends at x = 0.35).
  const CcdResult r = vertex_face_ccd(
      vertex_against_static_face(Vec3(0.6, 0.3, 1), Vec3(0.6, 0.3, -1), kA, kB, kC));
  CHECK_FALSE(r.contact);
  // A near miss: 0.01 outside the edge from (−1,−1) to (1,−1).
  const CcdResult near = vertex_face_ccd(
      vertex_against_static_face(Vec3(0, -1.01, 1), Vec3(0, -1.01, -1), kA, kB, kC));
  CHECK_FALSE(near.contact);
  // And a vertex stopping 1e-3 short of the plane.
  const CcdResult short_of =
      vertex_face_ccd(vertex_against_static_face(Vec3(0, 0, 1), Vec3(0, 0, 1e-3), kA, kB, kC));
  CHECK_FALSE(short_of.contact);
}

TEST_CASE("an edge crossing an edge at t = 0.5", "[ccd]") {
  // Edge a along x sinks from z = 1 to z = −1 through edge b along y.
  const CcdResult r = edge_edge_ccd(
      static_and_moving({Vec3(-1, 0, 1), Vec3(1, 0, 1), Vec3(0, -1, 0), Vec3(0, 1, 0)},
                        {Vec3(-1, 0, -1), Vec3(1, 0, -1), Vec3(0, -1, 0), Vec3(0, 1, 0)}));
  REQUIRE(r.contact);
  CHECK(r.toi <= 0.5);
  CHECK(r.toi >= 0.5 - kTolerance);
  // Offset along y by 1.5: the lines meet at t = 0.5 outside edge b.
  const CcdResult past = edge_edge_ccd(
      static_and_moving({Vec3(-1, 0, 1), Vec3(1, 0, 1), Vec3(0, 0.5, 0), Vec3(0, 2.5, 0)},
                        {Vec3(-1, 0, -1), Vec3(1, 0, -1), Vec3(0, 0.5, 0), Vec3(0, 2.5, 0)}));
  CHECK_FALSE(past.contact);
  // Passing 1e-3 beyond the end of edge a.
  const CcdResult beyond = edge_edge_ccd(
      static_and_moving({Vec3(-1, 0, 1), Vec3(-1e-3, 0, 1), Vec3(0, -1, 0), Vec3(0, 1, 0)},
                        {Vec3(-1, 0, -1), Vec3(-1e-3, 0, -1), Vec3(0, -1, 0), Vec3(0, 1, 0)}));
  CHECK_FALSE(beyond.contact);
}

TEST_CASE("parallel edges: sliding along one line, and side by side", "[ccd]") {
  // Collinear on the x axis: edge a [−3, −2] slides to [−0.5, 0.5] and meets
  // edge b [0, 1] when its right end −2 + 2.5 t reaches 0, at t = 0.8.
  const CcdResult collinear = edge_edge_ccd(
      static_and_moving({Vec3(-3, 0, 0), Vec3(-2, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)},
                        {Vec3(-0.5, 0, 0), Vec3(0.5, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)}));
  REQUIRE(collinear.contact);
  CHECK(collinear.toi <= 0.8);
  CHECK(collinear.toi >= 0.8 - kTolerance);
  // Collinear but stopping 0.1 short.
  const CcdResult short_of = edge_edge_ccd(
      static_and_moving({Vec3(-3, 0, 0), Vec3(-2, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)},
                        {Vec3(-1.1, 0, 0), Vec3(-0.1, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)}));
  CHECK_FALSE(short_of.contact);
  // Parallel in one plane, 0.1 apart, sliding past each other: coplanar at
  // every t (f ≡ 0), never touching.
  const CcdResult side_by_side = edge_edge_ccd(
      static_and_moving({Vec3(-3, 0.1, 0), Vec3(-2, 0.1, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)},
                        {Vec3(2, 0.1, 0), Vec3(3, 0.1, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)}));
  CHECK_FALSE(side_by_side.contact);
  // Parallel, closing in sideways until they lie on one line at t = 0.5.
  const CcdResult closing = edge_edge_ccd(
      static_and_moving({Vec3(0.5, 1, 0), Vec3(1.5, 1, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)},
                        {Vec3(0.5, -1, 0), Vec3(1.5, -1, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)}));
  REQUIRE(closing.contact);
  CHECK(closing.toi <= 0.5);
  CHECK(closing.toi >= 0.5 - kTolerance);
}

TEST_CASE("touching at t = 0 and at t = 1", "[ccd]") {
  // On the face at t = 0, moving away.
  const CcdResult start =
      vertex_face_ccd(vertex_against_static_face(Vec3(0, 0, 0), Vec3(0, 0, 1), kA, kB, kC));
  REQUIRE(start.contact);
  CHECK(start.toi == 0);
  // Reaching the face exactly at t = 1.
  const CcdResult end =
      vertex_face_ccd(vertex_against_static_face(Vec3(0, 0, 1), Vec3(0, 0, 0), kA, kB, kC));
  REQUIRE(end.contact);
  CHECK(end.toi <= 1);
  CHECK(end.toi >= 1 - kTolerance);
  // Reaching a vertex of the face (a boundary point) exactly at t = 1.
  const CcdResult corner =
      vertex_face_ccd(vertex_against_static_face(kB + Vec3(0, 0, 1), kB, kA, kB, kC));
  REQUIRE(corner.contact);
  CHECK(corner.toi >= 1 - kTolerance);
  // Edges touching end to end at t = 1.
  const CcdResult edges = edge_edge_ccd(
      static_and_moving({Vec3(-2, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 0), Vec3(0, 1, 0)},
                        {Vec3(-2, 0, 0), Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 1, 0)}));
  REQUIRE(edges.contact);
  CHECK(edges.toi >= 1 - kTolerance);
  // Edges crossing at t = 0 and separating.
  const CcdResult apart = edge_edge_ccd(
      static_and_moving({Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 1, 0)},
                        {Vec3(-1, 0, 1), Vec3(1, 0, 1), Vec3(0, -1, 0), Vec3(0, 1, 0)}));
  REQUIRE(apart.contact);
  CHECK(apart.toi == 0);
}

TEST_CASE("zero motion, with and without contact", "[ccd]") {
  const CcdResult resting =
      vertex_face_ccd(vertex_against_static_face(Vec3(0.2, 0.1, 0), Vec3(0.2, 0.1, 0), kA, kB, kC));
  REQUIRE(resting.contact);
  CHECK(resting.toi == 0);
  const CcdResult hovering =
      vertex_face_ccd(vertex_against_static_face(Vec3(0, 0, 1e-9), Vec3(0, 0, 1e-9), kA, kB, kC));
  CHECK_FALSE(hovering.contact);
  const CcdResult beside = vertex_face_ccd(
      vertex_against_static_face(Vec3(2, 0, 0), Vec3(2, 0, 0), kA, kB, kC));  // in the plane
  CHECK_FALSE(beside.contact);
  const std::array<Vec3, 4> crossing{Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 1, 0)};
  CHECK(edge_edge_ccd(static_and_moving(crossing, crossing)).contact);
  const std::array<Vec3, 4> skew{Vec3(-1, 0, 1e-9), Vec3(1, 0, 1e-9), Vec3(0, -1, 0),
                                 Vec3(0, 1, 0)};
  CHECK_FALSE(edge_edge_ccd(static_and_moving(skew, skew)).contact);
}

TEST_CASE("degenerate primitives: a collapsed triangle and a zero-length edge", "[ccd]") {
  // Triangle collapsed onto the segment (−1,0,0)–(1,0,0); the vertex passes
  // through the segment at t = 0.5, then a vertex passes beside it.
  const Vec3 a(-1, 0, 0), b(1, 0, 0), c(0, 0, 0);
  const CcdResult through =
      vertex_face_ccd(vertex_against_static_face(Vec3(0.3, 0, 1), Vec3(0.3, 0, -1), a, b, c));
  REQUIRE(through.contact);
  CHECK(through.toi <= 0.5);
  CHECK(through.toi >= 0.5 - kTolerance);
  const CcdResult beside =
      vertex_face_ccd(vertex_against_static_face(Vec3(0.3, 0.1, 1), Vec3(0.3, 0.1, -1), a, b, c));
  CHECK_FALSE(beside.contact);
  // A zero-length edge (a point) passing through an edge at t = 0.25.
  const CcdResult point_edge = edge_edge_ccd(
      static_and_moving({Vec3(0.5, 0, 1), Vec3(0.5, 0, 1), Vec3(0, 0, 0), Vec3(1, 0, 0)},
                        {Vec3(0.5, 0, -3), Vec3(0.5, 0, -3), Vec3(0, 0, 0), Vec3(1, 0, 0)}));
  REQUIRE(point_edge.contact);
  CHECK(point_edge.toi <= 0.25);
  CHECK(point_edge.toi >= 0.25 - kTolerance);
}

TEST_CASE("the evaluation budget answers conservatively", "[ccd]") {
  const LinearCcdQuery query =
      vertex_against_static_face(Vec3(0, 0, 1), Vec3(0, 0, -1), kA, kB, kC);  // toi 0.5
  for (const int budget : {1, 2, 3, 5, 10, 20}) {
    CcdSettings settings;
    settings.max_evaluations = budget;
    const CcdResult r = vertex_face_ccd(query, settings);
    INFO("budget " << budget);
    REQUIRE(r.contact);
    REQUIRE(r.budget_exhausted);
    CHECK(r.evaluations == budget);
    CHECK(r.toi <= 0.5);  // never later than the true contact
  }
  // A clear miss needs no budget beyond the first evaluations.
  CcdSettings tiny;
  tiny.max_evaluations = 1;
  CHECK_FALSE(
      vertex_face_ccd(vertex_against_static_face(Vec3(5, 5, 1), Vec3(5, 5, -1), kA, kB, kC), tiny)
          .contact);
  // A coarser tolerance stops sooner, still at or before the contact.
  CcdSettings coarse;
  coarse.time_tolerance = 0.1;
  const CcdResult r = vertex_face_ccd(query, coarse);
  REQUIRE(r.contact);
  CHECK(r.toi <= 0.5);
  CHECK(r.toi >= 0.4);
}

TEST_CASE("non-finite or huge input is answered as contact at t = 0", "[ccd]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const CcdResult r =
      vertex_face_ccd(vertex_against_static_face(Vec3(nan, 0, 1), Vec3(0, 0, -1), kA, kB, kC));
  CHECK(r.contact);
  CHECK(r.input_out_of_range);
  CHECK(r.toi == 0);
  CHECK(
      edge_edge_ccd(static_and_moving({Vec3(1e70, 0, 0), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()},
                                      {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()}))
          .input_out_of_range);
}

TEST_CASE("settings out of range are rejected naming the field", "[ccd]") {
  CcdSettings settings;
  settings.time_tolerance = 0;
  CHECK_THROWS_WITH(validate_ccd_settings(settings, "params.ccd"),
                    Catch::Contains("params.ccd.time_tolerance"));
  settings = CcdSettings{};
  settings.max_evaluations = 0;
  CHECK_THROWS_AS(validate_ccd_settings(settings, "params.ccd"), InputError);
  for (const double limit : {-0.1, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    settings = CcdSettings{};
    settings.time_limit = limit;
    CHECK_THROWS_WITH(validate_ccd_settings(settings, "params.ccd"),
                      Catch::Contains("params.ccd.time_limit"));
  }
  CHECK_NOTHROW(validate_ccd_settings(CcdSettings{}, "params.ccd"));
}

TEST_CASE("a time limit searches only up to it", "[ccd]") {
  // z(t) = 1 − 4t reaches the face at t = 0.25.
  const LinearCcdQuery query =
      vertex_against_static_face(Vec3(0, 0, 1), Vec3(0, 0, -3), kA, kB, kC);
  const CcdResult unlimited = vertex_face_ccd(query);
  REQUIRE(unlimited.contact);
  for (const double limit : {0.0, 0.1, 0.2, 0.249}) {
    CcdSettings settings;
    settings.time_limit = limit;
    const CcdResult r = vertex_face_ccd(query, settings);
    INFO("limit " << limit);
    CHECK_FALSE(r.contact);
    CHECK(r.evaluations <= unlimited.evaluations);
  }
  for (const double limit : {0.25, 0.2500001, 0.26, 0.5, 0.75, 1.0}) {
    CcdSettings settings;
    settings.time_limit = limit;
    const CcdResult r = vertex_face_ccd(query, settings);
    INFO("limit " << limit);
    REQUIRE(r.contact);
    CHECK(r.toi <= 0.25);
    CHECK(r.toi >= 0.25 - kTolerance);
  }
  // Touching at t = 0 is found with a zero limit; a face reached at t = 0.5
  // by an edge is not found before it.
  CcdSettings zero;
  zero.time_limit = 0;
  const CcdResult resting = vertex_face_ccd(
      vertex_against_static_face(Vec3(0.2, 0.1, 0), Vec3(0.2, 0.1, -1), kA, kB, kC), zero);
  REQUIRE(resting.contact);
  CHECK(resting.toi == 0);
  const LinearCcdQuery edges =
      static_and_moving({Vec3(-1, 0, 1), Vec3(1, 0, 1), Vec3(0, -1, 0), Vec3(0, 1, 0)},
                        {Vec3(-1, 0, -1), Vec3(1, 0, -1), Vec3(0, -1, 0), Vec3(0, 1, 0)});
  CcdSettings before;
  before.time_limit = 0.49;
  CHECK_FALSE(edge_edge_ccd(edges, before).contact);
  CcdSettings after;
  after.time_limit = 0.51;
  const CcdResult crossing = edge_edge_ccd(edges, after);
  REQUIRE(crossing.contact);
  CHECK(crossing.toi <= 0.5);
  CHECK(crossing.toi >= 0.5 - kTolerance);
}

// ---------------------------------------------------------------------------
// Random queries against dense sampling (an independent reference in double)

/// Distance of segments (p1, q1) and (p2, q2).
double segment_distance(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2) {
  return closest_points_of_segments(p1, q1, p2, q2).distance();
}

Vec3 lerp(const Vec3& a, const Vec3& b, double t) { return a + t * (b - a); }

/// The query's points at time t.
std::array<Vec3, 4> points_at(const LinearCcdQuery& q, double t) {
  return {lerp(q.start[0], q.end[0], t), lerp(q.start[1], q.end[1], t),
          lerp(q.start[2], q.end[2], t), lerp(q.start[3], q.end[3], t)};
}

/// Largest speed of any point of the query (m per unit t): a bound on how
/// fast the distance between the primitives changes is twice it.
double largest_speed(const LinearCcdQuery& q) {
  double speed = 0;
  for (int i = 0; i < 4; ++i) speed = std::max(speed, (q.end[i] - q.start[i]).norm());
  return speed;
}

/// What dense sampling of the motion says.
struct SampledTruth {
  double first_contact_t = 2;  // the sample by which a contact has surely happened; 2 if none
  double min_distance = 1e300;
};

constexpr int kSamples = 2000;
constexpr double kInsideMargin = 1e-3;

SampledTruth sample_vertex_face(const LinearCcdQuery& q) {
  SampledTruth truth;
  double previous_side = 0;
  bool previous_inside = false;
  for (int k = 0; k <= kSamples; ++k) {
    const double t = static_cast<double>(k) / kSamples;
    const auto x = points_at(q, t);
    const Vec3 n = (x[2] - x[1]).cross(x[3] - x[1]);
    const double side = n.dot(x[0] - x[1]);
    // Barycentric coordinates of the projection of the vertex.
    const double area = n.squaredNorm();
    bool inside = false;
    if (area > 1e-12) {
      const double u = n.dot((x[2] - x[0]).cross(x[3] - x[0])) / area;
      const double v = n.dot((x[3] - x[0]).cross(x[1] - x[0])) / area;
      inside = u > kInsideMargin && v > kInsideMargin && 1 - u - v > kInsideMargin;
    }
    const double distance = (x[0] - closest_point_on_triangle(x[0], x[1], x[2], x[3])).norm();
    truth.min_distance = std::min(truth.min_distance, distance);
    const bool crossed = k > 0 && inside && previous_inside && side * previous_side <= 0;
    if (truth.first_contact_t > 1 && (distance < 1e-12 || crossed)) truth.first_contact_t = t;
    previous_side = side;
    previous_inside = inside;
  }
  return truth;
}

SampledTruth sample_edge_edge(const LinearCcdQuery& q) {
  SampledTruth truth;
  double previous_side = 0;
  bool previous_inside = false;
  for (int k = 0; k <= kSamples; ++k) {
    const double t = static_cast<double>(k) / kSamples;
    const auto x = points_at(q, t);
    const Vec3 da = x[1] - x[0], db = x[3] - x[2], r = x[0] - x[2];
    const double side = da.cross(db).dot(x[2] - x[0]);
    // Parameters of the closest points of the two lines.
    const double a = da.squaredNorm(), e = db.squaredNorm(), b = da.dot(db);
    const double c = da.dot(r), f = db.dot(r), denom = a * e - b * b;
    bool inside = false;
    if (denom > 1e-6 * a * e) {
      const double s = (b * f - c * e) / denom, u = (a * f - b * c) / denom;
      inside =
          s > kInsideMargin && s < 1 - kInsideMargin && u > kInsideMargin && u < 1 - kInsideMargin;
    }
    const double distance = segment_distance(x[0], x[1], x[2], x[3]);
    truth.min_distance = std::min(truth.min_distance, distance);
    const bool crossed = k > 0 && inside && previous_inside && side * previous_side <= 0;
    if (truth.first_contact_t > 1 && (distance < 1e-12 || crossed)) truth.first_contact_t = t;
    previous_side = side;
    previous_inside = inside;
  }
  return truth;
}

/// A random query whose primitives come close to each other mid-step:
/// points drawn around a common centre, moving by up to `reach`.
LinearCcdQuery random_query(std::mt19937_64& rng, double reach) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  auto random_vec = [&]() { return Vec3(unit(rng), unit(rng), unit(rng)); };
  LinearCcdQuery q;
  for (int i = 0; i < 4; ++i) {
    q.start[i] = random_vec();
    q.end[i] = q.start[i] + reach * random_vec();
  }
  return q;
}

template <class Kernel, class Sample>
void check_against_sampling(Kernel kernel, Sample sample, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  int contacts = 0, separated = 0;
  for (int i = 0; i < 400; ++i) {
    const LinearCcdQuery q = random_query(rng, i % 2 ? 2.0 : 0.7);
    const SampledTruth truth = sample(q);
    const CcdResult r = kernel(q, CcdSettings{});
    INFO("query " << i);
    if (truth.first_contact_t <= 1) {
      ++contacts;
      REQUIRE(r.contact);
      REQUIRE(r.toi <= truth.first_contact_t);
    }
    // The distance changes by at most 2·speed per unit t, so between
    // samples it cannot dip by more than speed / kSamples.
    if (truth.min_distance - largest_speed(q) / kSamples > 1e-3) {
      ++separated;
      REQUIRE_FALSE(r.contact);
    }
  }
  // The generator must exercise both sides.
  CHECK(contacts >= 20);
  CHECK(separated >= 100);
}

TEST_CASE("random vertex-face queries agree with dense sampling", "[ccd][random]") {
  check_against_sampling([](const auto& q, const auto& s) { return vertex_face_ccd(q, s); },
                         sample_vertex_face, 21);
}

TEST_CASE("random edge-edge queries agree with dense sampling", "[ccd][random]") {
  check_against_sampling([](const auto& q, const auto& s) { return edge_edge_ccd(q, s); },
                         sample_edge_edge, 22);
}

TEST_CASE("with a small budget random queries still never answer later", "[ccd][random]") {
  std::mt19937_64 rng(23);
  CcdSettings settings;
  settings.max_evaluations = 6;
  int exhausted = 0;
  for (int i = 0; i < 400; ++i) {
    const LinearCcdQuery q = random_query(rng, 2.0);
    const SampledTruth truth = sample_vertex_face(q);
    const CcdResult r = vertex_face_ccd(q, settings);
    exhausted += r.budget_exhausted;
    if (truth.first_contact_t <= 1) {
      REQUIRE(r.contact);
      REQUIRE(r.toi <= truth.first_contact_t);
    }
  }
  CHECK(exhausted > 0);
}

// ---------------------------------------------------------------------------
// Screw motion

TEST_CASE("a screw motion runs from the start pose to the end pose", "[screw]") {
  const Pose start = pose(Vec3(0.1, -0.2, 0.3), 0.4, Vec3(1, 2, 3));
  const Pose end = pose(Vec3(-0.3, 0.5, 0.2), 2.1, Vec3(-1, 0.5, 2));
  const ScrewMotion motion(start, end);
  const Vec3 r(0.03, -0.02, 0.05);
  CHECK((motion.point_at(r, 0) - start.transform_point(r)).norm() < 1e-12);
  CHECK((motion.point_at(r, 1) - end.transform_point(r)).norm() < 1e-12);
  CHECK((motion.rotation_at(1) - end.q.toRotationMatrix()).norm() < 1e-12);
  // Constant rate about a fixed axis: the relative rotation at t is ωt about u.
  const Mat3 half = motion.rotation_at(0.5) * start.q.toRotationMatrix().transpose();
  const Eigen::AngleAxisd relative(half);
  CHECK(relative.angle() == Approx(0.5 * motion.angle()).margin(1e-12));
  // The interval path holds the point over any interval of t.
  const ScrewVectorPath path = motion.path(r);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> fraction(0.0, 1.0);
  for (int i = 0; i < 500; ++i) {
    double t0 = fraction(rng), t1 = fraction(rng);
    if (t0 > t1) std::swap(t0, t1);
    const ScrewMotionSample sample = motion.sample(Interval(t0, t1));
    const IntervalVec3 box = path.position(sample);
    const Vec3 world_point(0.2, 0.1, -0.3);
    const IntervalVec3 body_box = motion.body_coordinates(world_point, sample);
    for (int k = 0; k <= 20; ++k) {
      const double t = t0 + (t1 - t0) * k / 20.0;
      const Vec3 p = motion.point_at(r, t);
      REQUIRE(box.x.contains(p.x()));
      REQUIRE(box.y.contains(p.y()));
      REQUIRE(box.z.contains(p.z()));
      // The static point in body coordinates: R(t)ᵀ (x − T(t)).
      const Vec3 b =
          motion.rotation_at(t).transpose() * (world_point - motion.point_at(Vec3::Zero(), t));
      REQUIRE(body_box.x.contains(b.x()));
      REQUIRE(body_box.y.contains(b.y()));
      REQUIRE(body_box.z.contains(b.z()));
    }
  }
}

TEST_CASE("screw motion without rotation matches the linear kernels", "[screw]") {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int contacts = 0;
  for (int i = 0; i < 300; ++i) {
    const Vec3 c0(unit(rng), unit(rng), unit(rng)),
        c1 = c0 + 2 * Vec3(unit(rng), unit(rng), unit(rng));
    const ScrewMotion motion(Pose{c0, Quat::Identity()}, Pose{c1, Quat::Identity()});
    const Vec3 r(unit(rng) * 0.1, unit(rng) * 0.1, unit(rng) * 0.1);
    const std::array<Vec3, 3> face{Vec3(unit(rng), unit(rng), unit(rng)),
                                   Vec3(unit(rng), unit(rng), unit(rng)),
                                   Vec3(unit(rng), unit(rng), unit(rng))};
    const LinearCcdQuery linear{{c0 + r, face[0], face[1], face[2]},
                                {c1 + r, face[0], face[1], face[2]}};
    const SampledTruth truth = sample_vertex_face(linear);
    const CcdResult screw = screw_vertex_face_ccd(motion, r, face);
    INFO("query " << i);
    if (truth.first_contact_t <= 1) {
      ++contacts;
      REQUIRE(screw.contact);
      REQUIRE(screw.toi <= truth.first_contact_t);
      REQUIRE(screw.toi >= truth.first_contact_t - 2.0 / kSamples - kScrewTimeSlack);
    }
    if (truth.min_distance - largest_speed(linear) / kSamples > 1e-3) REQUIRE_FALSE(screw.contact);
  }
  CHECK(contacts >= 10);
}

TEST_CASE("a rotating point hits a plane at the analytic time", "[screw]") {
  // The body point (1, 0, 0) turns about z by π/2: it is at (cos ωt, sin ωt, 0)
  // and reaches the plane y = 0.5 when ωt = π/6, at t = 1/3.
  const ScrewMotion motion(Pose{}, pose(Vec3::Zero(), std::numbers::pi / 2, Vec3::UnitZ()));
  const std::array<Vec3, 3> face{Vec3(0, 0.5, -1), Vec3(2, 0.5, -1), Vec3(1, 0.5, 1)};
  const CcdResult r = screw_vertex_face_ccd(motion, Vec3(1, 0, 0), face);
  REQUIRE(r.contact);
  CHECK(r.toi <= 1.0 / 3);
  CHECK(r.toi >= 1.0 / 3 - kScrewTimeSlack);
  // Turning only by π/6 − 0.05 it stops 0.043 short of the plane.
  const ScrewMotion shorter(Pose{}, pose(Vec3::Zero(), std::numbers::pi / 6 - 0.05, Vec3::UnitZ()));
  CHECK_FALSE(screw_vertex_face_ccd(shorter, Vec3(1, 0, 0), face).contact);
  // A face of the body turning into a static vertex: the body triangle lies
  // in the body plane x = 1, so after turning by θ its plane is
  // {p : p · (cos θ, sin θ, 0) = 1}. The vertex is where the body point
  // (1, 0.3, 0.1), inside the triangle, is after turning by π/3; before
  // that its distance along the normal, cos δ − 0.3 sin δ (δ the angle
  // still to turn), is below 1. So contact at ωt = π/3, t = 2/3.
  const std::array<Vec3, 3> body_face{Vec3(1, -1, -1), Vec3(1, -1, 1), Vec3(1, 1, 0)};
  const double theta = std::numbers::pi / 3;
  const Vec3 vertex(std::cos(theta) - 0.3 * std::sin(theta),
                    std::sin(theta) + 0.3 * std::cos(theta), 0.1);
  const CcdResult f = screw_face_vertex_ccd(motion, body_face, vertex);
  REQUIRE(f.contact);
  CHECK(f.toi <= 2.0 / 3);
  CHECK(f.toi >= 2.0 / 3 - kScrewTimeSlack);
}

TEST_CASE("a rotating edge meets a static edge at the analytic time", "[screw]") {
  // The body edge from (0.5, 0, 0) to (2, 0, 0) turns about z by π/2; the
  // static vertical edge at radius 1, angle 60°, is met when the turn
  // reaches π/3, at t = 2/3.
  const ScrewMotion motion(Pose{}, pose(Vec3::Zero(), std::numbers::pi / 2, Vec3::UnitZ()));
  const double a = std::numbers::pi / 3;
  const std::array<Vec3, 2> world_edge{Vec3(std::cos(a), std::sin(a), -1),
                                       Vec3(std::cos(a), std::sin(a), 1)};
  const CcdResult r = screw_edge_edge_ccd(motion, {Vec3(0.5, 0, 0), Vec3(2, 0, 0)}, world_edge);
  REQUIRE(r.contact);
  CHECK(r.toi <= 2.0 / 3);
  CHECK(r.toi >= 2.0 / 3 - kScrewTimeSlack);
  // A static edge at radius 2.2, beyond the body edge's reach: no contact.
  const std::array<Vec3, 2> far_edge{Vec3(2.2 * std::cos(a), 2.2 * std::sin(a), -1),
                                     Vec3(2.2 * std::cos(a), 2.2 * std::sin(a), 1)};
  CHECK_FALSE(screw_edge_edge_ccd(motion, {Vec3(0.5, 0, 0), Vec3(2, 0, 0)}, far_edge).contact);
}

TEST_CASE("a helical path hits a plane at the time its height says", "[screw]") {
  // Turning by π/2 about z while rising by 1: the point at radius 0.5 reaches
  // z = 0.3 at t = 0.3 wherever it is on its circle.
  const ScrewMotion motion(Pose{}, pose(Vec3(0, 0, 1), std::numbers::pi / 2, Vec3::UnitZ()));
  const std::array<Vec3, 3> face{Vec3(-2, -2, 0.3), Vec3(2, -2, 0.3), Vec3(0, 2, 0.3)};
  const CcdResult r = screw_vertex_face_ccd(motion, Vec3(0.5, 0, 0), face);
  REQUIRE(r.contact);
  CHECK(r.toi <= 0.3);
  CHECK(r.toi >= 0.3 - kScrewTimeSlack);
}

TEST_CASE("screw kernels honour the time limit", "[screw]") {
  // The body point (1, 0, 0) turning about z by π/2 reaches the plane
  // y = 0.5 at t = 1/3.
  const ScrewMotion motion(Pose{}, pose(Vec3::Zero(), std::numbers::pi / 2, Vec3::UnitZ()));
  const std::array<Vec3, 3> face{Vec3(0, 0.5, -1), Vec3(2, 0.5, -1), Vec3(1, 0.5, 1)};
  CcdSettings settings;
  settings.time_limit = 0.33;
  CHECK_FALSE(screw_vertex_face_ccd(motion, Vec3(1, 0, 0), face, settings).contact);
  settings.time_limit = 0.34;
  const CcdResult r = screw_vertex_face_ccd(motion, Vec3(1, 0, 0), face, settings);
  REQUIRE(r.contact);
  CHECK(r.toi <= 1.0 / 3);
  CHECK(r.toi >= 1.0 / 3 - kScrewTimeSlack);
  // The rotating edge meets the static edge at angle 60° at t = 2/3.
  const double a = std::numbers::pi / 3;
  const std::array<Vec3, 2> world_edge{Vec3(std::cos(a), std::sin(a), -1),
                                       Vec3(std::cos(a), std::sin(a), 1)};
  settings.time_limit = 0.66;
  CHECK_FALSE(
      screw_edge_edge_ccd(motion, {Vec3(0.5, 0, 0), Vec3(2, 0, 0)}, world_edge, settings).contact);
  settings.time_limit = 0.67;
  CHECK(
      screw_edge_edge_ccd(motion, {Vec3(0.5, 0, 0), Vec3(2, 0, 0)}, world_edge, settings).contact);
}

TEST_CASE("screw kernels fall back conservatively on budget and bad input", "[screw]") {
  const ScrewMotion motion(Pose{}, pose(Vec3::Zero(), std::numbers::pi / 2, Vec3::UnitZ()));
  const std::array<Vec3, 3> face{Vec3(0, 0.5, -1), Vec3(2, 0.5, -1), Vec3(1, 0.5, 1)};
  CcdSettings settings;
  settings.max_evaluations = 4;
  const CcdResult r = screw_vertex_face_ccd(motion, Vec3(1, 0, 0), face, settings);
  REQUIRE(r.contact);
  CHECK(r.budget_exhausted);
  CHECK(r.toi <= 1.0 / 3);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const CcdResult bad = screw_vertex_face_ccd(motion, Vec3(nan, 0, 0), face);
  CHECK(bad.contact);
  CHECK(bad.input_out_of_range);
}

}  // namespace
}  // namespace hb
