#include "harness/cli/scenario_runner.h"

#include <algorithm>
#include <chrono>

#include "algorithms/core/input_error.h"
#include "algorithms/registry.h"
#include "harness/metrics/budgets.h"
#include "harness/output/ticks_csv.h"
#include "harness/reference/analytic_reference.h"

namespace hb {

namespace {

// "slow_loop_latency" belongs to the replay loop, not to the algorithm: it
// is taken out of the parameters before the renderer sees them.
ParamSet split_replay_params(const AlgorithmSpec& spec, PreparedAlgorithm& prepared) {
  ParamSet renderer_params(spec.params.prefix());
  for (const auto& [key, value] : spec.params.values())
    if (key != "slow_loop_latency") renderer_params.set(key, value);
  const std::optional<long long> latency =
      spec.params.integer_or_word("slow_loop_latency", 1, 1, 100000, "measured");
  prepared.replay.slow_loop_latency_ticks = latency;
  prepared.slow_loop_latency = latency ? std::to_string(*latency) : "measured";
  return renderer_params;
}

// Ground truth and logging for one algorithm's replay.
class EvaluatingObserver : public TickObserver {
 public:
  EvaluatingObserver(GroundTruth& truth, MetricsSettings settings)
      : truth_(truth), metrics_(settings) {}

  void on_tick(const TickRecord& record) override {
    TickEvaluation evaluation;
    const bool proxy_finite = is_finite(record.result.proxy);
    if (truth_.analytic) {
      const IdealRendering ideal = ideal_rigid_contact(*truth_.analytic, record.device->pose);
      evaluation.ideal_display = ideal.display;
      evaluation.reference_contact = ideal.in_contact;
      if (proxy_finite)
        evaluation.penetration_m = exact_penetration_depth(*truth_.analytic, record.result.proxy);
    }
    if (truth_.oracle) {
      evaluation.oracle =
          truth_.oracle->evaluate(record.device->tick, record.result.proxy, record.result.contacts);
      // Without a closed form, the penetration is the oracle's: Embree on
      // every tick, else CGAL on its ticks.
      if (!evaluation.penetration_m && !evaluation.oracle->broad_phase_skipped) {
        if (evaluation.oracle->embree)
          evaluation.penetration_m = evaluation.oracle->embree->max_depth_m;
        else if (evaluation.oracle->cgal)
          evaluation.penetration_m = evaluation.oracle->cgal->max_depth_m;
      } else if (!evaluation.penetration_m && proxy_finite && truth_.oracle->measures_penetration()) {
        evaluation.penetration_m = 0.0;  // bounds clear of the scene: no penetration
      }
    }
    metrics_.add(record, evaluation);
    ticks_.add(record, evaluation);
  }

  RunMetrics metrics() const { return metrics_.finish(); }
  const TicksCsvWriter& ticks() const { return ticks_; }

 private:
  GroundTruth& truth_;
  MetricsAccumulator metrics_;
  TicksCsvWriter ticks_;
};

std::string penetration_source(const GroundTruth& truth) {
  if (truth.analytic) return "analytic";
  if (!truth.oracle || !truth.oracle->measures_penetration()) return "";
  if (truth.oracle->has_embree()) return "embree";
  if (truth.oracle->has_cgal()) return "cgal";
  return "";
}

std::string analytic_reference_name(const RenderContext& context) {
  return "ideal rigid contact: " + shape_type_name(context.tool.shape->type) + " tool on box";
}

std::string with_source(const InputError& error, const std::string& path) {
  return error.source().empty() ? path : error.source();
}

}  // namespace

namespace {
std::vector<PreparedAlgorithm> prepare_algorithms(const Scenario& scenario,
                                                  const std::optional<std::string>& only) {
  std::vector<PreparedAlgorithm> prepared;
  for (std::size_t i = 0; i < scenario.algorithms.size(); ++i) {
    const AlgorithmSpec& spec = scenario.algorithms[i];
    if (only && spec.name != *only && spec.label != *only) continue;
    PreparedAlgorithm algorithm;
    algorithm.spec = &spec;
    try {
      const ParamSet params = split_replay_params(spec, algorithm);
      const auto t0 = std::chrono::steady_clock::now();
      algorithm.renderer = create_renderer(spec.name, scenario.context, params,
                                           "/algorithms/" + std::to_string(i) + "/name");
      const auto t1 = std::chrono::steady_clock::now();
      algorithm.preprocess.seconds = std::chrono::duration<double>(t1 - t0).count();
    } catch (const InputError& error) {
      throw InputError(with_source(error, scenario.path), error.location(), error.message());
    }
    prepared.push_back(std::move(algorithm));
  }
  if (only && prepared.empty()) {
    std::string known;
    for (const AlgorithmSpec& spec : scenario.algorithms)
      known += (known.empty() ? "" : ", ") + spec.label;
    throw InputError(
        scenario.path, "--algo",
        "no algorithm named or labelled \"" + *only + "\" (scenario has: " + known + ")");
  }
  return prepared;
}

GroundTruth prepare_ground_truth(const Scenario& scenario) {
  GroundTruth truth;
  if (scenario.reference.analytic == "auto") {
    truth.analytic = make_analytic_scene(scenario.context, &truth.analytic_note);
    if (truth.analytic) truth.analytic_name = analytic_reference_name(scenario.context);
  } else {
    truth.analytic_note = "analytic reference switched off by the scenario";
  }
  const std::string& oracle = scenario.reference.oracle;
  if (oracle != "none") {
    OracleEvaluationSettings settings;
    settings.use_embree = oracle == "embree" || oracle == "both";
    settings.use_cgal = oracle == "cgal" || oracle == "both";
    settings.exact_every = scenario.reference.exact_every;
    settings.sample_spacing_m = scenario.reference.sample_spacing_m;
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
  }
  return truth;
}
}  // namespace

PreparedScenario prepare_scenario(const Scenario& scenario, const std::optional<std::string>& only) {
  PreparedScenario prepared;
  prepared.scenario = &scenario;
  prepared.algorithms = prepare_algorithms(scenario, only);
  prepared.truth = prepare_ground_truth(scenario);
  return prepared;
}

ScenarioOutcome run_prepared(PreparedScenario& prepared) {
  const Scenario& scenario = *prepared.scenario;
  GroundTruth& truth = prepared.truth;
  ScenarioOutcome outcome;
  ScenarioRun& report = outcome.report;
  report.scenario_name = scenario.name;
  report.scenario_path = scenario.path;
  report.scenario_hash = scenario.content_hash;
  report.trace_description = scenario.trace_description;
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

  MetricsSettings metrics_settings;
  const Tool& tool = scenario.context.tool;
  const double tool_radius = tool.mesh.radius_about(tool.mass.centre_of_mass);
  metrics_settings.divergence_distance_m = std::max(0.1, 5.0 * tool_radius);

  for (PreparedAlgorithm& algorithm : prepared.algorithms) {
    EvaluatingObserver observer(truth, metrics_settings);
    replay(*algorithm.renderer, scenario.device_samples, algorithm.replay, observer);

    AlgorithmRun run;
    run.name = algorithm.spec->name;
    run.label = algorithm.spec->label;
    run.params_json = algorithm.spec->params_json;
    run.preprocess = algorithm.preprocess;
    run.metrics = observer.metrics();
    if (run.metrics.timing.slow_update_ns) run.slow_loop_latency = algorithm.slow_loop_latency;
    for (const Budget& budget : scenario.budgets)
      run.budgets.push_back(evaluate_budget(budget.name, budget.limit, run.metrics));
    run.ticks_file = "ticks_" + run.label + ".csv";
    run.ticks_hash = observer.ticks().deterministic_hash();
    run.analytic_reference = truth.analytic_name;
    run.reference_note = truth.analytic_note;
    run.penetration_source = penetration_source(truth);
    report.runs.push_back(std::move(run));
    outcome.ticks_csv.push_back(observer.ticks().text());
  }
  return outcome;
}

}  // namespace hb
