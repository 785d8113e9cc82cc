// Percentiles: nearest rank on a stored sample, and the streaming version
// against exact ones on recorded step and update times, within its bound.
#include "harness/metrics/percentiles.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace hb {
namespace {

TEST_CASE("percentiles use the nearest rank") {
  std::vector<int64_t> values;
  for (int64_t i = 1000; i >= 1; --i) values.push_back(i);  // 1..1000, shuffled order
  const Percentiles p = percentiles_of(values);
  CHECK(p.p50 == 500);
  CHECK(p.p90 == 900);
  CHECK(p.p99 == 990);
  CHECK(p.p999 == 999);
  CHECK(p.max == 1000);
  CHECK(p.count == 1000);
  const Percentiles one = percentiles_of({7});
  CHECK(one.p50 == 7);
  CHECK(one.p999 == 7);
  CHECK(percentiles_of({}).count == 0);
}

// |streaming - exact| <= bound * exact for every percentile; count and max exact.
void check_within_bound(const std::vector<int64_t>& values, std::size_t capacity) {
  StreamingPercentiles streaming(capacity);
  for (int64_t value : values) streaming.add(value);
  const Percentiles exact = percentiles_of(values);
  const Percentiles got = streaming.result();
  CHECK(streaming.exact() == (values.size() <= capacity));
  CHECK(got.count == exact.count);
  CHECK(got.max == exact.max);
  const double bound = StreamingPercentiles::kRelativeErrorBound;
  for (auto [g, e] : {std::pair{got.p50, exact.p50}, std::pair{got.p90, exact.p90},
                      std::pair{got.p99, exact.p99}, std::pair{got.p999, exact.p999}}) {
    INFO("streaming " << g << " exact " << e);
    CHECK(std::abs(g - e) <= bound * e);
  }
}

// The update_ns column of a recorded schedule (start_tick,install_tick,update_ns).
std::vector<int64_t> recorded_update_ns(const std::string& schedule) {
  std::ifstream in(std::string(HAPTICBENCH_SOURCE_DIR) + "/reports/baselines/smoke/" + schedule);
  std::string line;
  std::getline(in, line);  // header
  std::vector<int64_t> values;
  while (std::getline(in, line)) values.push_back(std::stoll(line.substr(line.rfind(',') + 1)));
  return values;
}

TEST_CASE("streaming percentiles are exact up to their capacity, then within 0.05 %") {
  CHECK(StreamingPercentiles::kRelativeErrorBound == Approx(1.0 / 2048));
  // Recorded slow-update times of the smoke baselines (50 ns to ~100 µs).
  for (const char* schedule :
       {"box_press_box/schedule_god_object.csv", "slow_contact_loop/schedule_slow_measured.csv"}) {
    INFO(schedule);
    const std::vector<int64_t> values = recorded_update_ns(schedule);
    REQUIRE(values.size() >= 1000);
    check_within_bound(values, values.size());  // exact
    check_within_bound(values, 0);              // histogram from the first value
    check_within_bound(values, 100);            // switched part way
    StreamingPercentiles exact(values.size());
    for (int64_t value : values) exact.add(value);
    const Percentiles e = percentiles_of(values);
    CHECK(exact.result().p99 == e.p99);
    CHECK(exact.result().p50 == e.p50);
  }
  // A heavy tail over nine decades, as step times with rare stalls have.
  std::mt19937_64 rng(5);
  std::lognormal_distribution<double> distribution(7.0, 2.5);
  std::vector<int64_t> values;
  for (int i = 0; i < 200000; ++i) values.push_back(std::llround(distribution(rng)));
  check_within_bound(values, 0);
  // Small values have their own buckets: exact even in the histogram.
  StreamingPercentiles small(0);
  for (int64_t v = 0; v < 1000; ++v) small.add(v);
  CHECK(small.result().p50 == 499);
  CHECK(small.result().p99 == 989);
}

}  // namespace
}  // namespace hb
