#include "harness/stability/stability_search.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>

#include "algorithms/core/input_file.h"
#include "hapticbench/input_error.h"
#include "harness/run/scenario_runner.h"
#include "harness/scenario/json_fields.h"
#include "harness/scenario/json_pointer.h"
#include "harness/scenario/scenario.h"
#include "harness/sweep/sweep_jobs.h"
#include "harness/sweep/sweep_spec.h"

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

struct ScenarioProber::Loaded {
  Scenario scenario;
};

ScenarioProber::ScenarioProber(std::string scenario_path, std::string label,
                               StabilityCriterion criterion, double epsilon_j,
                               ProgressDisplay& progress)
    : path_(std::move(scenario_path)),
      label_(std::move(label)),
      criterion_(criterion),
      epsilon_j_(epsilon_j),
      progress_(progress) {
  // The reader every scenario goes through: a regular file only (a FIFO
  // would block), nesting and duplicate keys checked before parsing.
  require_regular_file(path_, "a scenario file (.json)");
  std::ifstream in(path_, std::ios::binary);
  if (!in) throw InputError(path_, "", "cannot open scenario file");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  document_ = parse_json_document(text, path_);
  base_dir_ = std::filesystem::absolute(path_).parent_path().string();
}

ScenarioProber::Loaded ScenarioProber::load(
    const std::vector<std::pair<std::string, double>>& settings) {
  Json document = document_;
  for (const auto& [pointer, value] : settings) {
    const std::optional<std::vector<std::string>> tokens = json_pointer_tokens(pointer);
    const std::optional<std::string> failure =
        tokens ? set_at_pointer(document, *tokens, Json(value))
               : std::optional<std::string>("not a JSON pointer");
    if (failure) throw InputError(path_, pointer, "cannot set it: " + *failure);
  }
  // Only the algorithm asked for: the label must name one.
  const Json& algorithms = document["algorithms"];
  bool found = false;
  if (algorithms.is_array())
    for (const Json& a : algorithms)
      if (a.is_object() && (a.value("label", "") == label_ || a.value("name", "") == label_)) {
        found = true;
        algorithm_ = a.value("name", "");
        const Json params = a.value("params", Json::object());
        integrator_ =
            params.is_object() && params.contains("integrator") && params["integrator"].is_string()
                ? params["integrator"].get<std::string>()
                : "";
      }
  if (!found)
    throw InputError(path_, "/algorithms", "no algorithm labelled or named \"" + label_ + "\"");
  Loaded loaded{load_scenario_json(document.dump(), path_, base_dir_)};
  name_ = loaded.scenario.name;
  return loaded;
}

void ScenarioProber::check(const std::vector<std::pair<std::string, double>>& settings) {
  load(settings);
}

SmallSignalLimit ScenarioProber::small_signal(
    const std::vector<std::pair<std::string, double>>& settings) {
  const Loaded loaded = load(settings);
  const Scenario& scenario = loaded.scenario;
  if (!scenario.closed_loop)
    return {std::nullopt, "open loop: there is no hand and device whose loop to linearise"};
  return small_signal_k_t_limit(*scenario.closed_loop, scenario.context.coupling.b_t,
                                scenario.context.dt_s, algorithm_);
}

StabilityProbe ScenarioProber::probe(const std::vector<std::pair<std::string, double>>& settings) {
  const Loaded loaded = load(settings);
  std::ostringstream prefix;
  prefix << "run " << ++runs_;
  for (const auto& [pointer, value] : settings) prefix << ", " << pointer << " = " << value;
  progress_.set_prefix(prefix.str() + ": ");
  PreparedScenario prepared = prepare_scenario(loaded.scenario, {label_}, &progress_);
  RunOptions options;
  options.progress = &progress_;
  const ScenarioOutcome outcome = run_prepared(prepared, options);
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
