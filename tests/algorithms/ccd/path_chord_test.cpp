// Chords of point paths over intervals of a screw motion: every position
// the motion gives at sampled times inside the interval lies within the
// stray of the chord, inside its box and its side interval, and not within
// reach before first_within says; the stray of a turning point is the
// arc's own sagitta to first order, and a straight approach enters a
// sphere at the time its distance says.
#include "algorithms/ccd/path_chord.h"

#include <catch2/catch.hpp>
#include <random>

namespace hb {
namespace {

using ccd_detail::FrameChord;
using ccd_detail::FrameEnclosures;
using ccd_detail::PathChord;

/// Distance (m) from p to the segment [a, b].
double segment_distance(const Vec3& a, const Vec3& b, const Vec3& p) {
  const Vec3 along = b - a;
  const double length2 = along.squaredNorm();
  const double s = length2 > 0 ? std::clamp((p - a).dot(along) / length2, 0.0, 1.0) : 0.0;
  return (a + s * along - p).norm();
}

bool box_holds(const IntervalVec3& box, const Vec3& p) {
  return box.x.contains(p.x()) && box.y.contains(p.y()) && box.z.contains(p.z());
}

/// Checks a chord against sampled positions position(t), t in [t0, t1].
template <class Position>
void check_path(const PathChord& path, double t0, double t1, const Position& position,
                const Vec3& centre, double reach, const Vec3& normal) {
  const double first = path.first_within(centre, reach);
  const IntervalVec3 box = path.box();
  const Interval side = path.side(normal, centre);
  for (int s = 0; s <= 40; ++s) {
    const double fraction = s / 40.0;
    const Vec3 p = position(t0 + (t1 - t0) * fraction);
    INFO("fraction " << fraction << " stray " << path.stray);
    REQUIRE(segment_distance(path.start, path.end, p) <= path.stray);
    REQUIRE(box_holds(box, p));
    REQUIRE(side.contains(normal.dot(p - centre)));
    if (fraction < first) REQUIRE((p - centre).norm() > reach);
  }
}

TEST_CASE("chords hold the paths of points, vectors and body coordinates", "[path_chord]") {
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), fraction(0.0, 1.0);
  auto random_vec = [&](double scale) {
    return Vec3(scale * unit(rng), scale * unit(rng), scale * unit(rng));
  };
  int entered = 0;
  for (int m = 0; m < 150; ++m) {
    const double scale = m % 3 == 0 ? 0.05 : (m % 3 == 1 ? 1.0 : 30.0);
    // Turns up to π (the shorter way of a random pair of orientations).
    const Pose start{random_vec(scale), quat_from_rotation_vector(random_vec(2.0))};
    const Pose end{random_vec(scale), quat_from_rotation_vector(random_vec(2.0))};
    const ScrewMotion motion(start, end);
    const FrameEnclosures frames(motion);
    for (int k = 0; k < 12; ++k) {
      double t0 = fraction(rng), t1 = fraction(rng);
      if (t0 > t1) std::swap(t0, t1);
      if (k == 0) t0 = 0, t1 = 1;  // the whole motion
      if (k == 1) t1 = t0;         // an instant
      const FrameChord frame = ccd_detail::frame_chord(frames, motion, t0, t1);
      const Vec3 body_point = random_vec(scale), world_point = random_vec(scale);
      const Vec3 vector = random_vec(scale), normal = random_vec(1.0).normalized();
      // A sphere the point's path passes near: about its position halfway.
      const Vec3 centre = motion.point_at(body_point, 0.5 * (t0 + t1)) + random_vec(0.3 * scale);
      const double reach = 0.2 * scale * fraction(rng);
      INFO("motion " << m << " interval [" << t0 << ", " << t1 << "]");
      const PathChord point = frame.world_path(body_point);
      check_path(
          point, t0, t1, [&](double t) { return motion.point_at(body_point, t); }, centre, reach,
          normal);
      check_path(
          frame.world_vector(vector), t0, t1,
          [&](double t) { return Vec3(motion.rotation_at(t) * vector); }, centre, reach, normal);
      check_path(
          frame.body_path(world_point), t0, t1,
          [&](double t) {
            return Vec3(motion.rotation_at(t).transpose() *
                        (world_point - motion.point_at(Vec3::Zero(), t)));
          },
          centre, reach, normal);
      entered += point.first_within(centre, reach) <= 1;
    }
  }
  CHECK(entered > 100);  // the reach test was exercised where it admits
}

TEST_CASE("a turning point strays from its chord by the arc's sagitta", "[path_chord]") {
  // A point at ρ from the axis turning by φ: its arc lies ρ (1 − cos(φ/2))
  // ≈ ρ φ² / 8 from the chord at its middle; the stray bounds that and is
  // no more than a few percent above it.
  const double rho = 0.03;
  for (const double angle : {0.05, 0.4, 1.0}) {
    const ScrewMotion motion(Pose{Vec3::Zero(), Quat::Identity()},
                             Pose{Vec3::Zero(), Quat(Eigen::AngleAxisd(angle, Vec3::UnitZ()))});
    const FrameEnclosures frames(motion);
    const PathChord path =
        ccd_detail::frame_chord(frames, motion, 0.0, 1.0).world_path(Vec3(rho, 0, 0));
    const double sagitta = rho * (1 - std::cos(angle / 2));
    INFO("angle " << angle);
    CHECK(path.stray >= sagitta);
    CHECK(path.stray <= 1.03 * sagitta);
  }
}

TEST_CASE("a straight approach enters a sphere when its distance says", "[path_chord]") {
  // A point translating 10 cm along x toward a 1 cm sphere 6 cm ahead:
  // within reach from 5 cm on, fraction 0.5; moving away, never.
  const ScrewMotion motion(Pose{Vec3::Zero(), Quat::Identity()},
                           Pose{Vec3(0.1, 0, 0), Quat::Identity()});
  const FrameEnclosures frames(motion);
  const FrameChord whole = ccd_detail::frame_chord(frames, motion, 0.0, 1.0);
  const PathChord path = whole.world_path(Vec3::Zero());
  CHECK(path.first_within(Vec3(0.06, 0, 0), 0.01) == Approx(0.5).margin(1e-9));
  CHECK(path.first_within(Vec3(0.06, 0, 0), 0.01) <= 0.5);
  CHECK(path.first_within(Vec3(-0.05, 0, 0), 0.01) > 1);
  CHECK(path.first_within(Vec3(0.05, 0.02, 0), 0.01) > 1);   // passes 2 cm beside it
  CHECK(path.first_within(Vec3(0.0, 0.005, 0), 0.01) == 0);  // within at the start
}

}  // namespace
}  // namespace hb
