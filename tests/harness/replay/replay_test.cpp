#include "harness/replay/replay.h"

#include <catch2/catch.hpp>
#include <vector>

namespace hb {
namespace {

std::vector<DeviceSample> ticks(int64_t count) {
  std::vector<DeviceSample> samples(static_cast<std::size_t>(count));
  for (int64_t k = 0; k < count; ++k) {
    samples[k].tick = k;
    samples[k].t_ns = k * kTickNs;
    samples[k].pose.p = Vec3(0.001 * static_cast<double>(k), 0, 0);
  }
  return samples;
}

// A renderer whose slow update snapshots the tick it ran after, and whose
// step reports (in the force's x) the tick of the data installed.
class ProbeRenderer : public Renderer, public SlowLoop {
 public:
  struct Snapshot : SlowLoop::Result {
    int64_t tick;
    explicit Snapshot(int64_t t) : tick(t) {}
  };
  void reset(const Pose&) override {
    last_step_tick_ = -1;
    installed_tick_ = -1;
    resets_++;
  }
  TickResult step(const DeviceSample& device) override {
    last_step_tick_ = device.tick;
    TickResult r;
    r.display.force.x() = static_cast<double>(installed_tick_);
    r.proxy = device.pose;
    return r;
  }
  SlowLoop* slow_loop() override { return with_slow_loop_ ? this : nullptr; }
  std::unique_ptr<Result> run_slow_update() override {
    started_after_.push_back(last_step_tick_);
    return std::make_unique<Snapshot>(last_step_tick_);
  }
  void install_slow_result(std::unique_ptr<Result> result) override {
    installed_tick_ = static_cast<Snapshot&>(*result).tick;
  }

  bool with_slow_loop_ = true;
  int64_t last_step_tick_ = -1;
  int64_t installed_tick_ = -1;
  int resets_ = 0;
  std::vector<int64_t> started_after_;
};

struct Recorder : TickObserver {
  std::vector<TickRecord> records;
  void on_tick(const TickRecord& record) override { records.push_back(record); }
};

TEST_CASE("every sample is replayed once, in order, after one reset") {
  ProbeRenderer renderer;
  renderer.with_slow_loop_ = false;
  Recorder recorder;
  const auto samples = ticks(50);
  replay(renderer, samples, ReplaySettings{}, recorder);
  REQUIRE(renderer.resets_ == 1);
  REQUIRE(recorder.records.size() == 50);
  for (std::size_t k = 0; k < 50; ++k) {
    CHECK(recorder.records[k].device->tick == static_cast<int64_t>(k));
    CHECK(recorder.records[k].step_ns >= 0);
    CHECK_FALSE(recorder.records[k].slow_started);
    CHECK(recorder.records[k].slow_data_age_ticks == -1);
  }
}

TEST_CASE("a slow update started at tick k is installed before step k + L") {
  for (int64_t latency : {1, 3, 10}) {
    ProbeRenderer renderer;
    Recorder recorder;
    ReplaySettings settings;
    settings.slow_loop_latency_ticks = latency;
    const auto samples = ticks(40);
    replay(renderer, samples, settings, recorder);

    // Updates start after steps 0, L, 2L, ...: one in flight at a time.
    for (std::size_t i = 0; i < renderer.started_after_.size(); ++i)
      CHECK(renderer.started_after_[i] == static_cast<int64_t>(i) * latency);

    for (const TickRecord& r : recorder.records) {
      const int64_t k = r.device->tick;
      const int64_t seen = static_cast<int64_t>(r.result.display.force.x());
      if (k < latency) {
        CHECK(seen == -1);  // nothing installed yet
        CHECK(r.slow_data_age_ticks == -1);
      } else {
        // The newest update whose installation tick k + L has come.
        const int64_t expected = ((k - latency) / latency) * latency;
        CHECK(seen == expected);
        CHECK(r.slow_data_age_ticks == k - expected);
        CHECK(r.slow_data_age_ticks >= latency);
        CHECK(r.slow_data_age_ticks < 2 * latency);
      }
      CHECK(r.slow_started == (k % latency == 0));
      if (r.slow_started) CHECK(r.slow_latency_ticks == latency);
    }
  }
}

TEST_CASE("measured latency is the update's wall time in whole ticks, at least one") {
  ProbeRenderer renderer;
  Recorder recorder;
  ReplaySettings settings;
  settings.slow_loop_latency_ticks = std::nullopt;
  const auto samples = ticks(20);
  replay(renderer, samples, settings, recorder);
  for (const TickRecord& r : recorder.records) {
    if (!r.slow_started) continue;
    const int64_t expected = std::max<int64_t>(1, (r.slow_ns + kTickNs - 1) / kTickNs);
    CHECK(r.slow_latency_ticks == expected);
  }
}

TEST_CASE("an empty trace replays nothing") {
  ProbeRenderer renderer;
  Recorder recorder;
  replay(renderer, {}, ReplaySettings{}, recorder);
  CHECK(recorder.records.empty());
  CHECK(renderer.resets_ == 0);
}

}  // namespace
}  // namespace hb
