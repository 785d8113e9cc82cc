#include "hapticbench/proxy/device_output.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "tests/support/proxy_fixtures.h"

namespace hb {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST_CASE("a non-finite wrench is replaced by zero and flagged", "[device_output]") {
  const DeviceLimits limits{20, 1};
  for (const Wrench& raw :
       {Wrench{Vec3(1, kNaN, 0), Vec3::Zero()},
        Wrench{Vec3(1, 2, 3), Vec3(0, 0, std::numeric_limits<double>::infinity())}}) {
    uint32_t flags = 0;
    const Wrench shown = device_output(raw, limits, flags);
    CHECK(shown.force == Vec3::Zero());
    CHECK(shown.torque == Vec3::Zero());
    CHECK(flags == kFlagNonFiniteZeroed);
  }
}

TEST_CASE("saturation clips the magnitude and keeps the direction", "[device_output]") {
  const DeviceLimits limits{20, 1};
  uint32_t flags = 0;
  const Wrench raw{Vec3(30, -40, 0), Vec3(0, 2, 0)};  // |F| = 50 N, |τ| = 2 N·m
  const Wrench shown = device_output(raw, limits, flags);
  CHECK((shown.force - Vec3(12, -16, 0)).norm() < 1e-12);
  CHECK((shown.torque - Vec3(0, 1, 0)).norm() < 1e-12);
  CHECK(flags == (kFlagForceSaturated | kFlagTorqueSaturated));

  uint32_t quiet = 0;
  const Wrench within{Vec3(3, 4, 0), Vec3(0.1, 0, 0)};
  const Wrench same = device_output(within, limits, quiet);
  CHECK(same.force == within.force);
  CHECK(same.torque == within.torque);
  CHECK(quiet == 0);
}

TEST_CASE("a non-finite proxy state is reset to the device pose at rest", "[device_output]") {
  RigidBody body;
  body.centre_of_mass = Vec3(0, 0, 0.01);
  const Pose device{Vec3(0.1, 0.2, 0.3), Quat(Eigen::AngleAxisd(0.5, Vec3::UnitX()))};

  RigidBodyState healthy;
  healthy.v = Vec3(1, 0, 0);
  uint32_t flags = 0;
  CHECK_FALSE(reset_non_finite_proxy(body, device, healthy, flags));
  CHECK(flags == 0);
  CHECK(healthy.v.x() == 1);

  RigidBodyState broken;
  broken.w = Vec3(kNaN, 0, 0);
  CHECK(reset_non_finite_proxy(body, device, broken, flags));
  CHECK(flags == kFlagProxyReset);
  CHECK((tool_pose(body, broken).p - device.p).norm() < 1e-12);
  CHECK(broken.v == Vec3::Zero());
  CHECK(broken.w == Vec3::Zero());

  DeviceSample sample;
  CHECK(is_finite(sample));
  sample.twist.w.z() = kNaN;
  CHECK_FALSE(is_finite(sample));
}

}  // namespace
}  // namespace hb
