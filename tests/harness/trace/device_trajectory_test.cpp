// The device trajectory computes ticks block by block: any block equals the
// same ticks of the whole resampled trace, a generator's lazy samples equal
// its stored ones, and an hour-long trajectory costs no memory up front.
#include "harness/trace/device_trajectory.h"

#include <catch2/catch.hpp>
#include <cstdint>
#include <vector>

#include "hapticbench/input_error.h"
#include "harness/trace/generators.h"

namespace hb {
namespace {

bool same(const DeviceSample& a, const DeviceSample& b) {
  return a.tick == b.tick && a.t_ns == b.t_ns && a.pose.p == b.pose.p &&
         a.pose.q.coeffs() == b.pose.q.coeffs() && a.twist.v == b.twist.v && a.twist.w == b.twist.w;
}

// 250 Hz rows from t = 3.5 ms to about 0.9 s, turning and moving.
Trace sparse_trace(bool with_twist) {
  Trace trace;
  for (int i = 0; i < 225; ++i) {
    const double t = 0.0035 + 0.004 * i;
    TraceSample sample;
    sample.t_ns = 3'500'000 + 4'000'000 * int64_t{i};
    sample.pose.p = Vec3(0.1 * t, -0.05 * t * t, 0.02);
    sample.pose.q = quat_from_rotation_vector(Vec3(0.3 * t, 0.0, -0.7 * t));
    if (with_twist) sample.twist = Twist{Vec3(0.1, -0.1 * t, 0), Vec3(0.3, 0, -0.7)};
    trace.samples.push_back(sample);
  }
  return trace;
}

TEST_CASE("any block of ticks equals the same ticks of the whole trajectory") {
  for (bool with_twist : {false, true}) {
    INFO("with twist: " << with_twist);
    // 1200 ticks: held before the first row and after the last.
    const DeviceTrajectory trajectory = DeviceTrajectory::of_trace(sparse_trace(with_twist), 1200);
    REQUIRE(trajectory.ticks() == 1200);
    const std::vector<DeviceSample> whole = trajectory.all();
    // Blocks that start and end at, just inside and just outside the span.
    for (auto [first, count] : {std::pair<int64_t, int64_t>{0, 1},
                                {0, 5},
                                {3, 2},
                                {4, 1},
                                {5, 700},
                                {899, 3},
                                {900, 1},
                                {901, 299},
                                {1199, 1}}) {
      std::vector<DeviceSample> block(static_cast<std::size_t>(count));
      trajectory.fill(first, block);
      for (int64_t i = 0; i < count; ++i) {
        INFO("tick " << first + i);
        CHECK(same(block[static_cast<std::size_t>(i)], whole[static_cast<std::size_t>(first + i)]));
      }
    }
    std::size_t visited = 0;
    bool equal = true;
    trajectory.for_each(
        [&](const DeviceSample& sample) { equal = equal && same(sample, whole[visited++]); });
    CHECK(visited == whole.size());
    CHECK(equal);
    CHECK(same(trajectory.at(640), whole[640]));
    CHECK_THROWS_AS(trajectory.at(1200), std::out_of_range);
  }
}

TEST_CASE("a generator's samples computed on demand equal its stored trace, resampled") {
  for (const GeneratorEntry& entry : generator_table()) {
    INFO(entry.name);
    const GeneratorRequest request{2.0, 3, ParamSet("/trace/params")};
    const GeneratedTrace lazy = make_generated_trace(std::string(entry.name), request, "/g");
    const std::vector<DeviceSample> from_lazy = DeviceTrajectory(lazy.source, 0).all();
    const std::vector<DeviceSample> from_stored =
        DeviceTrajectory::of_trace(generate_trace(std::string(entry.name), request, "/g"), 0).all();
    REQUIRE(from_lazy.size() == 2001);
    REQUIRE(from_stored.size() == from_lazy.size());
    bool equal = true;
    for (std::size_t k = 0; k < from_lazy.size(); ++k)
      equal = equal && same(from_lazy[k], from_stored[k]);
    CHECK(equal);
  }
}

TEST_CASE("an hour-long generated trajectory is computed where it is read") {
  const GeneratorRequest request{3600.0, 1, ParamSet("/trace/params")};
  const GeneratedTrace trace = make_generated_trace("twist", request, "/g");
  const DeviceTrajectory trajectory(trace.source, 3'600'000);
  CHECK(trajectory.ticks() == 3'600'000);
  // The last minute, without the 59 before it: each tick is the generator's
  // sample at the same time (1 kHz rows: no interpolation in between).
  std::vector<DeviceSample> block(60'000);
  trajectory.fill(3'540'000, block);
  for (int64_t k : {int64_t{3'540'000}, int64_t{3'570'001}, int64_t{3'599'999}}) {
    const DeviceSample& sample = block[static_cast<std::size_t>(k - 3'540'000)];
    const TraceSample row = trace.source.at(k);
    CHECK(sample.t_ns == row.t_ns);
    CHECK(sample.pose.p == row.pose.p);
    CHECK(sample.pose.q.angularDistance(row.pose.q) < 1e-12);
    CHECK((sample.twist.v - row.twist->v).norm() < 1e-15);
  }
  // More ticks than a run may have are refused before anything is computed.
  CHECK_THROWS_AS(DeviceTrajectory(trace.source, 3'600'001), InputError);
}

}  // namespace
}  // namespace hb
