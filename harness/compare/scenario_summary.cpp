#include "harness/compare/scenario_summary.h"

#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>

#include "algorithms/core/input_error.h"
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

// oracle.embree.penetration_max_m where the run has an Embree oracle; the
// oracle block and its backends are null when they were not used.
std::optional<double> embree_penetration(const JsonField& run) {
  if (!run.has("oracle") || run.existing_member("oracle").json().is_null()) return std::nullopt;
  const JsonField oracle = object_member(run, "oracle");
  if (!oracle.has("embree") || oracle.existing_member("embree").json().is_null())
    return std::nullopt;
  return number_or_null(object_member(oracle, "embree"), "penetration_max_m");
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
  r.ticks_file = run.has("ticks_file")
                     ? run.existing_member("ticks_file").string("expected a file name")
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

  const JsonField accuracy = object_member(run, "accuracy");
  r.force_err_rms_n = number_or_null(accuracy, "force_err_rms_n");
  r.force_dir_err_max_deg = number_or_null(accuracy, "force_dir_err_max_deg");
  r.torque_err_rms_nm = number_or_null(accuracy, "torque_err_rms_nm");
  r.penetration_max_m = number_or_null(accuracy, "penetration_max_m");
  r.penetration_rms_m = number_or_null(accuracy, "penetration_rms_m");
  r.oracle_embree_penetration_max_m = embree_penetration(run);

  const JsonField stability = object_member(run, "stability");
  r.nonfinite = stability.member("nonfinite", "a count of ticks")
                    .integer(0, std::numeric_limits<int64_t>::max(),
                             "expected a non-negative whole number of ticks");
  r.diverged = stability.member("diverged", "true or false").boolean("expected true or false");
  r.passivity_energy_min_j = number_or_null(stability, "passivity_energy_min_j");
  r.force_jump_max_n = number_or_null(stability, "force_jump_max_n");

  r.ticks_hash = string_member(object_member(run, "determinism"), "ticks_hash");
  return r;
}

std::string read_file_text(const std::filesystem::path& path) {
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
