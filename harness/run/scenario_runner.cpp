// Running a prepared scenario: timing passes, then the evaluation pass
// with ground truth, metrics and the ticks log, per algorithm.
#include "harness/run/scenario_runner.h"

#include <sys/statvfs.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string_view>

#include "algorithms/registry.h"
#include "hapticbench/input_error.h"
#include "hapticbench/shapes.h"
#include "harness/metrics/budgets.h"
#include "harness/metrics/spill_buffer.h"
#include "harness/output/ticks_csv.h"
#include "harness/process/activity_report.h"
#include "harness/reference/analytic_reference.h"
#include "harness/reference/coupling_damper.h"
#include "harness/reference/tunnelling.h"
#include "harness/replay/noise_floor.h"

namespace hb {

namespace {

// Why a buffered write to `path` failed: the errno of the failed call when
// it set one, else ENOSPC when the filesystem has no block left for us (an
// earlier write failed and the stream stayed bad), else EIO.
int write_failure_cause(const std::filesystem::path& path) {
  if (errno != 0) return errno;
  struct statvfs space {};
  if (::statvfs(path.parent_path().c_str(), &space) == 0 && space.f_bavail == 0) return ENOSPC;
  return EIO;
}

}  // namespace

namespace {

// Hash of what a replay computed at each tick (display and proxy), to
// check that the timing pass and the evaluation pass computed the same.
void add_result(ContentHash& hash, const TickResult& result) {
  const double values[] = {
      result.display.force.x(),  result.display.force.y(),  result.display.force.z(),
      result.display.torque.x(), result.display.torque.y(), result.display.torque.z(),
      result.proxy.p.x(),        result.proxy.p.y(),        result.proxy.p.z(),
      result.proxy.q.w(),        result.proxy.q.x(),        result.proxy.q.y(),
      result.proxy.q.z()};
  hash.add(std::string_view(reinterpret_cast<const char*>(values), sizeof values));
}

// First pass: step() with nothing else between the ticks, so the ground
// truth of the second pass cannot evict the algorithm's data from the
// caches and inflate its measured times. The first pass keeps each tick's
// times for the evaluation pass (spilled to a temporary file when long);
// repetitions keep only their percentiles.
class TimingObserver : public TickObserver {
 public:
  TimingObserver(bool keep_times, ProgressDisplay* progress)
      : keep_times_(keep_times), progress_(progress) {}
  void on_tick(const TickRecord& record) override {
    if (keep_times_) times.push_back({record.step_ns, record.slow_ns});
    step_ns.add(record.step_ns);
    add_result(results, record.result);
    if (progress_) progress_->advance(record.device->tick + 1);
  }
  /// (step, slow update) wall time per tick, ns; only with keep_times.
  SpillBuffer<std::array<int64_t, 2>> times;
  StreamingPercentiles step_ns;
  ContentHash results;
  SlowLoopSchedule schedule;  ///< what the pass followed
  NoiseFloor noise;           ///< how quiet the machine was during the pass

 private:
  bool keep_times_;
  ProgressDisplay* progress_;
};

// Ground truth and logging for one algorithm's replay. With timings from a
// timing pass, the tick records take their wall-clock times from it.
class EvaluatingObserver : public TickObserver {
 public:
  EvaluatingObserver(GroundTruth& truth, const TriangleMesh& tool_mesh, MetricsSettings settings,
                     const TimingObserver* timing, std::ostream& ticks_out,
                     ProgressDisplay* progress)
      : truth_(truth), metrics_(settings), ticks_(ticks_out), progress_(progress) {
    if (timing) timing_.emplace(timing->times);
    if (truth_.force) force_reference_.emplace(*truth_.force);
    if (truth_.force_follows_device)
      follower_.emplace(*truth_.force_follows_device, "this run's device path (closed loop)");
    // Tunnelling by the exact box where there is one, else by the oracle,
    // for the tool's origin and extreme vertices.
    if (truth_.analytic) {
      const AnalyticScene& scene = *truth_.analytic;
      tunnelling_.emplace(tunnelling_points(tool_mesh),
                          [&] { return std::make_unique<BoxTunnellingDetector>(scene); });
      ideal_.emplace(*truth_.analytic);
      damper_.emplace(truth_.analytic->coupling, static_cast<double>(kTickNs) * 1e-9);
    } else if (truth_.oracle && truth_.oracle->primary_oracle()) {
      const Oracle& oracle = *truth_.oracle->primary_oracle();
      tunnelling_.emplace(tunnelling_points(tool_mesh),
                          [&] { return std::make_unique<OracleTunnellingDetector>(oracle); });
    }
  }

  void on_tick(const TickRecord& measured) override {
    TickRecord record_with_timing;
    const TickRecord* record_ptr = &measured;
    if (timing_) {
      std::array<int64_t, 2> times{};
      timing_->next(times);
      record_with_timing = measured;
      record_with_timing.result.contacts = measured.result.contacts;
      record_with_timing.step_ns = times[0];
      record_with_timing.slow_ns = times[1];
      record_ptr = &record_with_timing;
    }
    const TickRecord& record = *record_ptr;
    add_result(results_, record.result);
    TickEvaluation evaluation;
    const bool proxy_finite = is_finite(record.result.proxy);
    if (truth_.analytic) {
      IdealRendering ideal = ideal_->update(record.device->pose);
      // The whole coupling, as every algorithm displays it: its damper too.
      damper_->apply(record.device->tick, record.device->twist, ideal);
      evaluation.ideal_display = ideal.display;
      evaluation.reference_contact = ideal.in_contact;
      if (proxy_finite)
        evaluation.penetration_m = exact_penetration_depth(*truth_.analytic, record.result.proxy);
    }
    if (follower_) {
      if (const std::optional<IdealRendering> ideal = follower_->follow(*record.device)) {
        evaluation.ideal_display = ideal->display;
        evaluation.reference_contact = ideal->in_contact;
      }
    } else if (force_reference_) {
      const ForceReferenceTick& tick = force_reference_->at(record.device->tick);
      if (tick.evaluated) {
        evaluation.ideal_display = tick.display;
        evaluation.reference_contact = tick.in_contact;
      }
    }
    if (tunnelling_) evaluation.tunnelled = tunnelling_->update(record.result.proxy);
    if (record.device_actual) {
      if (truth_.analytic)
        evaluation.device_penetration_m =
            exact_penetration_depth(*truth_.analytic, *record.device_actual);
      else if (truth_.oracle)
        evaluation.device_penetration_m = truth_.oracle->primary_penetration(*record.device_actual);
    }
    if (truth_.oracle) {
      evaluation.oracle =
          truth_.oracle->evaluate(record.device->tick, record.result.proxy, record.result.contacts);
      // Without a closed form, the penetration is the oracle's: the
      // primary backend's, on the ticks it evaluates.
      if (!evaluation.penetration_m && !evaluation.oracle->broad_phase_skipped) {
        if (const PenetrationResult* first = evaluation.oracle->first_penetration())
          evaluation.penetration_m = first->max_depth_m;
      } else if (!evaluation.penetration_m && proxy_finite &&
                 truth_.oracle->measures_penetration()) {
        evaluation.penetration_m = 0.0;  // bounds clear of the scene: no penetration
      }
      // Without inside/outside, crossing the surface is what penetration is.
      if (evaluation.oracle->crossing)
        evaluation.crossing = evaluation.oracle->crossing;
      else if (evaluation.oracle->broad_phase_skipped && proxy_finite &&
               !truth_.oracle->measures_penetration())
        evaluation.crossing = false;  // bounds clear of the scene: no crossing
    }
    metrics_.add(record, evaluation);
    ticks_.add(record, evaluation);
    if (progress_) progress_->advance(record.device->tick + 1);
  }

  RunMetrics metrics() const { return metrics_.finish(); }
  /// The mesh reference that followed this run's device (closed loop).
  std::optional<ForceReferenceDescription> followed_reference() const {
    return follower_ ? std::optional(follower_->description()) : std::nullopt;
  }
  TicksCsvWriter& ticks() { return ticks_; }
  const ContentHash& results() const { return results_; }

 private:
  GroundTruth& truth_;
  std::optional<ToolTunnelling> tunnelling_;                    ///< none without ground truth
  std::optional<FrictionalContactReference> ideal_;             ///< with the analytic scene
  std::optional<IdealCouplingDamper> damper_;                   ///< ideal_'s coupling damper
  std::optional<ForceReferenceTrack::Reader> force_reference_;  ///< the mesh force reference
  std::optional<ForceReferenceFollower> follower_;  ///< closed loop: it, following the device
  MetricsAccumulator metrics_;
  std::optional<SpillBuffer<std::array<int64_t, 2>>::Reader> timing_;
  ContentHash results_;
  TicksCsvWriter ticks_;
  ProgressDisplay* progress_;
};

std::string penetration_source(const GroundTruth& truth) {
  if (truth.analytic) return "analytic";
  if (!truth.oracle || !truth.oracle->measures_penetration()) return "";
  return std::string(truth.oracle->primary_name());
}

}  // namespace

namespace {

// A run in which no algorithm reported a contact and the reference found
// no penetration measured free space only: the trace may miss the scene.
std::optional<std::string> never_reached_warning(const ScenarioRun& report) {
  if (report.runs.empty()) return std::nullopt;
  for (const AlgorithmRun& run : report.runs) {
    if (run.metrics.contacts.contact_ticks > 0) return std::nullopt;
    const std::optional<int64_t>& penetrating = run.metrics.accuracy.penetration_ticks;
    if (penetrating && *penetrating > 0) return std::nullopt;
  }
  return "no algorithm reported a contact on any tick and the reference found no penetration: "
         "the trace may never reach the scene, so the run measured free space only";
}

// The operator's intent in closed loop (the trace), every 10th tick, for
// the report's device-against-intent figure: "t_s,px,py,pz" (s, m, world).
std::string intent_csv(const DeviceTrajectory& trajectory) {
  constexpr int64_t kEvery = 10;
  std::ostringstream out;
  out.precision(9);
  out << "t_s,px,py,pz\n";
  for (int64_t tick = 0; tick < trajectory.ticks(); tick += kEvery) {
    const DeviceSample sample = trajectory.at(tick);
    out << static_cast<double>(sample.t_ns) * 1e-9 << "," << sample.pose.p.x() << ","
        << sample.pose.p.y() << "," << sample.pose.p.z() << "\n";
  }
  return out.str();
}

// What summary.json says of the scenario and its ground truth, before any run.
ScenarioRun scenario_report(const Scenario& scenario, const GroundTruth& truth) {
  ScenarioRun report;
  report.scenario_name = scenario.name;
  report.scenario_path = scenario.path;
  report.scenario_hash = scenario.content_hash;
  report.trace_description = scenario.trace_description;
  report.scenario_description = scenario.description;
  for (const SceneObject& object : scenario.context.scene) {
    Eigen::AlignedBox3d bounds;
    for (const Vec3& vertex : object.mesh.vertices)
      bounds.extend(object.pose.transform_point(vertex));
    report.scene_outline.push_back({object.name,
                                    object.shape ? shape_type_name(object.shape->type) : "mesh",
                                    bounds.min(), bounds.max(), object.distance_only});
  }
  const Tool& tool = scenario.context.tool;
  const Eigen::AlignedBox3d tool_bounds = tool.mesh.bounds();
  report.tool_outline =
      ObjectOutline{"tool", tool.shape ? shape_type_name(tool.shape->type) : "mesh",
                    tool_bounds.min(), tool_bounds.max(), false};
  for (const SceneObject& object : scenario.context.scene)
    report.scene_friction.push_back(object.friction);
  report.tags = scenario.tags;
  report.warnings = scenario.warnings;
  report.coupling = scenario.context.coupling;
  report.context = current_run_context();
  if (truth.oracle) {
    OracleDescription& d = report.oracle.emplace();
    d.backends = scenario.reference.oracle;
    d.exact_every = scenario.reference.exact_every;
    d.tool_samples = static_cast<int64_t>(truth.oracle->sample_count());
    d.sample_spacing_m = truth.oracle->sample_spacing_m();
    d.distance_only_objects = truth.oracle->distance_only_objects();
    d.build_seconds = truth.oracle_build_seconds;
  }
  if (truth.force) report.force_reference = truth.force->description;
  return report;
}

// The scenario's force_reference in closed loop: the runs' followed
// references together (their counts and times summed, their extremes kept).
void add_followed_reference(const ForceReferenceDescription& run, ScenarioRun& report) {
  if (!report.force_reference) {
    report.force_reference = run;
    report.force_reference->method =
        "rigid proxy along each run's own device path (closed loop), the runs together; "
        "each run's own: runs[].force_reference";
    return;
  }
  ForceReferenceDescription& all = *report.force_reference;
  all.evaluated_ticks += run.evaluated_ticks;
  all.not_started_ticks += run.not_started_ticks;
  all.unconverged_ticks += run.unconverged_ticks;
  all.infeasible_ticks += run.infeasible_ticks;
  all.sticking_ticks += run.sticking_ticks;
  all.max_iterations = std::max(all.max_iterations, run.max_iterations);
  all.kkt_residual_max = std::max(all.kkt_residual_max, run.kkt_residual_max);
  all.seconds += run.seconds;
}

MetricsSettings metrics_settings_for(const Scenario& scenario) {
  MetricsSettings settings;
  const Tool& tool = scenario.context.tool;
  const double tool_radius = tool.mesh.radius_about(tool.mass.centre_of_mass);
  settings.divergence_distance_m = std::max(0.1, 5.0 * tool_radius);
  settings.expected_ticks = scenario.trajectory.ticks();
  settings.coupling_k_t = scenario.context.coupling.k_t;
  settings.coupling_k_r = scenario.context.coupling.k_r;
  if (scenario.closed_loop) {
    settings.closed_loop = true;
    // An encoder's quantization alone dithers by about its resolution.
    settings.limit_cycle_floor_m =
        std::max(LimitCycleDetector::kDefaultFloorM, 2 * scenario.closed_loop->device.encoder_m);
    settings.encoder_m = scenario.closed_loop->device.encoder_m;
  }
  return settings;
}

// Timing passes: step() with nothing else between the ticks. The first
// one's times and schedule are the run's; repetitions give the spread.
std::vector<std::unique_ptr<TimingObserver>> run_timing_passes(PreparedAlgorithm& algorithm,
                                                               const Scenario& scenario, int repeat,
                                                               ProgressDisplay* progress) {
  ReplaySettings timing_settings = algorithm.replay;
  if (algorithm.replayed_schedule) {
    timing_settings.slow_loop_timing = SlowLoopTiming::kReplayed;
    timing_settings.replayed_schedule = algorithm.replayed_schedule.get();
  }
  std::vector<std::unique_ptr<TimingObserver>> passes;
  for (int i = 0; i < std::max(1, repeat); ++i)
    passes.push_back(std::make_unique<TimingObserver>(i == 0, progress));
  for (std::size_t i = 0; i < passes.size(); ++i) {
    TimingObserver& pass = *passes[i];
    if (progress)
      progress->phase(passes.size() == 1 ? std::string("timing pass")
                                         : "timing pass " + std::to_string(i + 1) + "/" +
                                               std::to_string(passes.size()),
                      scenario.trajectory.ticks(), true);
    const NoiseFloorProbe probe;
    try {
      pass.schedule = replay(*algorithm.renderer, scenario.trajectory, timing_settings, pass);
    } catch (const ScheduleMismatch& mismatch) {
      throw InputError(algorithm.schedule_source, "",
                       std::string("the schedule does not fit ") + algorithm.spec->label + " of " +
                           scenario.path + ": " + mismatch.what());
    }
    pass.noise = probe.finish();
  }
  return passes;
}

// The spread of the timing passes' step-time percentiles; none with one pass.
std::optional<TimingRepeats> timing_repeats(
    const std::vector<std::unique_ptr<TimingObserver>>& passes) {
  if (passes.size() < 2) return std::nullopt;
  std::vector<double> p50, p99;
  for (const std::unique_ptr<TimingObserver>& pass : passes) {
    const Percentiles p = pass->step_ns.result();
    p50.push_back(p.p50);
    p99.push_back(p.p99);
  }
  return TimingRepeats{static_cast<int>(passes.size()), spread_of(p50), spread_of(p99)};
}

}  // namespace

ScenarioOutcome run_prepared(PreparedScenario& prepared, const RunOptions& options) {
  const Scenario& scenario = *prepared.scenario;
  GroundTruth& truth = prepared.truth;
  ScenarioOutcome outcome;
  outcome.report = scenario_report(scenario, truth);
  if (scenario.closed_loop) outcome.intent_csv = intent_csv(scenario.trajectory);
  const MetricsSettings metrics_settings = metrics_settings_for(scenario);
  outcome.scratch = std::make_unique<ScratchFolder>("hapticbench-run");

  ProgressDisplay* const progress = options.progress;
  for (PreparedAlgorithm& algorithm : prepared.algorithms) {
    if (progress) progress->task(scenario.name + " / " + algorithm.spec->label);
    report_activity("running " + algorithm.spec->label + "\t" +
                    algorithm_origin(algorithm.spec->name));
    const std::vector<std::unique_ptr<TimingObserver>> passes =
        run_timing_passes(algorithm, scenario, options.repeat, progress);
    const TimingObserver& timing = *passes.front();
    // The evaluation pass follows the first timing pass's schedule, so both
    // compute the same forces whatever the slow loop's timing.
    ReplaySettings evaluation_settings = algorithm.replay;
    evaluation_settings.slow_loop_timing = SlowLoopTiming::kReplayed;
    evaluation_settings.replayed_schedule = &timing.schedule;
    const std::string ticks_file = "ticks_" + algorithm.spec->label + ".csv";
    const std::filesystem::path ticks_path = outcome.scratch->path() / ticks_file;
    std::ofstream ticks_out(ticks_path, std::ios::binary | std::ios::trunc);
    if (progress)
      progress->phase(truth.oracle ? "evaluation pass + oracle" : "evaluation pass",
                      scenario.trajectory.ticks());
    EvaluatingObserver observer(truth, scenario.context.tool.mesh, metrics_settings, &timing,
                                ticks_out, progress);
    replay(*algorithm.renderer, scenario.trajectory, evaluation_settings, observer);
    errno = 0;
    if (!observer.ticks().finish())
      throw std::filesystem::filesystem_error(
          "cannot write the ticks log", ticks_path,
          std::error_code(write_failure_cause(ticks_path), std::generic_category()));

    AlgorithmRun run;
    run.name = algorithm.spec->name;
    run.label = algorithm.spec->label;
    const AlgorithmEntry* entry = find_algorithm(run.name);
    run.renders_friction = entry && entry->renders_friction;
    run.plugin = algorithm_origin(run.name);
    run.params_json = algorithm.spec->params_json;
    run.preprocess = algorithm.preprocess;
    run.metrics = observer.metrics();
    run.force_reference = observer.followed_reference();
    if (run.force_reference) add_followed_reference(*run.force_reference, outcome.report);
    run.noise = timing.noise;
    run.repeats = timing_repeats(passes);
    std::string schedule_text;
    if (algorithm.has_slow_loop()) {
      run.slow_loop_latency =
          algorithm.replayed_schedule ? "replayed" : algorithm.slow_loop_latency;
      run.schedule_source = algorithm.schedule_source;
      run.schedule_file = "schedule_" + algorithm.spec->label + ".csv";
      schedule_text = schedule_csv(timing.schedule);
    }
    for (const Budget& budget : scenario.budgets)
      run.budgets.push_back(evaluate_budget(budget.name, budget.limit, run.metrics));
    if (const auto expected = scenario.expected_unstable.find(run.label);
        expected != scenario.expected_unstable.end())
      run.unstable_expected = expected->second;
    run.ticks_file = ticks_file;
    run.ticks_hash = observer.ticks().deterministic_hash();
    run.timing_pass = "separate";
    run.passes_agree = timing.results.value() == observer.results().value();
    run.analytic_reference = truth.analytic_name;
    run.reference_note = truth.analytic_note;
    run.penetration_source = penetration_source(truth);
    outcome.report.runs.push_back(std::move(run));
    outcome.ticks_files.push_back(ticks_path);
    outcome.schedule_csv.push_back(std::move(schedule_text));
    report_activity("idle");
    if (progress) progress->finish_task();
  }
  if (const std::optional<std::string> warning = never_reached_warning(outcome.report))
    outcome.report.warnings.push_back(*warning);
  return outcome;
}

}  // namespace hb
