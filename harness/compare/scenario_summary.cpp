#include "harness/compare/scenario_summary.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>

#include "hapticbench/input_error.h"
#include "harness/metrics/metric_table.h"
#include "harness/process/input_file.h"
#include "harness/scenario/json_fields.h"

namespace hb {

namespace {

using Json = nlohmann::ordered_json;

constexpr const char* kNumberOrNull = "expected a number or null";

std::optional<double> number_or_null(const JsonField& parent, const std::string& key) {
  const JsonField field = parent.member(key, "a number or null");
  if (field.json().is_null()) return std::nullopt;
  return field.number(kNumberOrNull);
}

JsonField object_member(const JsonField& parent, const std::string& key) {
  const JsonField field = parent.member(key, "an object");
  field.require_object("expected an object");
  return field;
}

std::string string_member(const JsonField& parent, const std::string& key) {
  return parent.member(key, "a string").string("expected a string");
}

// A compared metric of the table, found by its JSON pointer in the run. A
// metric compared only when present may be missing (or sit below a null
// object); any other must be there, typed by its rule.
std::optional<double> read_metric(const JsonField& run, const MetricDefinition& metric) {
  std::vector<std::string> keys;
  const std::string pointer(metric.json_pointer);
  for (std::size_t start = 1; start <= pointer.size();) {
    const std::size_t end = std::min(pointer.find('/', start), pointer.size());
    keys.push_back(pointer.substr(start, end - start));
    start = end + 1;
  }
  JsonField field = run;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const bool last = i + 1 == keys.size();
    if (metric.compare_when_present &&
        (!field.has(keys[i]) || field.existing_member(keys[i]).json().is_null()))
      return std::nullopt;
    if (!last) {
      field = object_member(field, keys[i]);
      continue;
    }
    switch (metric.compare) {
      case CompareRule::kFlag:
        return field.member(keys[i], "true or false").boolean("expected true or false") ? 1.0 : 0.0;
      case CompareRule::kCount:
        return static_cast<double>(
            field.member(keys[i], "a count")
                .integer(0, std::numeric_limits<int64_t>::max(),
                         "expected a non-negative whole number of " + std::string(metric.unit)));
      default:
        return number_or_null(field, keys[i]);
    }
  }
  return std::nullopt;
}

bool present(const JsonField& parent, const std::string& key) {
  return parent.has(key) && !parent.existing_member(key).json().is_null();
}

// timing.noise and timing.instructions: newer keys, absent or null in older
// summaries and where they were not measured.
void read_noise_and_instructions(const JsonField& timing, RunSummary& r) {
  if (present(timing, "noise")) {
    const JsonField noise = object_member(timing, "noise");
    r.timing_quiet = noise.member("quiet", "true or false").boolean("expected true or false");
    r.calibration_ns = number_or_null(noise, "calibration_before_ns");
    char text[160];
    std::snprintf(text, sizeof text, "cpu share %.2f, calibration spread %.2f, load %.2f",
                  number_or_null(noise, "cpu_share").value_or(0),
                  number_or_null(noise, "calibration_spread").value_or(0),
                  number_or_null(noise, "load_average_1m").value_or(0));
    r.noise_text = text;
  }
  if (present(timing, "instructions")) {
    const JsonField instructions = object_member(timing, "instructions");
    r.instructions_step_per_tick = number_or_null(instructions, "step_per_tick_mean");
    r.instructions_slow_update_per_call = number_or_null(instructions, "slow_update_per_call_mean");
  }
}

RunSummary read_run(const JsonField& run) {
  run.require_object("expected an object (one algorithm run)");
  RunSummary r;
  r.label = string_member(run, "label");
  if (run.has("params")) r.params = run.existing_member("params").json();
  r.ticks_file = run.has("ticks_file")
                     ? run.existing_member("ticks_file").file_name_inside("expected a file name")
                     : "ticks_" + r.label + ".csv";

  const JsonField timing = object_member(run, "timing");
  const JsonField step_ns = object_member(timing, "step_ns");
  r.step_ns_p50 = number_or_null(step_ns, "p50");
  r.step_ns_p99 = number_or_null(step_ns, "p99");
  const JsonField sample = timing.member("step_ns_sample", "an array of step times (ns)");
  const std::size_t count = sample.array_size("expected an array of step times (ns)");
  r.step_ns_sample.reserve(count);
  for (std::size_t i = 0; i < count; ++i)
    r.step_ns_sample.push_back(static_cast<double>(sample.element(i).integer(
        0, int64_t{1} << 53, "expected a whole, non-negative number of ns")));

  read_noise_and_instructions(timing, r);

  for (const MetricDefinition& metric : metric_table())
    if (metric.compare != CompareRule::kNone)
      r.metrics[std::string(metric.name)] = read_metric(run, metric);

  r.ticks_hash = string_member(object_member(run, "determinism"), "ticks_hash");
  return r;
}

std::string read_file_text(const std::filesystem::path& path) {
  require_regular_file(path, "a summary.json");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", "cannot open file");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(path.string(), "", "cannot read file");
  return text;
}

}  // namespace

const RunSummary* ScenarioSummary::find_run(const std::string& label) const {
  for (const RunSummary& run : runs)
    if (run.label == label) return &run;
  return nullptr;
}

ScenarioSummary scenario_summary_from_json(const Json& document, const std::string& source) {
  const JsonField root(document, source, "");
  root.require_object("expected a summary object");
  // The version first: a summary of another schema may lack every other key.
  const JsonField version = root.member("schema_version", "the summary schema version (1)");
  const int64_t schema =
      version.integer(std::numeric_limits<int64_t>::min(), std::numeric_limits<int64_t>::max(),
                      "expected a whole number");
  if (schema != kComparedSchemaVersion)
    version.fail_with("schema_version " + std::to_string(schema) +
                      " is not supported; this hapticbench compares schema_version " +
                      std::to_string(kComparedSchemaVersion));

  ScenarioSummary summary;
  summary.source = source;
  const JsonField context = object_member(root, "context");
  summary.context.commit = string_member(context, "commit");
  summary.context.compiler = string_member(context, "compiler");
  summary.context.build_type = string_member(context, "build_type");
  summary.context.cpu = string_member(context, "cpu");

  const JsonField scenario = object_member(root, "scenario");
  summary.scenario_name = string_member(scenario, "name");
  summary.scenario_hash = string_member(scenario, "hash");
  if (scenario.has("coupling")) summary.coupling = scenario.existing_member("coupling").json();

  const JsonField runs = root.member("runs", "an array of algorithm runs");
  const std::size_t count = runs.array_size("expected an array of algorithm runs");
  std::set<std::string> labels;
  for (std::size_t i = 0; i < count; ++i) {
    summary.runs.push_back(read_run(runs.element(i)));
    if (!labels.insert(summary.runs.back().label).second)
      runs.element(i).existing_member("label").fail_with(
          "label \"" + summary.runs.back().label + "\" is used by an earlier run; runs are " +
          "matched by label, so each must be unique");
  }
  return summary;
}

ScenarioSummary read_scenario_summary(const std::filesystem::path& summary_file) {
  const std::string source = summary_file.string();
  return scenario_summary_from_json(parse_json_document(read_file_text(summary_file), source),
                                    source);
}

}  // namespace hb
