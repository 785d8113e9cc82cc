#include "harness/output/run_report.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "harness/metrics/metric_table.h"
#include "harness/output/xml_text.h"
#include "harness/metrics/stability_verdict.h"

namespace hb {

using nlohmann::json;

namespace {
template <typename T>
json or_null(const std::optional<T>& value) {
  return value ? json(*value) : json(nullptr);
}

json percentiles_json(const Percentiles& p) {
  return {{"p50", p.p50},   {"p90", p.p90}, {"p99", p.p99},
          {"p999", p.p999}, {"max", p.max}, {"count", p.count}};
}
json percentiles_json(const std::optional<Percentiles>& p) {
  return p ? percentiles_json(*p) : json(nullptr);
}

json work_json(const std::vector<std::pair<std::string, int64_t>>& totals) {
  json out = json::object();
  for (const auto& [name, count] : totals) out[name] = count;
  return out;
}

json backend_json(const OracleBackendMetrics* b) {
  if (!b) return nullptr;
  return {{"ticks_evaluated", b->ticks_evaluated},
          {"penetration_max_m", b->penetration_max_m},
          {"penetration_rms_m", b->penetration_rms_m},
          {"penetrating_ticks", b->penetrating_ticks},
          {"inside_samples_max", b->inside_samples_max},
          {"evaluation_ns", percentiles_json(b->evaluation_ns)}};
}

json oracle_json(const std::optional<OracleMetrics>& o) {
  if (!o) return nullptr;
  json out = {{"broad_phase_skipped_ticks", o->broad_phase_skipped_ticks},
              {"inside_disagreements", o->inside_disagreements},
              {"intersection_volume_max_m3", or_null(o->intersection_volume_max_m3)},
              {"volume_evaluations", o->volume_evaluations},
              {"volume_ns", percentiles_json(o->volume_ns)},
              {"distance_min_m", or_null(o->distance_min_m)},
              {"distance_max_m", or_null(o->distance_max_m)},
              {"contacts_checked", o->contacts_checked},
              {"contact_normal_err_max_deg", or_null(o->contact_normal_err_max_deg)},
              {"contact_depth_err_rms_m", or_null(o->contact_depth_err_rms_m)},
              {"contact_depth_err_max_m", or_null(o->contact_depth_err_max_m)}};
  // Every known backend by name: null where the scenario did not ask for it.
  for (const OracleBackendEntry& entry : oracle_backends())
    out[std::string(entry.name)] = backend_json(o->backend(entry.name));
  return out;
}

// The closed-loop block's values outside the metric table; null in open loop.
json closed_loop_json(const std::optional<ClosedLoopMetrics>& c) {
  if (!c) return nullptr;
  return {
      {"contact_blocks", c->limit_cycles.contact_blocks},
      {"oscillating_blocks", c->limit_cycles.oscillating_blocks},
      {"displayed_stiffness_note",
       c->displayed_stiffness_note.empty() ? json(nullptr) : json(c->displayed_stiffness_note)}};
}

// Every metric of the table at its place, typed by its kind: a flag as
// true/false, a count as a whole number, others as numbers; null
// where it does not apply, unless the object that would hold it is absent
// (an oracle block that is null stays null).
void write_table_metrics(json& out, const RunMetrics& m) {
  for (const MetricDefinition& metric : metric_table()) {
    const json::json_pointer pointer{std::string(metric.json_pointer)};
    const std::optional<double> value = metric.read(m);
    if (!value) {
      if (out.contains(pointer.parent_pointer()) && out[pointer.parent_pointer()].is_object())
        out[pointer] = nullptr;
      continue;
    }
    switch (metric.kind) {
      case ValueKind::kFlag:
        out[pointer] = *value != 0;
        break;
      case ValueKind::kCount:
        out[pointer] = static_cast<int64_t>(*value);
        break;
      case ValueKind::kNumber:
        out[pointer] = *value;
        break;
    }
  }
}

// The one stability verdict (stability_verdict.h) at its defaults, with
// the criterion it applied, and whether the run passes it (stable, or
// unstable where that is expected, and why).
json stability_verdict_json(const AlgorithmRun& run) {
  const StabilityOptions options;
  const StabilityResult verdict = run_stability(run);
  return {
      {"stable", verdict.stable},
      {"failed", verdict.failed == StabilityCheck::kNone
                     ? json(nullptr)
                     : json(stability_check_name(verdict.failed))},
      {"reason", verdict.reason},
      {"criterion", stability_criterion_name(options.criterion)},
      {"epsilon_j", options.epsilon_j},
      {"expected_unstable", run.unstable_expected ? json(*run.unstable_expected) : json(nullptr)},
      {"pass", stability_passes(run)}};
}

// Every oracle backend this build knows, in oracle_backends() order: the
// ticks CSV has <name>_pen_m and <name>_inside columns for each, and
// <name>_volume_m3 for those that compute intersection volumes.
json oracle_backends_json() {
  json out = json::array();
  for (const OracleBackendEntry& entry : oracle_backends())
    out.push_back(
        {{"name", std::string(entry.name)}, {"intersection_volume", entry.intersection_volume}});
  return out;
}

json budgets_json(const std::vector<BudgetVerdict>& verdicts) {
  json budgets = json::array();
  for (const BudgetVerdict& b : verdicts) {
    budgets.push_back({{"name", b.name},
                       {"limit", b.limit},
                       {"value", or_null(b.value)},
                       {"pass", b.pass},
                       {"lower_bound", budget_is_lower_bound(b.name)},
                       {"message", b.message}});
  }
  return budgets;
}

json preprocess_json(const PreprocessInfo& preprocess) {
  json details = json::object();
  for (const auto& [name, value] : preprocess.details)
    details[name] = std::isfinite(value) ? json(value) : json(nullptr);
  return {{"seconds", preprocess.seconds},
          {"memory_bytes", preprocess.memory_bytes},
          {"cache_hit", preprocess.cache_hit},
          {"details", details}};
}

// The slow loop's block; null without a slow loop.
json slow_loop_json(const AlgorithmRun& run) {
  const TimingMetrics& t = run.metrics.timing;
  if (!t.slow_update_ns) return nullptr;
  const std::string& latency = run.slow_loop_latency;
  return {
      {"latency_ticks", latency},
      {"schedule", latency == "measured" || latency == "replayed" ? latency : "fixed"},
      {"schedule_file", run.schedule_file.empty() ? json(nullptr) : json(run.schedule_file)},
      {"schedule_source", run.schedule_source.empty() ? json(nullptr) : json(run.schedule_source)},
      {"update_ns", percentiles_json(t.slow_update_ns)},
      {"updates_over_1ms", or_null(t.slow_updates_over_tick)},
      {"data_age_mean_ticks", or_null(t.slow_data_age_mean_ticks)},
      {"data_age_p99_ticks", or_null(t.slow_data_age_p99_ticks)},
      {"data_age_max_ticks", or_null(t.slow_data_age_max_ticks)}};
}

json noise_json(const NoiseFloor& n) {
  return {{"quiet", n.quiet},
          {"cpu_share", n.cpu_share},
          {"calibration_before_ns", n.calibration_before_ns},
          {"calibration_after_ns", n.calibration_after_ns},
          {"calibration_spread", n.calibration_spread},
          {"calibration_drift", n.calibration_drift},
          {"load_average_1m", n.load_average_1m},
          {"logical_cores", n.logical_cores},
          {"other_runnable", n.other_runnable},
          {"interruptions",
           {{"rate_hz", n.interruptions.rate_hz},
            {"p50_ns", n.interruptions.p50_ns},
            {"max_ns", n.interruptions.max_ns}}},
          {"rule",
           "quiet: cpu_share >= 0.97, calibration spread and drift <= 0.10, "
           "load average <= cores - 0.5, other runnable tasks <= max(0, cores - 2)"}};
}

// The spread of the timing passes' percentiles; null with one pass.
json repeats_json(const std::optional<TimingRepeats>& repeats) {
  if (!repeats) return nullptr;
  auto spread = [](const Spread& s) {
    return json{{"min", s.min}, {"median", s.median}, {"max", s.max}};
  };
  return {{"count", repeats->count},
          {"step_p50_ns", spread(repeats->step_p50_ns)},
          {"step_p99_ns", spread(repeats->step_p99_ns)}};
}

// Callgrind's counts; null when not asked for.
json instructions_json(const std::optional<InstructionCounts>& c) {
  if (!c) return nullptr;
  auto mean = [](int64_t total, int64_t count) {
    return count > 0 ? json(static_cast<double>(total) / static_cast<double>(count))
                     : json(nullptr);
  };
  return {{"tool", "valgrind callgrind, user-space instructions (Ir) inside the measured calls"},
          {"step_per_tick_mean", mean(c->step_total, c->ticks)},
          {"step_total", c->step_total},
          {"slow_update_per_call_mean",
           c->has_slow_loop ? mean(c->slow_update_total, c->slow_updates) : json(nullptr)},
          {"slow_update_total", c->has_slow_loop ? json(c->slow_update_total) : json(nullptr)},
          {"slow_updates", c->has_slow_loop ? json(c->slow_updates) : json(nullptr)}};
}

json timing_json(const AlgorithmRun& run) {
  const TimingMetrics& t = run.metrics.timing;
  // The CPU per tick's p99 and mean are the metric table's.
  const json cpu_per_tick = {
      {"p50", t.cpu_per_tick_ns.percentiles.p50},
      {"max", t.cpu_per_tick_ns.percentiles.max},
      {"attribution",
       "step() of the tick plus, for each slow update, its time spread evenly over the ticks "
       "from its start to its installation"}};
  return {{"ticks", t.ticks},
          {"step_ns", percentiles_json(t.step_ns)},
          {"step_ns_sample", t.step_ns_sample},
          {"free_space_step_ns", percentiles_json(t.free_space_step_ns)},
          {"contact_step_ns", percentiles_json(t.contact_step_ns)},
          {"slow_loop", slow_loop_json(run)},
          {"cpu_per_tick_ns", cpu_per_tick},
          {"noise", noise_json(run.noise)},
          {"repeats", repeats_json(run.repeats)},
          {"instructions", instructions_json(run.instructions)}};
}

// One run of summary.json: the blocks written here, then every metric of
// the table at its place.
json force_reference_json(const ForceReferenceDescription& f) {
  return {{"method", f.method},
          {"every", f.every},
          {"evaluated_ticks", f.evaluated_ticks},
          {"not_started_ticks", f.not_started_ticks},
          {"unconverged_ticks", f.unconverged_ticks},
          {"infeasible_ticks", f.infeasible_ticks},
          {"max_iterations", f.max_iterations},
          {"kkt_residual_max", f.kkt_residual_max},
          {"tool_points", f.tool_points},
          {"clearance_m", f.clearance_m},
          {"friction", f.friction},
          {"sticking_ticks", f.sticking_ticks},
          {"seconds", f.seconds},
          {"cache_hit", f.cache_hit}};
}

json run_json(const AlgorithmRun& run) {
  const RunMetrics& m = run.metrics;
  json out = {
      {"algorithm", run.name},
      {"label", run.label},
      {"renders_friction", run.renders_friction},
      {"plugin", run.plugin.empty() ? json(nullptr) : json(run.plugin)},
      {"params", json::parse(run.params_json.empty() ? "{}" : run.params_json)},
      {"force_reference",
       run.force_reference ? force_reference_json(*run.force_reference) : json(nullptr)},
      {"ticks_file", run.ticks_file},
      {"preprocess", preprocess_json(run.preprocess)},
      {"timing", timing_json(run)},
      {"accuracy",
       {{"reference",
         run.analytic_reference.empty() ? json(nullptr) : json(run.analytic_reference)},
        {"reference_note", run.reference_note},
        {"penetration_source",
         run.penetration_source.empty() ? json(nullptr) : json(run.penetration_source)},
        {"force_dir_err_rms_deg", or_null(m.accuracy.force_dir_err_rms_deg)},
        {"penetration_ticks", or_null(m.accuracy.penetration_ticks)}}},
      {"stability",
       {{"diverged_at_tick", or_null(m.stability.diverged_at_tick)},
        {"proxy_resets", m.stability.proxy_resets},
        {"saturated_ticks", m.stability.saturated_ticks},
        {"max_proxy_separation_m", m.stability.max_proxy_separation_m},
        {"proxy_nonfinite_ticks", m.stability.proxy_nonfinite_ticks},
        {"passivity_energy_final_j", m.stability.passivity_energy_final_j},
        {"force_hf_energy_fraction", m.stability.force_hf_energy_fraction},
        {"device_chatter_m", m.stability.device_chatter_m},
        {"verdict", stability_verdict_json(run)}}},
      {"transparency",
       {{"free_space_ticks", m.transparency.free_space_ticks},
        {"free_space_force_rms_n", or_null(m.transparency.free_space_force_rms_n)}}},
      {"contacts",
       {{"contact_ticks", m.contacts.contact_ticks},
        {"max_contacts", m.contacts.max_contacts},
        {"mean_contacts", m.contacts.mean_contacts},
        {"work", work_json(m.contacts.total_work)}}},
      {"oracle", oracle_json(m.oracle)},
      {"closed_loop", closed_loop_json(m.closed_loop)},
      {"determinism",
       {{"ticks_hash", run.ticks_hash},
        {"timing_pass", run.timing_pass},
        {"passes_agree", or_null(run.passes_agree)}}},
      {"budgets", budgets_json(run.budgets)},
  };
  write_table_metrics(out, m);
  return out;
}

}  // namespace

Spread spread_of(std::vector<double> values) {
  if (values.empty()) return {};
  std::sort(values.begin(), values.end());
  return {values.front(), values[(values.size() - 1) / 2], values.back()};
}

StabilityResult run_stability(const AlgorithmRun& run) { return judge_stability(run.metrics); }

bool stability_passes(const AlgorithmRun& run) {
  return run.unstable_expected.has_value() || run_stability(run).stable;
}

bool ScenarioRun::all_stable_or_expected() const {
  return std::all_of(runs.begin(), runs.end(), stability_passes);
}

bool ScenarioRun::all_budgets_pass() const {
  for (const AlgorithmRun& run : runs)
    for (const BudgetVerdict& b : run.budgets)
      if (!b.pass) return false;
  return true;
}

namespace {
json vec3_json(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

json outline_json(const ObjectOutline& outline) {
  return {{"name", outline.name},
          {"type", outline.type},
          {"min", vec3_json(outline.min)},
          {"max", vec3_json(outline.max)},
          {"distance_only", outline.distance_only}};
}

// The scene's and the tool's bounds, for the report's picture; null
// without them.
json outline_json(const ScenarioRun& run) {
  if (run.scene_outline.empty() || !run.tool_outline) return nullptr;
  json scene = json::array();
  for (const ObjectOutline& object : run.scene_outline) scene.push_back(outline_json(object));
  json tool = outline_json(*run.tool_outline);
  tool.erase("distance_only");
  tool.erase("name");
  return {{"scene", scene}, {"tool", tool}};
}
}  // namespace

json summary_json(const ScenarioRun& run) {
  json runs = json::array();
  for (const AlgorithmRun& r : run.runs) runs.push_back(run_json(r));
  json oracle = nullptr;
  if (run.oracle) {
    oracle = {{"backends", run.oracle->backends},
              {"exact_every", run.oracle->exact_every},
              {"tool_samples", run.oracle->tool_samples},
              {"sample_spacing_m", run.oracle->sample_spacing_m},
              {"distance_only_objects", run.oracle->distance_only_objects},
              {"build_seconds", run.oracle->build_seconds}};
  }
  json force_reference = nullptr;
  if (run.force_reference) force_reference = force_reference_json(*run.force_reference);
  return {{"schema_version", 1},
          {"context",
           {{"commit", run.context.commit},
            {"build_type", run.context.build_type},
            {"compiler", run.context.compiler},
            {"compiler_flags", run.context.compiler_flags},
            {"cpu", run.context.cpu},
            {"logical_cores", run.context.logical_cores},
            {"cpu_governor",
             run.context.cpu_governor.empty() ? json(nullptr) : json(run.context.cpu_governor)},
            {"load_average_1m", or_null(run.context.load_average_1m)},
            {"clock_overhead_ns", run.context.clock_overhead_ns},
            {"date", run.context.date},
            {"hapticbench_version", run.context.hapticbench_version}}},
          {"scenario",
           {{"name", run.scenario_name},
            {"path", run.scenario_path},
            {"description", run.scenario_description},
            {"outline", outline_json(run)},
            {"hash", run.scenario_hash},
            {"trace", run.trace_description},
            {"scene_friction", run.scene_friction},
            {"tags", run.tags},
            {"coupling",
             {{"k_t", run.coupling.k_t},
              {"b_t", run.coupling.b_t},
              {"k_r", run.coupling.k_r},
              {"b_r", run.coupling.b_r}}}}},
          {"oracle", oracle},
          {"force_reference", force_reference},
          {"runs", runs},
          {"warnings", run.warnings},
          {"metric_table", metric_table_json()},
          {"oracle_backends", oracle_backends_json()}};
}

std::string junit_xml(const ScenarioRun& run) {
  int tests = 0, failures = 0;
  std::ostringstream cases;
  for (const AlgorithmRun& r : run.runs) {
    // The stability verdict, a test of every run: it fails where the run is
    // unstable and that is not expected.
    ++tests;
    const StabilityResult verdict = run_stability(r);
    cases << "    <testcase classname=\"" << xml_escape(run.scenario_name + "." + r.label)
          << "\" name=\"stability\">";
    if (!stability_passes(r)) {
      ++failures;
      cases << "<failure message=\"" << xml_escape("unstable: " + verdict.reason) << "\"/>";
    } else {
      cases << "<system-out>"
            << xml_escape(verdict.stable ? "stable (" + verdict.reason + ")"
                                         : "unstable: " + verdict.reason +
                                               ", expected: " + *r.unstable_expected)
            << "</system-out>";
    }
    cases << "</testcase>\n";
    for (const BudgetVerdict& b : r.budgets) {
      ++tests;
      cases << "    <testcase classname=\"" << xml_escape(run.scenario_name + "." + r.label)
            << "\" name=\"" << xml_escape(b.name) << "\">";
      // Every case, passing or not, says the measured value and the limit.
      std::ostringstream figures;
      figures.precision(6);
      figures << b.name << " = ";
      if (b.value)
        figures << *b.value;
      else
        figures << "n/a";
      figures << (budget_is_lower_bound(b.name) ? ", lower bound " : ", limit ") << b.limit;
      if (!b.pass) {
        ++failures;
        cases << "<failure message=\"" << xml_escape(b.message) << "\">"
              << xml_escape(figures.str()) << "</failure>";
      } else {
        cases << "<system-out>"
              << xml_escape(figures.str() + (b.message.empty() ? "" : "; " + b.message))
              << "</system-out>";
      }
      cases << "</testcase>\n";
    }
  }
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<testsuites tests=\"" << tests << "\" failures=\"" << failures << "\">\n"
      << "  <testsuite name=\"" << xml_escape(run.scenario_name) << "\" tests=\"" << tests
      << "\" failures=\"" << failures << "\">\n"
      << cases.str() << "  </testsuite>\n</testsuites>\n";
  return out.str();
}

}  // namespace hb
