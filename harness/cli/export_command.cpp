// `hapticbench export --format gbench RUN_DIR... [--out FILE]`: run folders
// as Google Benchmark JSON, so that tools reading that format (its
// compare.py, continuous-benchmarking dashboards, CI actions) take
// hapticbench results unchanged. One benchmark entry per scenario and
// algorithm label: iterations = ticks, real_time = cpu_time = the mean CPU
// time per tick of both loops (timing.cpu_per_tick_ns.mean) in ns, and
// counters for step percentiles, error and instruction counts.
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "algorithms/core/replacing_file.h"
#include "hapticbench/input_error.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/cli/option_table.h"
#include "harness/cli/run_folder_search.h"
#include "harness/metrics/metric_table.h"
#include "harness/output/output_ownership.h"
#include "harness/scenario/json_fields.h"

namespace hb {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

// A JSON value at `path` in `document`, or null where any key is missing.
Json at(const Json& document, std::initializer_list<const char*> path) {
  const Json* node = &document;
  for (const char* key : path) {
    if (!node->is_object() || !node->contains(key)) return nullptr;
    node = &(*node)[key];
  }
  return *node;
}

Json benchmark_entry(const Json& summary, const Json& run, std::size_t family) {
  const std::string name =
      at(summary, {"scenario", "name"}).get<std::string>() + "/" + run["label"].get<std::string>();
  Json cpu_mean = at(run, {"timing", "cpu_per_tick_ns", "mean"});
  if (!cpu_mean.is_number()) cpu_mean = at(run, {"timing", "step_ns", "p50"});
  Json entry = {{"name", name},
                {"family_index", family},
                {"per_family_instance_index", 0},
                {"run_name", name},
                {"run_type", "iteration"},
                {"repetitions", 1},
                {"repetition_index", 0},
                {"threads", 1},
                {"iterations", at(run, {"timing", "ticks"})},
                {"real_time", cpu_mean},
                {"cpu_time", cpu_mean},
                {"time_unit", "ns"}};
  // Counters: numbers only (Google Benchmark's counters are doubles).
  const std::pair<const char*, Json> counters[] = {
      {"step_p50_ns", at(run, {"timing", "step_ns", "p50"})},
      {"step_p99_ns", at(run, {"timing", "step_ns", "p99"})},
      {"cpu_per_tick_p99_ns", at(run, {"timing", "cpu_per_tick_ns", "p99"})},
      {"over_budget_ticks", at(run, {"timing", "over_budget"})},
      {"force_err_rms_n", at(run, {"accuracy", "force_err_rms_n"})},
      {"penetration_max_m", at(run, {"accuracy", "penetration_max_m"})},
      {"nonfinite_ticks", at(run, {"stability", "nonfinite"})},
      {"instructions_step_per_tick", at(run, {"timing", "instructions", "step_per_tick_mean"})},
      {"instructions_slow_update_per_call",
       at(run, {"timing", "instructions", "slow_update_per_call_mean"})},
  };
  for (const auto& [key, value] : counters)
    if (value.is_number()) entry[key] = value;
  // The headline accuracy the metric table names (as the report's axis):
  // the first role that applies, in the summary's unit.
  for (const char* role : {"accuracy", "accuracy_fallback"}) {
    const MetricDefinition* metric = headline_metric(role);
    const Json::json_pointer pointer(metric ? std::string(metric->json_pointer) : "");
    if (metric && run.contains(pointer) && run[pointer].is_number()) {
      entry["headline_accuracy"] = run[pointer];
      // Counters are numbers: 1 where the fallback (penetration) stood in.
      entry["headline_accuracy_is_fallback"] = std::string_view(role) == "accuracy" ? 0 : 1;
      break;
    }
  }
  const Json diverged = at(run, {"stability", "diverged"});
  if (diverged.is_boolean()) entry["diverged"] = diverged.get<bool>() ? 1 : 0;
  return entry;
}

struct ExportArguments {
  std::vector<fs::path> inputs;
  std::optional<fs::path> out;
};

using Table = OptionTable<ExportArguments>;

const Table& export_table() {
  static const Table table(
      {"export", {}, {}, {}},
      {Table::positional("RUN_DIR", "a run folder or a folder of run folders (a suite, a sweep)", 1,
                         kAnyCount, &ExportArguments::inputs),
       Table::value("--format", "FORMAT",
                    "gbench: Google Benchmark's JSON (the only format so far)",
                    [](ExportArguments&, const std::string& format) {
                      if (format != "gbench")
                        throw UsageError{"--format: expected gbench, got \"" + format + "\""};
                    })
           .required(),
       Table::value("--out", "FILE",
                    "write there (default: standard output); replaces only a file export wrote",
                    &ExportArguments::out)});
  return table;
}

}  // namespace

int export_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const auto parse_result = parse_command_line([&] { return export_table().parse(args); },
                                               export_table().usage(), exit_code);
  if (!parse_result) return exit_code;
  const ExportArguments& parsed = *parse_result;
  const std::vector<fs::path>& inputs = parsed.inputs;
  const std::optional<fs::path>& out = parsed.out;
  // A file export wrote names itself in its context.
  const auto exported = [](const fs::path& path) {
    std::ifstream in(path);
    std::string head(4096, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    return head.find("\"hapticbench_export\"") != std::string::npos;
  };
  if (out) require_replaceable_file(*out, "benchmark export", exported);

  Json benchmarks = Json::array();
  Json first_context = nullptr;
  for (const fs::path& folder : find_run_folders(inputs)) {
    const Json summary = read_run_summary(folder / "summary.json");
    if (first_context.is_null()) first_context = at(summary, {"context"});
    for (const Json& run : summary["runs"])
      benchmarks.push_back(benchmark_entry(summary, run, benchmarks.size()));
  }
  const Json load = at(first_context, {"load_average_1m"});
  const Json build_type = at(first_context, {"build_type"});
  Json context = {
      {"date", at(first_context, {"date"})},
      {"host_name", ""},
      {"executable", "hapticbench"},
      {"num_cpus", at(first_context, {"logical_cores"}).is_number()
                       ? at(first_context, {"logical_cores"})
                       : Json(0)},
      {"mhz_per_cpu", 0},
      {"cpu_scaling_enabled", at(first_context, {"cpu_governor"}) != "performance"},
      {"caches", Json::array()},
      {"load_avg", load.is_number() ? Json::array({load}) : Json::array()},
      {"library_build_type", build_type.is_string() && build_type == "Debug" ? "debug" : "release"},
      {"hapticbench_export",
       {{"cpu", at(first_context, {"cpu"})},
        {"commit", at(first_context, {"commit"})},
        {"compiler", at(first_context, {"compiler"})},
        {"real_time",
         "mean CPU time per tick of both loops (timing.cpu_per_tick_ns.mean); iterations = "
         "ticks"}}}};
  const std::string text = Json{{"context", context}, {"benchmarks", benchmarks}}.dump(2) + "\n";
  if (!out) {
    std::cout << text;
    return kExitOk;
  }
  write_file_replacing(*out, text);
  std::cerr << "export: " << benchmarks.size() << " benchmarks -> " << out->string() << "\n";
  return kExitOk;
}

const CommandSyntax& export_syntax() { return export_table().syntax(); }

}  // namespace hb
