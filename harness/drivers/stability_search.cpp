#include "harness/drivers/stability_search.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "hapticbench/input_error.h"
#include "harness/run/run_request.h"
#include "harness/scenario/scenario.h"

namespace hb {

namespace {
using Json = nlohmann::ordered_json;
constexpr int kMaxProbes = 64;

Json or_null(const std::optional<double>& value) { return value ? Json(*value) : Json(); }
}  // namespace

Json probe_json(const StabilityProbe& p) {
  Json json = Json::object();
  for (const auto& [pointer, value] : p.settings) json["settings"][pointer] = value;
  json["value"] = p.settings.empty() ? Json() : Json(p.settings.back().second);
  json["stable"] = p.stable;
  json["failed"] =
      p.failed == StabilityCheck::kNone ? Json() : Json(stability_check_name(p.failed));
  json["reason"] = p.reason;
  json["diverged"] = p.diverged;
  json["nonfinite"] = p.nonfinite;
  json["passivity_energy_min_j"] = p.passivity_min_j;
  json["max_proxy_separation_m"] = p.max_separation_m;
  json["chatters"] = p.chatters;
  json["proxy_chatter_m"] = p.proxy_chatter_m;
  json["display_energy_min_j"] = or_null(p.display_energy_min_j);
  json["limit_cycle"] = p.limit_cycle ? Json(*p.limit_cycle) : Json();
  json["limit_cycle_amplitude_m"] = or_null(p.limit_cycle_amplitude_m);
  json["limit_cycle_frequency_hz"] = or_null(p.limit_cycle_frequency_hz);
  return json;
}

ScenarioProber::ScenarioProber(std::string scenario_path, std::string label,
                               StabilityCriterion criterion, double epsilon_j,
                               ProgressDisplay& progress)
    : source_(ScenarioSource::read_now(scenario_path)),
      label_(std::move(label)),
      criterion_(criterion),
      epsilon_j_(epsilon_j),
      progress_(progress) {}

RunRequest ScenarioProber::request(const std::vector<std::pair<std::string, double>>& settings) {
  RunRequest request;
  request.scenario = source_;
  for (const auto& [pointer, value] : settings) request.edits.push_back({pointer, value});
  request.algorithms = {label_};
  request.options.progress = &progress_;
  return request;
}

Scenario ScenarioProber::load(const RunRequest& request) {
  Scenario scenario = read_scenario(request);
  // Only the algorithm asked for: the label must name one.
  const auto spec =
      std::find_if(scenario.algorithms.begin(), scenario.algorithms.end(),
                   [&](const AlgorithmSpec& a) { return a.label == label_ || a.name == label_; });
  if (spec == scenario.algorithms.end())
    throw InputError(source_.path, "/algorithms",
                     "no algorithm labelled or named \"" + label_ + "\"");
  algorithm_ = spec->name;
  const Json params = Json::parse(spec->params_json);
  integrator_ = params.contains("integrator") && params["integrator"].is_string()
                    ? params["integrator"].get<std::string>()
                    : "";
  name_ = scenario.name;
  return scenario;
}

void ScenarioProber::check(const std::vector<std::pair<std::string, double>>& settings) {
  load(request(settings));
}

SmallSignalLimit ScenarioProber::small_signal(
    const std::vector<std::pair<std::string, double>>& settings) {
  const Scenario scenario = load(request(settings));
  if (!scenario.closed_loop)
    return {std::nullopt, "open loop: there is no hand and device whose loop to linearise"};
  return small_signal_k_t_limit(*scenario.closed_loop, scenario.context.coupling.b_t,
                                scenario.context.dt_s, algorithm_);
}

StabilityProbe ScenarioProber::probe(const std::vector<std::pair<std::string, double>>& settings) {
  const RunRequest run = request(settings);
  const Scenario scenario = load(run);
  std::ostringstream prefix;
  prefix << "run " << ++runs_;
  for (const auto& [pointer, value] : settings) prefix << ", " << pointer << " = " << value;
  progress_.set_prefix(prefix.str() + ": ");
  PreparedScenario prepared = prepare_request(scenario, run);
  const ScenarioOutcome outcome = run_prepared(prepared, run.options);
  const RunMetrics& m = outcome.report.runs.front().metrics;
  StabilityProbe p;
  p.settings = settings;
  p.diverged = m.stability.diverged;
  p.nonfinite = m.stability.nonfinite;
  p.passivity_min_j = m.stability.passivity_energy_min_j;
  p.max_separation_m = m.stability.max_proxy_separation_m;
  p.chatters = m.stability.chatters;
  p.proxy_chatter_m = m.stability.proxy_chatter_m;
  if (m.closed_loop) {
    p.display_energy_min_j = m.closed_loop->display_energy_min_j;
    p.limit_cycle = m.closed_loop->limit_cycles.limit_cycle;
    p.limit_cycle_amplitude_m = m.closed_loop->limit_cycles.amplitude_m;
    p.limit_cycle_frequency_hz = m.closed_loop->limit_cycles.frequency_hz;
  }
  const StabilityResult verdict = judge_stability(m, {criterion_, epsilon_j_});
  p.stable = verdict.stable;
  p.failed = verdict.failed;
  p.reason = verdict.reason;
  std::ostringstream line;
  line << "stability:";
  for (const auto& [pointer, value] : settings) line << " " << pointer << " = " << value;
  line << ": " << (p.stable ? "stable" : "unstable") << " (" << p.reason << ")\n";
  progress_.print_above(std::cerr, line.str());
  return p;
}

std::string bracket_note(const StabilityBracket& bracket, double low, double high) {
  std::ostringstream note;
  if (!bracket.non_monotonic.empty())
    note << bracket.non_monotonic;
  else if (!bracket.largest_stable)
    note << "unstable already at the range's bottom (" << low
         << "): the search assumes stability is lost as the value grows and does not look "
            "below it; give a lower bottom";
  else if (!bracket.smallest_unstable)
    note << "stable up to the range's top (" << high << "); give a higher top to find the limit";
  return note.str();
}

StabilityBracket search_largest_stable(const std::function<StabilityProbe(double)>& probe,
                                       double low, double high, double tolerance) {
  StabilityBracket bracket;
  std::vector<std::pair<double, bool>> verdicts;  // (value, stable) of every probe
  const auto run = [&](double value) {
    bracket.probes.push_back(probe(value));
    verdicts.emplace_back(value, bracket.probes.back().stable);
    return bracket.probes.back().stable;
  };
  if (!run(low)) {
    bracket.smallest_unstable = low;
    return bracket;
  }
  bracket.largest_stable = low;
  if (run(high)) {
    bracket.largest_stable = high;
    return bracket;
  }
  bracket.smallest_unstable = high;
  for (int k = 0;
       k<kMaxProbes&& * bracket.smallest_unstable / *bracket.largest_stable - 1> tolerance; ++k) {
    const double middle = std::sqrt(*bracket.largest_stable * *bracket.smallest_unstable);
    (run(middle) ? bracket.largest_stable : bracket.smallest_unstable) = middle;
  }
  // The bisection assumes the verdict changes once, from stable to unstable,
  // as the value grows. Checked beyond the bracket, one probe on each side
  // where there is room, and over every probe run.
  const double above = std::sqrt(*bracket.smallest_unstable * high);
  if (above / *bracket.smallest_unstable - 1 > tolerance) run(above);
  const double below = std::sqrt(low * *bracket.largest_stable);
  if (*bracket.largest_stable / below - 1 > tolerance) run(below);
  std::optional<double> highest_stable, lowest_unstable;
  for (const auto& [value, stable] : verdicts) {
    if (stable)
      highest_stable = std::max(highest_stable.value_or(value), value);
    else
      lowest_unstable = std::min(lowest_unstable.value_or(value), value);
  }
  if (highest_stable && lowest_unstable && *highest_stable > *lowest_unstable) {
    std::ostringstream note;
    note << "not monotonic: stable at " << *highest_stable << " above unstable at "
         << *lowest_unstable << "; the verdict changes more than once in the range, so no limit "
         << "is reported (the runs are listed)";
    bracket.non_monotonic = note.str();
    bracket.largest_stable.reset();
    bracket.smallest_unstable.reset();
  }
  return bracket;
}

}  // namespace hb
