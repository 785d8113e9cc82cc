// hapticbench list [SCENARIO_DIR]: algorithms, generators and the scenarios
// shipped in scenarios/. The tables the docs hold, as Markdown: list
// --metrics (docs/metric-table.md), --generators (the generators'
// parameters, traces/README.md), --params (the algorithms' parameters,
// docs/algorithms/README.md), --limits (the plausible ranges,
// docs/limits.md).
#include <algorithm>
#include <filesystem>
#include <iostream>

#include "algorithms/registry.h"
#include "hapticbench/input_error.h"
#include "harness/cli/commands.h"
#include "harness/metrics/metric_table.h"
#include "harness/scenario/scenario.h"
#include "harness/trace/generators.h"
#include "harness/trace/trace.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

const char* better_text(Better better) { return better == Better::kLower ? "lower" : "higher"; }

void print_metric_table(std::ostream& out) {
  out << "| metric (budget name) | unit (budget, console, report) | summary.json, in a run | "
         "its unit | better | budget | compare | what it is |\n"
         "| --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (const MetricDefinition& m : metric_table()) {
    const std::string_view unit = m.budget_unit.empty() ? m.unit : m.budget_unit;
    out << "| `" << m.name << "` | " << unit << " | `" << m.json_pointer << "` | " << m.unit
        << " | " << better_text(m.better) << " | " << (m.budget ? "yes" : "-") << " | "
        << compare_rule_meaning(m.compare) << (m.compare_when_present ? " (when present)" : "")
        << " | " << m.description << " |\n";
  }
}

// Every generator's parameters as its code asks for them: each generator
// runs once, for a 1 s trace, with no parameters given.
void print_generator_parameters(std::ostream& out) {
  out << "| generator | parameter | default (1 s trace) | accepted |\n| --- | --- | --- | --- |\n";
  for (const GeneratorEntry& entry : generator_table()) {
    GeneratorRequest request;
    request.params = ParamSet("/trace/params");
    make_generated_trace(std::string(entry.name), request, "/trace/generator");
    for (const ParamDeclaration& p : request.params.declared())
      out << "| `" << entry.name << "` | `" << p.key << "` | " << p.default_value << " | "
          << p.accepted << " |\n";
  }
}

// The scene every algorithm is built on to list its parameters: defaults that
// depend on the tool (the proxy mass is the tool's mass) are this tool's.
constexpr const char* kParameterProbeScenario = R"({
  "name": "parameter_probe",
  "scene": [{ "shape": { "type": "box", "size": [0.1, 0.1, 0.02] },
              "pose": { "p": [0, 0, -0.01], "q": [1, 0, 0, 0] } }],
  "tool": { "shape": { "type": "sphere", "radius": 0.02, "subdivisions": 2 }, "density": 1000 },
  "trace": { "generator": "rest", "duration_s": 0.01, "params": { "p": [0, 0, 0.03] } },
  "algorithms": [{ "name": "coupling_only" }]
})";

// Every algorithm's parameters as its code asks for them: each algorithm is
// built once on the probe scene with no parameters given. A parameter read
// only under another parameter's non-default value is not listed.
void print_algorithm_parameters(std::ostream& out) {
  const Scenario probe =
      load_scenario_json(kParameterProbeScenario, "parameter probe scenario", fs::path());
  out << "| algorithm | parameter | default (a 2 cm sphere tool, 1000 kg/m³) | accepted |\n"
         "| --- | --- | --- | --- |\n";
  for (const AlgorithmEntry& entry : algorithm_table()) {
    const ParamSet params("/algorithms/0/params");
    entry.create(probe.context, params);
    for (const ParamDeclaration& p : params.declared())
      out << "| `" << entry.name << "` | `" << p.key << "` | " << p.default_value << " | "
          << p.accepted << " |\n";
  }
}

void print_plausible_ranges(std::ostream& out) {
  out << "| field | plausible range | unit | why |\n| --- | --- | --- | --- |\n";
  for (const PlausibleRange& range : plausible_ranges())
    out << "| `" << range.pointer << "` | " << range.low << " – " << range.high << " | "
        << range.unit << " | " << range.why << " |\n";
  out << "\n| trace file | plausible up to | unit | why |\n| --- | --- | --- | --- |\n";
  for (const TracePlausibleLimit& limit : trace_plausible_limits())
    out << "| " << limit.quantity << " | " << limit.high << " | " << limit.unit << " | "
        << limit.why << " |\n";
}

}  // namespace

int list_command(const std::vector<std::string>& args) {
  if (args.size() == 1 && args.front() == "--metrics") {
    print_metric_table(std::cout);
    return kExitOk;
  }
  if (args.size() == 1 && args.front() == "--generators") {
    print_generator_parameters(std::cout);
    return kExitOk;
  }
  if (args.size() == 1 && args.front() == "--params") {
    print_algorithm_parameters(std::cout);
    return kExitOk;
  }
  if (args.size() == 1 && args.front() == "--limits") {
    print_plausible_ranges(std::cout);
    return kExitOk;
  }
  std::string scenario_root = "scenarios";
  if (!args.empty()) {
    scenario_root = args.front();
    std::error_code error;
    // A folder the user names must exist; the default may be absent.
    if (!fs::is_directory(scenario_root, error))
      throw InputError(scenario_root, "", "not a folder; expected a folder of scenario files");
  }

  std::cout << "algorithms:\n";
  for (const AlgorithmEntry& entry : algorithm_table()) {
    const std::string plugin = algorithm_origin(entry.name);
    std::cout << "  " << entry.name << "  -  " << entry.summary
              << (plugin.empty() ? "" : " [plugin " + plugin + "]") << "\n";
  }
  std::cout << "generators:\n";
  for (const GeneratorEntry& entry : generator_table())
    std::cout << "  " << entry.name << "  -  " << entry.summary << "\n";

  // Sweep files live in a folder named "sweeps"; everything else is a scenario.
  std::vector<std::string> scenarios, sweeps;
  std::error_code error;
  if (fs::is_directory(scenario_root, error)) {
    for (const auto& entry : fs::recursive_directory_iterator(scenario_root, error)) {
      if (entry.path().extension() != ".json") continue;
      const bool is_sweep = entry.path().parent_path().filename() == "sweeps";
      (is_sweep ? sweeps : scenarios).push_back(entry.path().string());
    }
  }
  std::sort(scenarios.begin(), scenarios.end());
  std::sort(sweeps.begin(), sweeps.end());
  std::cout << "scenarios (" << scenario_root << "/):\n";
  if (scenarios.empty())
    std::cout << "  (none found; run from the project folder or pass a folder)\n";
  for (const std::string& file : scenarios) std::cout << "  " << file << "\n";
  std::cout << "sweeps:\n";
  if (sweeps.empty()) std::cout << "  (none)\n";
  for (const std::string& file : sweeps) std::cout << "  " << file << "\n";
  return kExitOk;
}

}  // namespace hb
