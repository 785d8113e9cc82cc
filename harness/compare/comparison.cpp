#include "harness/compare/comparison.h"

#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include "hapticbench/input_error.h"
#include "harness/compare/run_checks.h"
#include "harness/metrics/metric_table.h"
#include "harness/process/input_file.h"
#include "harness/scenario/json_fields.h"

namespace hb {

CheckRow check_row(const std::string& scenario, const std::string& label,
                   const std::string& check) {
  CheckRow row;
  row.scenario = scenario;
  row.label = label;
  row.check = check;
  return row;
}

bool settle_null_values(CheckRow& row, std::optional<double> baseline,
                        std::optional<double> candidate) {
  row.baseline = baseline ? nlohmann::json(*baseline) : nlohmann::json(nullptr);
  row.candidate = candidate ? nlohmann::json(*candidate) : nlohmann::json(nullptr);
  if (!baseline && !candidate) {
    row.verdict = Verdict::kNotApplicable;
    row.note = "null on both sides: does not apply";
    return true;
  }
  if (!candidate) {
    row.verdict = Verdict::kFailure;
    row.note = "metric disappeared: null in the candidate";
    return true;
  }
  if (!baseline) {
    row.verdict = Verdict::kInfo;
    row.note = "metric appeared: null in the baseline";
    return true;
  }
  return false;
}

namespace {

CheckRow presence_row(const std::string& scenario, const std::string& label, bool in_baseline) {
  CheckRow row;
  row.scenario = scenario;
  row.label = label;
  row.check = label.empty() ? "scenario" : "run";
  const std::string what = label.empty() ? "scenario" : "run";
  if (in_baseline) {
    row.baseline = "present";
    row.candidate = "absent";
    row.verdict = Verdict::kFailure;
    row.note = what + " missing from the candidate";
  } else {
    row.baseline = "absent";
    row.candidate = "present";
    row.verdict = Verdict::kNew;
    row.note = "new " + what + ": only in the candidate";
  }
  return row;
}

// "PREFIX/key a → b" for each top-level key whose value differs between two
// objects (a missing key reads "absent").
void add_changed_keys(const nlohmann::ordered_json& a, const nlohmann::ordered_json& b,
                      const std::string& prefix, std::vector<std::string>& changes) {
  const auto text = [](const nlohmann::ordered_json& object, const std::string& key) {
    return object.is_object() && object.contains(key) ? object.at(key).dump() : "absent";
  };
  std::set<std::string> keys;
  for (const nlohmann::ordered_json* object : {&a, &b})
    if (object->is_object())
      for (const auto& item : object->items()) keys.insert(item.key());
  for (const std::string& key : keys)
    if (text(a, key) != text(b, key))
      changes.push_back(prefix + "/" + key + " " + text(a, key) + " → " + text(b, key));
}

// What the two summaries show changed in the scenario: the coupling and the
// parameters of each label both ran.
std::vector<std::string> scenario_changes(const ScenarioSummary& baseline,
                                          const ScenarioSummary& candidate) {
  std::vector<std::string> changes;
  add_changed_keys(baseline.coupling, candidate.coupling, "/coupling", changes);
  for (const RunSummary& run : baseline.runs)
    if (const RunSummary* other = candidate.find_run(run.label))
      add_changed_keys(run.params, other->params, run.label + " params", changes);
  return changes;
}

CheckRow scenario_hash_row(const ScenarioSummary& baseline, const ScenarioSummary& candidate) {
  CheckRow row;
  row.scenario = baseline.scenario_name;
  row.check = "scenario.hash";
  row.baseline = baseline.scenario_hash;
  row.candidate = candidate.scenario_hash;
  if (baseline.scenario_hash == candidate.scenario_hash) {
    row.change = "equal";
    row.note = "same scenario file, meshes and trace";
  } else {
    row.change = "differs";
    row.verdict = Verdict::kInfo;
    const std::vector<std::string> changes = scenario_changes(baseline, candidate);
    std::string listed;
    for (const std::string& change : changes) listed += (listed.empty() ? "" : "; ") + change;
    row.note = "the scenario or a file it names changed (" +
               (listed.empty() ? std::string("not in the coupling or the parameters") : listed) +
               "): metrics may differ for that reason";
  }
  return row;
}

}  // namespace

const char* verdict_name(Verdict verdict) {
  switch (verdict) {
    case Verdict::kPass:
      return "pass";
    case Verdict::kImproved:
      return "improved";
    case Verdict::kNotApplicable:
      return "n/a";
    case Verdict::kInfo:
      return "info";
    case Verdict::kNew:
      return "new";
    case Verdict::kRegression:
      return "regression";
    case Verdict::kFailure:
      return "failure";
  }
  return "?";
}

bool is_failing(Verdict verdict) {
  return verdict == Verdict::kRegression || verdict == Verdict::kFailure;
}

std::size_t Comparison::failing_rows() const {
  std::size_t count = 0;
  for (const CheckRow& row : rows) count += is_failing(row.verdict) ? 1 : 0;
  return count;
}

std::vector<CheckRow> compare_scenarios(const ScenarioSummary& baseline,
                                        const ScenarioSummary& candidate,
                                        const CompareOptions& options) {
  std::vector<CheckRow> rows;
  rows.push_back(scenario_hash_row(baseline, candidate));
  for (const RunSummary& run : baseline.runs) {
    const RunSummary* match = candidate.find_run(run.label);
    if (!match) {
      rows.push_back(presence_row(baseline.scenario_name, run.label, true));
      continue;
    }
    std::vector<CheckRow> checks = compare_runs(baseline, run, candidate, *match, options);
    rows.insert(rows.end(), checks.begin(), checks.end());
  }
  for (const RunSummary& run : candidate.runs)
    if (!baseline.find_run(run.label))
      rows.push_back(presence_row(baseline.scenario_name, run.label, false));
  return rows;
}

Comparison compare_summary_sets(const SummarySet& baseline, const SummarySet& candidate,
                                const CompareOptions& options, ProgressDisplay* progress) {
  Comparison comparison;
  comparison.baseline_path = baseline.path;
  comparison.candidate_path = candidate.path;
  comparison.options = options;

  if (!baseline.is_suite && !candidate.is_suite) {
    const ScenarioSummary& b = baseline.scenarios.front();
    const ScenarioSummary& c = candidate.scenarios.front();
    if (b.scenario_name != c.scenario_name)
      throw InputError(c.source, "/scenario/name",
                       "different scenarios: baseline " + b.scenario_name + ", candidate " +
                           c.scenario_name + " (baseline " + b.source + ")");
  }
  if (progress) {
    progress->task(baseline.path + " against " + candidate.path);
    progress->phase("comparing", static_cast<int64_t>(baseline.scenarios.size()), false,
                    "scenarios");
  }
  for (std::size_t i = 0; i < baseline.scenarios.size(); ++i) {
    const ScenarioSummary& b = baseline.scenarios[i];
    if (progress) progress->advance(static_cast<int64_t>(i));
    const ScenarioSummary* c = candidate.find_scenario(b.scenario_name);
    if (!c) {
      comparison.rows.push_back(presence_row(b.scenario_name, "", true));
      continue;
    }
    std::vector<CheckRow> rows = compare_scenarios(b, *c, options);
    comparison.rows.insert(comparison.rows.end(), rows.begin(), rows.end());
  }
  if (progress) progress->finish_task();
  for (const ScenarioSummary& c : candidate.scenarios)
    if (!baseline.find_scenario(c.scenario_name))
      comparison.rows.push_back(presence_row(c.scenario_name, "", false));
  return comparison;
}

std::map<std::string, MetricTolerance> read_tolerances_file(const std::string& path) {
  const nlohmann::ordered_json document =
      parse_json_document(read_regular_file(path, "a tolerances file (.json)"), path);
  const JsonField root(document, path, "");
  root.require_object("expected {metric name: {\"rel_tol\": x, \"abs_tol\": y}}");
  std::map<std::string, MetricTolerance> tolerances;
  for (const auto& item : document.items()) {
    const JsonField field = root.existing_member(item.key());
    const MetricDefinition* metric = find_metric(item.key());
    if (metric == nullptr || (metric->compare != CompareRule::kTolerance &&
                              metric->compare != CompareRule::kGeneratedEnergy)) {
      std::string known;
      for (const MetricDefinition& m : metric_table())
        if (m.compare == CompareRule::kTolerance || m.compare == CompareRule::kGeneratedEnergy)
          known += (known.empty() ? "" : ", ") + std::string(m.name);
      field.fail(std::string(metric == nullptr ? "unknown metric" : "not compared by tolerance") +
                 "; metrics compared by tolerance: " + known);
    }
    MetricTolerance tolerance;
    const std::string expected = "expected a number >= 0";
    if (item.value().is_number()) {
      tolerance.rel_tol = field.non_negative_number(expected);
    } else {
      field.require_object("expected {\"rel_tol\": x, \"abs_tol\": y} or a number (rel_tol)");
      field.reject_unknown_keys({"rel_tol", "abs_tol"});
      if (field.has("rel_tol"))
        tolerance.rel_tol = field.existing_member("rel_tol").non_negative_number(expected);
      if (field.has("abs_tol"))
        tolerance.abs_tol = field.existing_member("abs_tol").non_negative_number(
            expected + " in the metric's unit (" +
            std::string(metric->budget_unit.empty() ? metric->unit : metric->budget_unit) + ")");
    }
    tolerances[item.key()] = tolerance;
  }
  return tolerances;
}

std::string display_value(const nlohmann::json& value) {
  if (value.is_null()) return "null";
  if (value.is_boolean()) return value.get<bool>() ? "true" : "false";
  if (value.is_string()) return value.get<std::string>();
  if (value.is_number_integer() || value.is_number_unsigned()) return value.dump();
  if (value.is_number()) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", value.get<double>());
    return text;
  }
  return value.dump();
}

}  // namespace hb
