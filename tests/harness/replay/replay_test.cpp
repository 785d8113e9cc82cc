#include "harness/replay/replay.h"

#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <deque>
#include <map>
#include <vector>

#include "hapticbench/input_error.h"
#include "harness/replay/slow_loop_schedule.h"
#include "harness/trace/device_trajectory.h"

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
    const auto until = std::chrono::steady_clock::now() + std::chrono::nanoseconds(busy_step_ns_);
    while (std::chrono::steady_clock::now() < until) {
    }
    TickResult r;
    r.display.force.x() = static_cast<double>(installed_tick_);
    r.proxy = device.pose;
    return r;
  }
  SlowLoop* slow_loop() override { return with_slow_loop_ ? this : nullptr; }
  std::unique_ptr<Result> run_slow_update() override {
    started_after_.push_back(last_step_tick_);
    // Optionally busy for 0, 1.5 or 2.5 ms in turn: measured latencies differ.
    if (busy_) {
      const double ms[] = {0.0, 1.5, 2.5};
      const auto until =
          std::chrono::steady_clock::now() +
          std::chrono::microseconds(static_cast<int64_t>(1000 * ms[started_after_.size() % 3]));
      while (std::chrono::steady_clock::now() < until) {
      }
    }
    return std::make_unique<Snapshot>(last_step_tick_);
  }
  void install_slow_result(std::unique_ptr<Result> result) override {
    installed_tick_ = static_cast<Snapshot&>(*result).tick;
  }

  bool with_slow_loop_ = true;
  bool busy_ = false;
  int64_t busy_step_ns_ = 0;  ///< each step() takes at least this long
  int64_t last_step_tick_ = -1;
  int64_t installed_tick_ = -1;
  int resets_ = 0;
  std::vector<int64_t> started_after_;
};

// Keeps every record with its own copy of the device sample: the replay's
// record.device is valid only during on_tick.
struct Recorder : TickObserver {
  std::vector<TickRecord> records;
  std::deque<DeviceSample> devices;
  void on_tick(const TickRecord& record) override {
    devices.push_back(*record.device);
    records.push_back(record);
    records.back().device = &devices.back();
  }
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
    CHECK_FALSE(recorder.records[k].slow_started);
    CHECK(recorder.records[k].slow_data_age_ticks == -1);
  }
}

TEST_CASE("the timed window holds step(): a step busy for 200 µs is timed at 200 µs or more") {
  ProbeRenderer renderer;
  renderer.with_slow_loop_ = false;
  renderer.busy_step_ns_ = 200'000;
  Recorder recorder;
  const auto samples = ticks(20);
  replay(renderer, samples, ReplaySettings{}, recorder);
  for (const TickRecord& r : recorder.records) CHECK(r.step_ns >= 200'000);
}

TEST_CASE("a slow update started at tick k is installed before step k + L") {
  for (int64_t latency : {1, 3, 10}) {
    ProbeRenderer renderer;
    Recorder recorder;
    ReplaySettings settings;
    settings.slow_loop_timing = SlowLoopTiming::kFixed;
    settings.fixed_latency_ticks = latency;
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
  renderer.busy_ = true;
  Recorder recorder;
  const ReplaySettings settings;  // measured is the default
  REQUIRE(settings.slow_loop_timing == SlowLoopTiming::kMeasured);
  const auto samples = ticks(40);
  const SlowLoopSchedule schedule = replay(renderer, samples, settings, recorder);
  std::map<int64_t, int64_t> latency_by_start;
  for (const TickRecord& r : recorder.records) {
    if (!r.slow_started) continue;
    const int64_t expected = std::max<int64_t>(1, (r.slow_ns + kTickNs - 1) / kTickNs);
    CHECK(r.slow_latency_ticks == expected);
    latency_by_start[r.device->tick] = r.slow_latency_ticks;
  }
  // The busy updates take at least 1.5 ms: their results wait 2 ticks or more.
  int64_t longest = 0;
  for (const auto& [start, latency] : latency_by_start) longest = std::max(longest, latency);
  CHECK(longest >= 2);
  // Data age is never below the wall time of the update that produced it.
  for (const TickRecord& r : recorder.records) {
    if (r.slow_data_age_ticks < 0) continue;
    const int64_t start = r.device->tick - r.slow_data_age_ticks;
    REQUIRE(latency_by_start.count(start) == 1);
    CHECK(r.slow_data_age_ticks >= latency_by_start[start]);
  }
  // The schedule returned is the one followed.
  REQUIRE(schedule.updates.size() == latency_by_start.size());
  for (const SlowLoopUpdate& u : schedule.updates)
    CHECK(u.install_tick - u.start_tick == latency_by_start[u.start_tick]);
}

TEST_CASE("a recorded schedule replays the same ticks whatever the updates now take") {
  const auto samples = ticks(60);
  ProbeRenderer measured;
  measured.busy_ = true;
  Recorder first;
  const SlowLoopSchedule schedule = replay(measured, samples, ReplaySettings{}, first);

  ProbeRenderer quick;  // not busy: measured again, every latency would be 1
  Recorder second;
  ReplaySettings settings;
  settings.slow_loop_timing = SlowLoopTiming::kReplayed;
  settings.replayed_schedule = &schedule;
  // Through the file format and back.
  const SlowLoopSchedule parsed = parse_schedule_csv(schedule_csv(schedule), "schedule.csv");
  settings.replayed_schedule = &parsed;
  const SlowLoopSchedule followed = replay(quick, samples, settings, second);
  REQUIRE(first.records.size() == second.records.size());
  for (std::size_t k = 0; k < first.records.size(); ++k) {
    CHECK(first.records[k].result.display.force.x() == second.records[k].result.display.force.x());
    CHECK(first.records[k].slow_data_age_ticks == second.records[k].slow_data_age_ticks);
  }
  REQUIRE(followed.updates.size() == schedule.updates.size());
  for (std::size_t i = 0; i < followed.updates.size(); ++i)
    CHECK(followed.updates[i].install_tick == schedule.updates[i].install_tick);
}

TEST_CASE("a schedule that does not fit the run is refused") {
  const auto samples = ticks(30);
  ProbeRenderer renderer;
  Recorder recorder;
  ReplaySettings settings;
  settings.slow_loop_timing = SlowLoopTiming::kReplayed;
  SlowLoopSchedule short_schedule;
  short_schedule.updates = {{0, 2, 0}, {2, 4, 0}};
  settings.replayed_schedule = &short_schedule;
  CHECK_THROWS_AS(replay(renderer, samples, settings, recorder), ScheduleMismatch);
  SlowLoopSchedule shifted;
  shifted.updates = {{1, 3, 0}};
  settings.replayed_schedule = &shifted;
  CHECK_THROWS_AS(replay(renderer, samples, settings, recorder), ScheduleMismatch);
}

TEST_CASE("schedule files: malformed rows are refused with the line") {
  CHECK_THROWS_AS(parse_schedule_csv("start,install\n", "s.csv"), InputError);
  try {
    parse_schedule_csv("start_tick,install_tick,update_ns\n0,2,5\n2,2,5\n", "s.csv");
    FAIL("expected an InputError");
  } catch (const InputError& error) {
    CHECK(error.source() == "s.csv");
    CHECK(error.location() == "line 3");
  }
  CHECK_THROWS_AS(parse_schedule_csv("start_tick,install_tick,update_ns\n0,4,5\n2,6,5\n", "s"),
                  InputError);
  CHECK_THROWS_AS(parse_schedule_csv("start_tick,install_tick,update_ns\n0,x,5\n", "s"),
                  InputError);
}

TEST_CASE("an empty trace replays nothing") {
  ProbeRenderer renderer;
  Recorder recorder;
  replay(renderer, DeviceTrajectory{}, ReplaySettings{}, recorder);
  CHECK(recorder.records.empty());
  CHECK(renderer.resets_ == 0);
}

}  // namespace
}  // namespace hb

namespace hb {
namespace {

// Displays a constant force and keeps what step() was given.
class ConstantForceRenderer : public Renderer {
 public:
  explicit ConstantForceRenderer(const Vec3& force) : force_(force) {}
  void reset(const Pose& pose) override { reset_pose = pose; }
  TickResult step(const DeviceSample& device) override {
    seen.push_back(device);
    TickResult r;
    r.display.force = force_;
    r.proxy = device.pose;
    return r;
  }
  Pose reset_pose;
  std::vector<DeviceSample> seen;

 private:
  Vec3 force_;
};

// Samples of a curved, turning motion with twists, over several blocks.
std::vector<DeviceSample> curved_ticks(int64_t count) {
  std::vector<DeviceSample> samples(static_cast<std::size_t>(count));
  for (int64_t k = 0; k < count; ++k) {
    const double t = 1e-3 * static_cast<double>(k);
    DeviceSample& s = samples[static_cast<std::size_t>(k)];
    s.tick = k;
    s.t_ns = k * kTickNs;
    s.pose.p = Vec3(0.01 * std::sin(t), 0.02 * t, -0.003 * t * t);
    s.pose.q = Quat(Eigen::AngleAxisd(0.3 * t, Vec3(1, 2, 3).normalized()));
    s.twist.v = Vec3(0.01 * std::cos(t), 0.02, -0.006 * t);
  }
  return samples;
}

TEST_CASE("open loop: step() is given the trajectory's samples bit for bit, across blocks") {
  const std::vector<DeviceSample> samples = curved_ticks(3 * DeviceTrajectory::kBlockTicks + 7);
  ConstantForceRenderer renderer(Vec3(1, 2, 3));
  Recorder recorder;
  replay(renderer, samples, ReplaySettings{}, recorder);
  REQUIRE(renderer.seen.size() == samples.size());
  for (std::size_t k = 0; k < samples.size(); ++k) {
    INFO("tick " << k);
    CHECK(renderer.seen[k].pose.p == samples[k].pose.p);
    CHECK(renderer.seen[k].pose.q.coeffs() == samples[k].pose.q.coeffs());
    CHECK(renderer.seen[k].twist.v == samples[k].twist.v);
    CHECK(recorder.records[k].intent == nullptr);
    CHECK(recorder.records[k].device_actual == nullptr);
  }
}

TEST_CASE("closed loop: step() sees the device, which the held force and the hand move") {
  // A hand-held device pushed by a constant 0.5 N along x while the intent
  // stays put: it settles where the hand's spring balances the force,
  // 0.5 N / k_hand from the intent, and step() is given that position.
  ClosedLoopModel model;
  model.device.friction_n = 0;
  model.device.encoder_m = 0;
  const std::vector<DeviceSample> still = [] {
    std::vector<DeviceSample> samples(3000);
    for (std::size_t k = 0; k < samples.size(); ++k) {
      samples[k].tick = static_cast<int64_t>(k);
      samples[k].t_ns = static_cast<int64_t>(k) * kTickNs;
      samples[k].pose.p = Vec3(0.1, 0.2, 0.3);
    }
    return samples;
  }();
  ConstantForceRenderer renderer(Vec3(0.5, 0, 0));
  Recorder recorder;
  ReplaySettings settings;
  settings.closed_loop = &model;
  replay(renderer, still, settings, recorder);
  REQUIRE(renderer.seen.size() == still.size());
  CHECK(renderer.reset_pose.p == still[0].pose.p);  // the device starts at the intent
  CHECK(renderer.seen[0].pose.p == still[0].pose.p);
  const Vec3 settled = renderer.seen.back().pose.p - still.back().pose.p;
  CHECK(settled.x() == Approx(0.5 / model.hand.k_t).epsilon(1e-6));
  CHECK(settled.tail<2>().norm() < 1e-12);
  for (std::size_t k = 0; k < still.size(); k += 500) {
    REQUIRE(recorder.records[k].intent != nullptr);
    CHECK(recorder.records[k].device->pose.p == renderer.seen[k].pose.p);
  }
}

}  // namespace
}  // namespace hb
