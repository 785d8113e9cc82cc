// Frame enclosures of screw motions: positions, body coordinates and body
// directions of random points over random intervals of t hold the values
// the motion gives at sampled times inside.
#include "algorithms/ccd/frame_enclosure.h"

#include <catch2/catch.hpp>
#include <random>

namespace hb {
namespace {

bool holds(const IntervalVec3& box, const Vec3& p) {
  return box.x.contains(p.x()) && box.y.contains(p.y()) && box.z.contains(p.z());
}

TEST_CASE("frame enclosures hold the motion's positions and body coordinates",
          "[frame_enclosure]") {
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
      const Vec3 body_point = random_vec(scale), world_point = random_vec(scale);
      const Vec3 direction = random_vec(1.0);
      const IntervalVec3 position = frame.position(body_point);
      const IntervalVec3 body = frame.body_coordinates(world_point);
      const IntervalVec3 body_direction = frame.body_direction(direction);
      for (int s = 0; s <= 10; ++s) {
        const double t = t0 + (t1 - t0) * s / 10.0;
        const Mat3 rotation = motion.rotation_at(t);
        const Vec3 origin = motion.point_at(Vec3::Zero(), t);
        // The double evaluations carry rounding of about 1e-16 relative: an
        // instant's enclosure is that narrow too, so compare with a margin.
        const double margin = 1e-13 * (scale + 1);
        auto near = [&](const IntervalVec3& box, const Vec3& p) {
          IntervalVec3 wide = box;
          for (Interval* c : {&wide.x, &wide.y, &wide.z})
            *c = Interval(c->lo - margin, c->hi + margin);
          return holds(wide, p);
        };
        INFO("motion " << m << " t " << t);
        REQUIRE(near(position, motion.point_at(body_point, t)));
        REQUIRE(near(body, rotation.transpose() * (world_point - origin)));
        REQUIRE(near(body_direction, rotation.transpose() * direction));
        if (t1 - t0 > 1e-6) {  // wide enough for the rounding not to matter
          REQUIRE(holds(position, motion.point_at(body_point, t)));
          REQUIRE(holds(body, rotation.transpose() * (world_point - origin)));
        }
      }
    }
  }
}

}  // namespace
}  // namespace hb
