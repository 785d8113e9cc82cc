// The trace of a scenario: a trace file (CSV or TUM, in the units it is
// written in) or a generator, resampled to the 1 kHz clock. A trace file is
// hashed into the scenario's content hash.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>

#include "hapticbench/content_hash.h"
#include "hapticbench/input_error.h"
#include "harness/scenario/input_error_context.h"
#include "harness/scenario/json_params.h"
#include "harness/scenario/scenario_reader.h"
#include "harness/trace/generators.h"
#include "harness/trace/trace.h"

namespace hb::scenario_detail {

namespace {

constexpr double kMaxTraceDurationS = kMaxRunDurationS;

}  // namespace

// Whole ticks of the 1 kHz clock in a duration.
int64_t ScenarioReader::read_duration_ticks(const JsonField& field) const {
  const std::string expected = "expected a duration in [0.001, 3600] s";
  const double seconds = field.number(expected);
  if (!(seconds >= 1 / kTicksPerSecond && seconds <= kMaxTraceDurationS)) field.fail(expected);
  return std::llround(seconds * kTicksPerSecond);
}

void ScenarioReader::read_trace(const JsonField& field, Scenario& scenario) {
  field.require_object("expected {\"generator\": NAME, ...} or {\"file\": PATH, ...}");
  const bool has_file = field.has("file");
  if (has_file == field.has("generator"))
    field.fail_with(has_file ? "give either \"file\" or \"generator\", not both"
                             : "missing; expected \"generator\": NAME or \"file\": PATH");
  if (has_file) {
    field.reject_unknown_keys({"file", "format", "duration_s", "units"});
    const JsonField file_field = field.existing_member("file");
    const std::string path = existing_file(file_field, "trace file");
    const std::string extension = std::filesystem::path(path).extension().string();
    std::string format = extension == ".tum" || extension == ".txt" ? "tum" : "csv";
    if (field.has("format")) format = field.existing_member("format").choice({"csv", "tum"});
    const int64_t ticks =
        field.has("duration_s") ? read_duration_ticks(field.existing_member("duration_s")) : 0;
    std::optional<TraceUnits> units;
    if (field.has("units")) {
      const JsonField units_field = field.existing_member("units");
      units = parse_trace_units(units_field.string(kTraceUnitsExpected));
      if (!units) units_field.fail(kTraceUnitsExpected);
    }
    try {
      Trace trace = read_trace_file(
          path, format == "tum" ? TraceFileFormat::kTum : TraceFileFormat::kHapticbenchCsv, units);
      scenario.trace_description =
          "file " + path + " (" + format + trace_reading_note(trace.info) + ")";
      for (const std::string& warning : trace_plausibility_warnings(trace))
        load_warnings_.push_back(file_field.pointer() + ": " + path + ": " + warning);
      scenario.trajectory = DeviceTrajectory::of_trace(std::move(trace), ticks);
      scenario_hash_.add(file_content_hash(path));
    } catch (const InputError& error) {
      // An error about the trace's samples is the trace file's.
      const InputError located =
          error.source().empty() ? InputError(path, error.location(), error.message()) : error;
      throw with_reference_note(located, path_, file_field.pointer());
    }
  } else {
    field.reject_unknown_keys({"generator", "duration_s", "seed", "params"});
    const JsonField name_field = field.existing_member("generator");
    const std::string name = name_field.string("expected a generator name");
    GeneratorRequest request;
    const int64_t ticks = read_duration_ticks(
        field.member("duration_s", "the trace's length in seconds, in [0.001, 3600]"));
    request.duration_s = static_cast<double>(ticks) / kTicksPerSecond;
    if (field.has("seed"))
      request.seed = static_cast<uint64_t>(field.existing_member("seed").integer(
          0, std::numeric_limits<int64_t>::max(), "expected a whole number >= 0"));
    request.params = ParamSet("/trace/params");
    if (field.has("params"))
      request.params =
          param_set_from_json(field.existing_member("params").json(), "/trace/params", path_);
    try {
      GeneratedTrace trace = make_generated_trace(name, request, name_field.pointer());
      scenario.trajectory = DeviceTrajectory(std::move(trace.source), ticks);
    } catch (const InputError& error) {
      throw with_default_source(error, path_);
    }
    scenario.trace_description =
        "generator " + name + " (seed " + std::to_string(request.seed) + ")";
  }
  if (scenario.trajectory.ticks() == 0)
    field.fail_with("the trace gives no samples on the 1 kHz clock");
}

}  // namespace hb::scenario_detail
