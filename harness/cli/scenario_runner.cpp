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
  EvaluatingObserver(const std::optional<AnalyticScene>& analytic, MetricsSettings settings)
      : analytic_(analytic), metrics_(settings) {}

  void on_tick(const TickRecord& record) override {
    TickEvaluation evaluation;
    if (analytic_) {
      const IdealRendering ideal = ideal_rigid_contact(*analytic_, record.device->pose);
      evaluation.ideal_display = ideal.display;
      evaluation.reference_contact = ideal.in_contact;
      if (is_finite(record.result.proxy))
        evaluation.penetration_m = exact_penetration_depth(*analytic_, record.result.proxy);
    }
    metrics_.add(record, evaluation);
    ticks_.add(record, evaluation);
  }

  RunMetrics metrics() const { return metrics_.finish(); }
  const TicksCsvWriter& ticks() const { return ticks_; }

 private:
  const std::optional<AnalyticScene>& analytic_;
  MetricsAccumulator metrics_;
  TicksCsvWriter ticks_;
};

std::string analytic_reference_name(const RenderContext& context) {
  return "ideal rigid contact: " + shape_type_name(context.tool.shape->type) + " tool on box";
}

std::string with_source(const InputError& error, const std::string& path) {
  return error.source().empty() ? path : error.source();
}

}  // namespace

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

ScenarioOutcome run_prepared(const Scenario& scenario, std::vector<PreparedAlgorithm>& algorithms) {
  ScenarioOutcome outcome;
  ScenarioRun& report = outcome.report;
  report.scenario_name = scenario.name;
  report.scenario_path = scenario.path;
  report.scenario_hash = scenario.content_hash;
  report.trace_description = scenario.trace_description;
  report.context = current_run_context();

  std::optional<AnalyticScene> analytic;
  std::string reference_note;
  if (scenario.reference.analytic == "auto") {
    analytic = make_analytic_scene(scenario.context);
    if (!analytic)
      reference_note = "no closed form: the scene is not one box with a sphere or box tool";
  } else {
    reference_note = "analytic reference switched off by the scenario";
  }

  MetricsSettings metrics_settings;
  const Tool& tool = scenario.context.tool;
  const double tool_radius = tool.mesh.radius_about(tool.mass.centre_of_mass);
  metrics_settings.divergence_distance_m = std::max(0.1, 5.0 * tool_radius);

  for (PreparedAlgorithm& algorithm : algorithms) {
    EvaluatingObserver observer(analytic, metrics_settings);
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
    run.analytic_reference = analytic ? analytic_reference_name(scenario.context) : "";
    run.reference_note = reference_note;
    report.runs.push_back(std::move(run));
    outcome.ticks_csv.push_back(observer.ticks().text());
  }
  return outcome;
}

}  // namespace hb
