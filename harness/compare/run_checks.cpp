#include "harness/compare/run_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>

#include "harness/compare/timing_checks.h"
#include "harness/metrics/metric_table.h"
#include "harness/metrics/formatted_number.h"

namespace hb {

namespace {

using nlohmann::json;

std::string quantity(double value, const std::string& unit) {
  return formatted("%.3g", value) + " " + unit;
}

// "+20.0%" against a non-zero baseline, else the difference with its unit.
std::string change_text(double baseline, double candidate, const std::string& unit) {
  const double difference = candidate - baseline;
  if (difference == 0) return "0";
  if (baseline != 0) return formatted("%+.1f%%", 100 * difference / std::abs(baseline));
  return formatted("%+.3g", difference) + " " + unit;
}

// A metric compared against a tolerance of max(abs_tol, rel_tol |baseline|).
CheckRow tolerance_row(CheckRow row, std::optional<double> baseline,
                       std::optional<double> candidate, double abs_tol, double rel_tol,
                       const std::string& unit, Better better) {
  if (settle_null_values(row, baseline, candidate)) return row;
  const double difference = *candidate - *baseline;
  const double worse_by = better == Better::kLower ? difference : -difference;
  const double tolerance = std::max(abs_tol, rel_tol * std::abs(*baseline));
  row.change = change_text(*baseline, *candidate, unit);
  row.detail = {{"difference", difference},
                {"tolerance", tolerance},
                {"abs_tol", abs_tol},
                {"rel_tol", rel_tol},
                {"better", better == Better::kLower ? "lower" : "higher"}};
  const std::string direction = better == Better::kLower ? "higher" : "lower";
  if (worse_by > tolerance) {
    row.verdict = Verdict::kRegression;
    row.note = "worse: " + quantity(std::abs(difference), unit) + " " + direction + ", tolerance " +
               quantity(tolerance, unit);
  } else if (worse_by < -tolerance) {
    row.verdict = Verdict::kImproved;
    row.note = "better by " + quantity(std::abs(difference), unit) + ", tolerance " +
               quantity(tolerance, unit);
  } else {
    row.note = "within tolerance " + quantity(tolerance, unit);
  }
  return row;
}

// An energy compared by its part below zero, the energy generated
// (CompareRule::kGeneratedEnergy); the row shows the values themselves.
CheckRow generated_energy_row(CheckRow row, std::optional<double> baseline,
                              std::optional<double> candidate, double abs_tol, double rel_tol,
                              const std::string& unit) {
  if (settle_null_values(row, baseline, candidate)) return row;
  const auto generated = [](double value) { return std::min(value, 0.0); };
  row = tolerance_row(row, generated(*baseline), generated(*candidate), abs_tol, rel_tol, unit,
                      Better::kHigher);
  row.baseline = *baseline;
  row.candidate = *candidate;
  row.change = change_text(*baseline, *candidate, unit);
  if (*baseline >= 0 && *candidate >= 0) row.note = "no energy generated on either side";
  return row;
}

// A count where any increase regresses; `what` says what is counted.
CheckRow count_row(CheckRow row, int64_t baseline, int64_t candidate, std::string_view what) {
  row.baseline = baseline;
  row.candidate = candidate;
  const int64_t difference = candidate - baseline;
  row.change = std::to_string(difference);
  if (difference > 0) row.change.insert(row.change.begin(), '+');
  if (difference > 0) {
    row.verdict = Verdict::kRegression;
    row.note = "more " + std::string(what) + " (any increase fails)";
  } else if (difference < 0) {
    row.verdict = Verdict::kImproved;
    row.note = "fewer " + std::string(what);
  } else {
    row.note = "same count";
  }
  return row;
}

// A flag where false -> true regresses; `what` names the condition.
CheckRow flag_row(CheckRow row, bool baseline, bool candidate, std::string_view what) {
  row.baseline = baseline;
  row.candidate = candidate;
  row.change = baseline == candidate ? "same" : baseline ? "true -> false" : "false -> true";
  if (!baseline && candidate) {
    row.verdict = Verdict::kRegression;
    row.note = "the candidate " + std::string(what) + ", the baseline not";
  } else if (baseline && !candidate) {
    row.verdict = Verdict::kImproved;
    row.note = "the baseline " + std::string(what) + ", the candidate not";
  } else {
    row.note = std::string(candidate ? "" : "not ") + std::string(what) + " on both sides";
  }
  return row;
}

std::string build_name(const BuildContext& context) {
  return context.commit + " " + context.compiler + " " + context.build_type;
}

bool identifies_code(const std::string& commit) {
  constexpr std::string_view kDirty = "-dirty";
  const bool dirty = commit.size() >= kDirty.size() &&
                     commit.compare(commit.size() - kDirty.size(), kDirty.size(), kDirty) == 0;
  return !commit.empty() && commit != "unknown" && !dirty;
}

CheckRow determinism_row(CheckRow row, const ScenarioSummary& baseline_scenario,
                         const RunSummary& baseline, const ScenarioSummary& candidate_scenario,
                         const RunSummary& candidate) {
  const BuildContext& b = baseline_scenario.context;
  const BuildContext& c = candidate_scenario.context;
  row.baseline = baseline.ticks_hash;
  row.candidate = candidate.ticks_hash;
  const bool equal = baseline.ticks_hash == candidate.ticks_hash;
  row.change = equal ? "equal" : "differs";
  const bool strict = same_build(b, c);
  row.detail = {{"same_build", strict}, {"hashes_equal", equal}};
  if (baseline_scenario.scenario_hash != candidate_scenario.scenario_hash) {
    // A changed scenario may change the forces: that is information.
    row.verdict = Verdict::kInfo;
    row.note = std::string("the scenario changed (scenario.hash), so ") +
               (equal ? "the forces could have differed and did not" : "the forces may differ");
    return row;
  }
  if (strict) {
    row.verdict = equal ? Verdict::kPass : Verdict::kRegression;
    row.note = equal ? "same forces on the same build"
                     : "forces differ on the same build (" + build_name(b) + ")";
    return row;
  }
  row.verdict = Verdict::kInfo;
  const std::string forces = equal ? "forces identical" : "forces differ";
  if (b.commit == c.commit && b.compiler == c.compiler && b.build_type == c.build_type)
    row.note =
        "commit " + b.commit + " does not identify the code, so the builds may differ; " + forces;
  else
    row.note = "builds differ (" + build_name(b) + " vs " + build_name(c) + "); " + forces;
  return row;
}

// How a count's or a flag's notes speak of it.
std::string_view counted_as(const MetricDefinition& metric) {
  return metric.counted_as.empty() ? metric.name : metric.counted_as;
}

}  // namespace

bool same_build(const BuildContext& a, const BuildContext& b) {
  return a.commit == b.commit && a.compiler == b.compiler && a.build_type == b.build_type &&
         identifies_code(a.commit);
}

std::vector<CheckRow> compare_runs(const ScenarioSummary& baseline_scenario,
                                   const RunSummary& baseline,
                                   const ScenarioSummary& candidate_scenario,
                                   const RunSummary& candidate, const CompareOptions& options) {
  auto row = [&](const std::string& check) {
    return check_row(baseline_scenario.scenario_name, baseline.label, check);
  };
  std::vector<CheckRow> rows;
  for (const MetricDefinition& metric : metric_table()) {
    if (metric.compare == CompareRule::kNone) continue;
    const std::string check = metric_check_name(metric);
    const std::optional<double> b = baseline.metrics.at(std::string(metric.name));
    const std::optional<double> c = candidate.metrics.at(std::string(metric.name));
    // A metric compared only when present: absent on both sides, no row;
    // on one side only, the row says which.
    if (metric.compare_when_present && (!b || !c)) {
      if (!b && !c) continue;
      CheckRow settled = row(check);
      settle_null_values(settled, b, c);
      rows.push_back(settled);
      continue;
    }
    // The defaults, or the tolerances file's for this metric.
    double abs_tol = metric.abs_tol, rel_tol = options.rel_tol;
    if (const auto given = options.tolerances.find(std::string(metric.name));
        given != options.tolerances.end()) {
      // Given in the metric's own unit (its name's), compared in the summary's.
      if (given->second.abs_tol) abs_tol = *given->second.abs_tol / metric.budget_scale;
      rel_tol = given->second.rel_tol.value_or(rel_tol);
    }
    switch (metric.compare) {
      case CompareRule::kTolerance:
        rows.push_back(tolerance_row(row(check), b, c, abs_tol, rel_tol, std::string(metric.unit),
                                     metric.better));
        break;
      case CompareRule::kGeneratedEnergy:
        rows.push_back(
            generated_energy_row(row(check), b, c, abs_tol, rel_tol, std::string(metric.unit)));
        break;
      case CompareRule::kCount:
        rows.push_back(count_row(row(check), static_cast<int64_t>(b.value_or(0)),
                                 static_cast<int64_t>(c.value_or(0)), counted_as(metric)));
        break;
      case CompareRule::kFlag:
        rows.push_back(
            flag_row(row(check), b.value_or(0) != 0, c.value_or(0) != 0, counted_as(metric)));
        break;
      case CompareRule::kNone:
        break;
    }
  }

  rows.push_back(determinism_row(row("determinism.ticks_hash"), baseline_scenario, baseline,
                                 candidate_scenario, candidate));

  if (options.timing) {
    std::vector<CheckRow> timing =
        timing_checks(baseline_scenario, baseline, candidate_scenario, candidate, options);
    rows.insert(rows.end(), timing.begin(), timing.end());
  }
  // Instruction counts do not depend on the machine's load: compared even
  // with the wall-clock checks off.
  std::vector<CheckRow> instructions =
      instruction_checks(baseline_scenario, baseline, candidate_scenario, candidate, options);
  rows.insert(rows.end(), instructions.begin(), instructions.end());
  return rows;
}

}  // namespace hb
