#include "harness/cli/doc_tables.h"

#include <filesystem>
#include <string>

#include "algorithms/registry.h"
#include "harness/metrics/metric_table.h"
#include "harness/scenario/scenario.h"
#include "harness/trace/generators.h"
#include "harness/trace/trace.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

const char* better_text(Better better) { return better == Better::kLower ? "lower" : "higher"; }

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

}  // namespace

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

}  // namespace hb
