#include "harness/run/run_request.h"


#include "algorithms/registry.h"
#include "hapticbench/input_error.h"
#include "harness/plugins/plugin_loader.h"
#include "harness/process/input_file.h"
#include "harness/scenario/input_error_context.h"
#include "harness/scenario/json_fields.h"
#include "harness/scenario/json_pointer.h"

namespace hb {

namespace {

constexpr const char* kScenarioFile = "a scenario file (.json)";

// The scenario's text with the edits made; the text itself when there are none.
std::string edited_text(const std::string& text, const RunRequest& request) {
  if (request.edits.empty()) return text;
  const std::string& path = request.scenario.path;
  nlohmann::ordered_json document = parse_json_document(text, path);
  for (const ScenarioEdit& edit : request.edits) {
    const std::optional<std::vector<std::string>> tokens = json_pointer_tokens(edit.pointer);
    const std::optional<std::string> failure =
        tokens ? set_at_pointer(document, *tokens, edit.value)
               : std::optional<std::string>("not a JSON pointer");
    if (failure) throw InputError(path, edit.pointer, "cannot set it: " + *failure);
  }
  return document.dump();
}

}  // namespace

ScenarioSource ScenarioSource::file(std::string path) {
  ScenarioSource source;
  source.base_dir = std::filesystem::path(path).parent_path();
  source.path = std::move(path);
  return source;
}

ScenarioSource ScenarioSource::read_now(const std::string& path) {
  ScenarioSource source = file(path);
  source.document = read_regular_file(path, kScenarioFile);
  return source;
}

void load_plugins_and_check_algorithms(Scenario& scenario) {
  bool plugins_not_loaded = false;  // the policy left a named plugin unloaded
  for (const ScenarioPlugin& plugin : scenario.plugins) {
    // Refused by policy: the scenario's field is at fault, not the file.
    if (const std::optional<std::string> refused = scenario_plugin_refusal(plugin.path))
      throw InputError(scenario.path, plugin.pointer, *refused);
    try {
      if (!load_scenario_plugin(plugin.path, plugin.pointer)) plugins_not_loaded = true;
    } catch (const InputError& error) {
      throw with_reference_note(error, scenario.path, plugin.pointer);
    }
  }
  std::vector<std::string> unchecked;  // warnings, said first
  std::vector<AlgorithmSpec> checked;
  for (AlgorithmSpec& spec : scenario.algorithms) {
    if (find_algorithm(spec.name) != nullptr) {
      checked.push_back(std::move(spec));
    } else if (plugins_not_loaded) {
      unchecked.push_back(spec.pointer + "/name: algorithm \"" + spec.name +
                          "\" is not checked: it is not built in, and the scenario's plugins, "
                          "which may register it, are not loaded here (they would run code)");
    } else {
      throw InputError(scenario.path, spec.pointer + "/name", unknown_algorithm_message(spec.name));
    }
  }
  scenario.algorithms = std::move(checked);
  scenario.warnings.insert(scenario.warnings.begin(), unchecked.begin(), unchecked.end());
}

Scenario read_scenario(const RunRequest& request) {
  const ScenarioSource& source = request.scenario;
  const std::string text =
      source.document ? *source.document : read_regular_file(source.path, kScenarioFile);
  Scenario scenario = load_scenario_json(edited_text(text, request), source.path, source.base_dir);
  load_plugins_and_check_algorithms(scenario);
  if (!request.ground_truth) scenario.reference.switch_off_oracle();
  return scenario;
}

PreparedScenario prepare_request(const Scenario& scenario, const RunRequest& request) {
  PreparedScenario prepared =
      prepare_scenario(scenario, request.algorithms, request.options.progress);
  if (request.schedule) use_recorded_schedules(prepared, *request.schedule);
  return prepared;
}

RunResult run_request(const RunRequest& request) {
  RunResult result;
  result.scenario = read_scenario(request);
  PreparedScenario prepared = prepare_request(result.scenario, request);
  result.outcome = run_prepared(prepared, request.options);
  return result;
}

}  // namespace hb
