// Preparing a scenario: renderers (with the replay's own parameters split
// off), the reach box, ground truth, and recorded schedules to follow.
#include <fnmatch.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "algorithms/core/build_progress.h"
#include "algorithms/registry.h"
#include "hapticbench/input_error.h"
#include "harness/process/activity_report.h"
#include "harness/reference/analytic_reference.h"
#include "harness/run/scenario_runner.h"

namespace hb {

namespace {

// "slow_loop_latency" belongs to the replay loop, not to the algorithm: it
// is taken out of the parameters before the renderer sees them.
ParamSet split_replay_params(const AlgorithmSpec& spec, PreparedAlgorithm& prepared) {
  ParamSet renderer_params(spec.params.prefix());
  for (const auto& [key, value] : spec.params.values())
    if (key != "slow_loop_latency") renderer_params.set(key, value);
  // Measured by default: an update is installed as many ticks after it
  // started as it took on this machine; a whole number is an idealised,
  // fixed latency.
  const std::optional<long long> latency =
      spec.params.has("slow_loop_latency")
          ? spec.params.integer_or_word("slow_loop_latency", 1, 1, 100000, "measured")
          : std::nullopt;
  prepared.replay.slow_loop_timing = latency ? SlowLoopTiming::kFixed : SlowLoopTiming::kMeasured;
  if (latency) prepared.replay.fixed_latency_ticks = *latency;
  prepared.slow_loop_latency = latency ? std::to_string(*latency) : "measured";
  return renderer_params;
}

std::string analytic_reference_name(const RenderContext& context) {
  return "ideal rigid contact: " + shape_type_name(context.tool.shape->type) + " tool on box";
}

std::string with_source(const InputError& error, const std::string& path) {
  return error.source().empty() ? path : error.source();
}

}  // namespace

namespace {
// What the renderers are given: the scenario's context plus the box the
// tool can reach, the trace's tool-frame positions grown by the tool's
// radius about its frame origin. In closed loop the trace is the intent and
// the device strays from it by what the hand's spring lets it: the box grows
// by kClosedLoopReachMargin more.
constexpr double kClosedLoopReachMargin = 0.05;  // m: 15 N on the default hand
RenderContext context_with_reach(const Scenario& scenario) {
  RenderContext context = scenario.context;
  Eigen::AlignedBox3d reach;
  scenario.trajectory.for_each([&reach](const DeviceSample& sample) {
    if (sample.pose.p.allFinite()) reach.extend(sample.pose.p);
  });
  if (!reach.isEmpty()) {
    const double radius = context.tool.mesh.radius_about(Vec3::Zero()) +
                          (scenario.closed_loop ? kClosedLoopReachMargin : 0.0);
    reach.min().array() -= radius;
    reach.max().array() += radius;
    context.reach = reach;
  }
  return context;
}

std::vector<PreparedAlgorithm> prepare_algorithms(const Scenario& scenario,
                                                  const RenderContext& context,
                                                  const AlgorithmSelection& only,
                                                  ProgressDisplay* progress) {
  std::vector<PreparedAlgorithm> prepared;
  for (std::size_t i = 0; i < scenario.algorithms.size(); ++i) {
    const AlgorithmSpec& spec = scenario.algorithms[i];
    if (!is_selected(only, spec)) continue;
    PreparedAlgorithm algorithm;
    algorithm.spec = &spec;
    if (scenario.closed_loop) algorithm.replay.closed_loop = &*scenario.closed_loop;
    if (progress) {
      progress->task(scenario.name + " / " + spec.label);
      progress->phase("preprocessing");
    }
    const ScopedBuildProgressListener stages(progress);
    report_activity("running " + spec.label + "\t" + algorithm_origin(spec.name));
    try {
      const ParamSet params = split_replay_params(spec, algorithm);
      const auto t0 = std::chrono::steady_clock::now();
      algorithm.renderer =
          create_renderer(spec.name, context, params, "/algorithms/" + std::to_string(i) + "/name");
      const auto t1 = std::chrono::steady_clock::now();
      algorithm.preprocess.seconds = std::chrono::duration<double>(t1 - t0).count();
      BuildReport built = algorithm.renderer->build_report();
      algorithm.preprocess.memory_bytes = built.memory_bytes;
      algorithm.preprocess.cache_hit = built.cache_hit;
      algorithm.preprocess.details = std::move(built.details);
    } catch (const InputError& error) {
      // A renderer that cannot render the scene or the tool names what it
      // cannot render; the choice to change is the algorithm's entry.
      const std::string& location = error.location();
      if (location.rfind("/scene", 0) == 0 || location.rfind("/tool", 0) == 0)
        throw InputError(with_source(error, scenario.path), "/algorithms/" + std::to_string(i),
                         spec.name + " (label " + spec.label +
                             ") cannot run on this scenario: " + location + ": " + error.message());
      throw InputError(with_source(error, scenario.path), location, error.message());
    }
    report_activity("idle");
    if (progress) progress->finish_task();
    prepared.push_back(std::move(algorithm));
  }
  if (!only.empty() && prepared.empty()) {
    std::string known, asked;
    for (const AlgorithmSpec& spec : scenario.algorithms)
      known += (known.empty() ? "" : ", ") + spec.label;
    for (const std::string& name : only) asked += (asked.empty() ? "\"" : " or \"") + name + "\"";
    throw InputError(scenario.path, "--algo",
                     "no algorithm named or labelled " + asked + " (scenario has: " + known + ")");
  }
  return prepared;
}

GroundTruth prepare_ground_truth(const Scenario& scenario, ProgressDisplay* progress) {
  GroundTruth truth;
  if (scenario.reference.analytic == "auto") {
    truth.analytic = make_analytic_scene(scenario.context, &truth.analytic_note);
    if (truth.analytic) truth.analytic_name = analytic_reference_name(scenario.context);
  } else {
    truth.analytic_note = "analytic reference switched off by the scenario";
  }
  if (!scenario.reference.oracle_backends.empty()) {
    OracleEvaluationSettings settings;
    settings.backends = scenario.reference.oracle_backends;
    settings.exact_every = scenario.reference.exact_every;
    settings.sample_spacing_m = scenario.reference.sample_spacing_m;
    if (progress) {
      progress->task(scenario.name + " / ground truth");
      progress->phase("oracle");
    }
    const ScopedBuildProgressListener stages(progress);
    const auto t0 = std::chrono::steady_clock::now();
    try {
      truth.oracle = std::make_unique<OracleEvaluator>(scenario.context, settings);
    } catch (const InputError& error) {
      // The oracle names the object; the scenario names where it comes from.
      throw InputError(with_source(error, scenario.path), error.location(),
                       error.message() + " (scenario " + scenario.path + ")");
    }
    truth.oracle_build_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (progress) progress->finish_task();
  }
  if (wants_mesh_force_reference(scenario, truth.analytic.has_value()) && scenario.closed_loop) {
    // Built per run as its device moves; checked here, so that a scene the
    // oracles refuse stops the command before anything runs.
    try {
      const ForceReferenceFollower check(scenario, "the device");
    } catch (const InputError& error) {
      throw InputError(with_source(error, scenario.path), error.location(),
                       error.message() + " (scenario " + scenario.path + ")");
    }
    truth.force_follows_device = &scenario;
    truth.analytic_name =
        "mesh reference along each run's own device path (closed loop): rigid proxy with the "
        "coupling's damper and the scene's friction";
    truth.analytic_note.clear();
  } else if (wants_mesh_force_reference(scenario, truth.analytic.has_value())) {
    try {
      truth.force = compute_force_reference(scenario, progress);
    } catch (const InputError& error) {
      throw InputError(with_source(error, scenario.path), error.location(),
                       error.message() + " (scenario " + scenario.path + ")");
    }
    const ForceReferenceDescription& made = truth.force->description;
    if (made.not_started_ticks > 0) {
      char clearance_mm[32];
      std::snprintf(clearance_mm, sizeof clearance_mm, "%g", made.clearance_m * 1000);
      const std::string warning =
          "warning: " + scenario.path + ": the force reference could not start on " +
          std::to_string(made.not_started_ticks) + " of " +
          std::to_string(made.not_started_ticks + made.evaluated_ticks) +
          " sampled ticks: the tool was inside the scene or within " + clearance_mm +
          " mm of it at the device's pose; those ticks have no force reference\n";
      if (progress)
        progress->print_above(std::cerr, warning);
      else
        std::cerr << warning;
    }
    truth.analytic_name = "mesh reference: " + truth.force->description.method;
    truth.analytic_note.clear();
  }
  return truth;
}
}  // namespace

bool is_selected(const AlgorithmSelection& only, const AlgorithmSpec& spec) {
  const auto matches = [](const std::string& pattern, const std::string& text) {
    return pattern == text || ::fnmatch(pattern.c_str(), text.c_str(), 0) == 0;
  };
  return only.empty() || std::find_if(only.begin(), only.end(), [&](const std::string& name) {
                           return matches(name, spec.name) || matches(name, spec.label);
                         }) != only.end();
}

PreparedScenario prepare_scenario(const Scenario& scenario, const AlgorithmSelection& only,
                                  ProgressDisplay* progress) {
  PreparedScenario prepared;
  prepared.scenario = &scenario;
  prepared.context = std::make_unique<RenderContext>(context_with_reach(scenario));
  prepared.algorithms = prepare_algorithms(scenario, *prepared.context, only, progress);
  prepared.truth = prepare_ground_truth(scenario, progress);
  return prepared;
}

void use_recorded_schedules(PreparedScenario& prepared, const std::string& path) {
  namespace fs = std::filesystem;
  const Scenario& scenario = *prepared.scenario;
  std::error_code error;
  if (fs::is_regular_file(path, error)) {
    const std::string name = fs::path(path).filename().string();
    const std::string prefix = "schedule_", suffix = ".csv";
    const std::string label =
        name.size() > prefix.size() + suffix.size() && name.rfind(prefix, 0) == 0 &&
                name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0
            ? name.substr(prefix.size(), name.size() - prefix.size() - suffix.size())
            : "";
    for (PreparedAlgorithm& algorithm : prepared.algorithms)
      if (algorithm.spec->label == label && algorithm.has_slow_loop()) {
        algorithm.replayed_schedule = std::make_unique<SlowLoopSchedule>(read_schedule_file(path));
        algorithm.schedule_source = path;
        return;
      }
    throw InputError(path, "--schedule",
                     "expected schedule_<label>.csv for a multi-rate algorithm of " +
                         scenario.path + "; no such label");
  }
  if (!fs::is_directory(path, error))
    throw InputError(path, "--schedule", "expected a schedule file or a run folder holding one");
  for (PreparedAlgorithm& algorithm : prepared.algorithms) {
    if (!algorithm.has_slow_loop()) continue;
    const std::string file = "schedule_" + algorithm.spec->label + ".csv";
    fs::path found;
    for (const fs::path& candidate : {fs::path(path) / file, fs::path(path) / scenario.name / file})
      if (fs::is_regular_file(candidate, error)) {
        found = candidate;
        break;
      }
    if (found.empty())
      throw InputError(path, "--schedule",
                       "no " + file + " here or in " + scenario.name + "/ for " +
                           algorithm.spec->label + " of " + scenario.path);
    algorithm.replayed_schedule =
        std::make_unique<SlowLoopSchedule>(read_schedule_file(found.string()));
    algorithm.schedule_source = found.string();
  }
}

}  // namespace hb
