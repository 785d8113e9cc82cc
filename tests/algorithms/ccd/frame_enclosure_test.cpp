// Frame enclosures of screw motions: over random intervals of t (instants
// among them), the origin T(t) and every entry of R(t) lie within the
// enclosure's midpoint ± radius at sampled times inside.
#include "algorithms/ccd/frame_enclosure.h"

#include <catch2/catch.hpp>
#include <random>

namespace hb {
namespace {

bool within(const ccd_detail::MidRad& m, double x, double margin) {
  return std::abs(x - m.mid) <= m.rad + margin;
}

TEST_CASE("frame enclosures hold the motion's origin and rotation", "[frame_enclosure]") {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), fraction(0.0, 1.0);
  auto random_vec = [&](double scale) {
    return Vec3(scale * unit(rng), scale * unit(rng), scale * unit(rng));
  };
  for (int m = 0; m < 200; ++m) {
    const double scale = m % 3 == 0 ? 0.05 : (m % 3 == 1 ? 1.0 : 30.0);
    const Pose start{random_vec(scale), quat_from_rotation_vector(random_vec(2.0))};
    const Pose end{random_vec(scale), quat_from_rotation_vector(random_vec(2.0))};
    const ScrewMotion motion(start, end);
    const ccd_detail::FrameEnclosures frames(motion);
    for (int k = 0; k < 20; ++k) {
      double t0 = fraction(rng), t1 = fraction(rng);
      if (t0 > t1) std::swap(t0, t1);
      if (k % 4 == 0) t1 = t0;  // an instant
      const ccd_detail::FrameEnclosure frame = frames.over(Interval(t0, t1));
      for (int s = 0; s <= 10; ++s) {
        const double t = t0 + (t1 - t0) * s / 10.0;
        const Mat3 rotation = motion.rotation_at(t);
        const Vec3 origin = motion.point_at(Vec3::Zero(), t);
        // The double evaluations carry rounding of about 1e-16 relative: an
        // instant's enclosure is that narrow too, so compare with a margin,
        // and without one where the interval is wide.
        const double margin = t1 - t0 > 1e-6 ? 0.0 : 1e-13 * (scale + 1);
        INFO("motion " << m << " t " << t);
        for (int i = 0; i < 3; ++i) {
          REQUIRE(within(frame.origin[i], origin[i], margin));
          for (int j = 0; j < 3; ++j)
            REQUIRE(within(frame.rotation[i][j], rotation(i, j), t1 - t0 > 1e-6 ? 0.0 : 1e-13));
        }
      }
    }
  }
}

TEST_CASE("an instant's enclosure is as narrow as rounding", "[frame_enclosure]") {
  const ScrewMotion motion(Pose{Vec3(0.1, 0.2, 0.3), Quat::Identity()},
                           Pose{Vec3(0.2, 0.1, 0.3), Quat(Eigen::AngleAxisd(0.4, Vec3::UnitZ()))});
  const ccd_detail::FrameEnclosure frame =
      ccd_detail::FrameEnclosures(motion).over(Interval(0.375));
  for (int i = 0; i < 3; ++i) {
    CHECK(frame.origin[i].rad < 1e-14);
    for (int j = 0; j < 3; ++j) CHECK(frame.rotation[i][j].rad < 1e-14);
  }
}

}  // namespace
}  // namespace hb
