#include "harness/sweep/sweep_spec.h"

#include <filesystem>
#include <fstream>
#include <iterator>

#include "hapticbench/input_error.h"
#include "harness/scenario/json_fields.h"
#include "harness/scenario/json_pointer.h"
#include "harness/sweep/job_name.h"

namespace hb {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

std::string read_sweep_file(const std::string& path) {
  std::error_code error;
  if (!fs::is_regular_file(path, error))
    throw InputError(path, "", "cannot open sweep file (no such file)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open sweep file");
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void read_scenarios(const JsonField& field, const std::string& sweep_path, SweepSpec& spec) {
  const std::string expected =
      "expected a non-empty array of scenario file paths (relative to the sweep file)";
  const std::size_t count = field.array_size(expected);
  if (count == 0) field.fail(expected);
  const fs::path directory = fs::path(sweep_path).parent_path();
  for (std::size_t i = 0; i < count; ++i) {
    const JsonField entry = field.element(i);
    const std::string written = entry.string(expected);
    if (written.empty()) entry.fail(expected);
    const fs::path relative(written);
    const std::string resolved = relative.is_absolute() || directory.empty()
                                     ? relative.lexically_normal().string()
                                     : (directory / relative).lexically_normal().string();
    std::error_code error;
    if (!fs::is_regular_file(resolved, error))
      entry.fail_with("scenario file \"" + written + "\" not found (looked for " + resolved + ")");
    for (std::size_t j = 0; j < spec.scenario_paths.size(); ++j)
      if (fs::path(spec.scenario_paths[j]) == fs::path(resolved))
        entry.fail_with("scenario \"" + written + "\" is also /scenarios/" + std::to_string(j) +
                        "; list each scenario once");
    spec.scenario_entries.push_back(written);
    spec.scenario_paths.push_back(resolved);
  }
}

void read_grid(const JsonField& field, SweepSpec& spec) {
  field.require_object(
      "expected an object {JSON pointer into the scenario: [values...]}, e.g. "
      "{\"/coupling/k_t\": [1000, 2000]}");
  for (const auto& item : field.json().items()) {
    const JsonField axis_field = field.existing_member(item.key());
    const auto tokens = json_pointer_tokens(item.key());
    if (!tokens)
      axis_field.fail_with("grid key \"" + item.key() +
                           "\" is not a JSON pointer; expected \"/key/...\" (RFC 6901: each "
                           "component after a '/', '~' written as ~0 and '/' as ~1)");
    if (tokens->size() == 1 && tokens->front() == "name")
      axis_field.fail_with(
          "grid key \"/name\": the sweep names each job itself (scenario name and grid values)");
    // A sweep file is data: it may not make a trusted scenario load code.
    if (!tokens->empty() && tokens->front() == "plugins")
      axis_field.fail_with("grid key \"" + item.key() +
                           "\": a sweep may not set a scenario's plugins (shared libraries run "
                           "code); name them in the scenario, or load them with --plugin");
    const std::string expected = "expected a non-empty array of values for \"" + item.key() + "\"";
    const std::size_t count = axis_field.array_size(expected);
    if (count == 0) axis_field.fail(expected);
    SweepGridAxis axis;
    axis.pointer = item.key();
    for (std::size_t i = 0; i < count; ++i) {
      const Json& value = axis_field.element(i).json();
      for (std::size_t j = 0; j < axis.values.size(); ++j)
        if (axis.values[j] == value)
          axis_field.element(i).fail_with("value " + json_value_preview(value) +
                                          " is also element " + std::to_string(j) +
                                          "; list each value once");
      axis.values.push_back(value);
    }
    spec.grid.push_back(std::move(axis));
  }
}

void read_only_algorithms(const JsonField& field, SweepSpec& spec) {
  const std::string expected = "expected a non-empty array of algorithm labels";
  const std::size_t count = field.array_size(expected);
  if (count == 0) field.fail(expected);
  for (std::size_t i = 0; i < count; ++i) {
    const JsonField entry = field.element(i);
    const std::string label = entry.string(expected);
    if (label.empty()) entry.fail(expected);
    for (const std::string& earlier : spec.only_algorithms)
      if (earlier == label) entry.fail_with("label \"" + label + "\" is listed twice");
    spec.only_algorithms.push_back(label);
  }
}

}  // namespace

// Most jobs one sweep may have (each is a run folder; the index lists all).
constexpr double kMaxSweepJobs = 100'000;

SweepSpec parse_sweep_spec(const std::string& json_text, const std::string& path) {
  const Json document = parse_json_document(json_text, path);
  const JsonField root(document, path, "");
  root.require_object("expected a JSON object with the sweep's keys");
  root.reject_unknown_keys({"name", "description", "scenarios", "grid", "only_algorithms"});

  SweepSpec spec;
  spec.path = path;
  const std::string name_expected =
      "expected a non-empty string of letters, digits, '_', '.', '-' and '=' (it names the output "
      "folder)";
  const JsonField name = root.member("name", "the sweep's name");
  spec.name = name.string(name_expected);
  if (!is_safe_folder_name(spec.name)) name.fail(name_expected);
  if (root.has("description")) root.existing_member("description").string("expected a string");
  read_scenarios(root.member("scenarios", "a non-empty array of scenario file paths"), path, spec);
  if (root.has("grid")) read_grid(root.existing_member("grid"), spec);
  // Jobs = scenarios × the product of the grid's axes, counted before any
  // job is made: a few short axes can multiply into billions.
  double jobs = static_cast<double>(spec.scenario_paths.size());
  for (const auto& axis : spec.grid) jobs *= static_cast<double>(axis.values.size());
  if (jobs > kMaxSweepJobs)
    root.member("grid", "")
        .fail_with("gives " + std::to_string(static_cast<long long>(std::min(jobs, 9e18))) +
                   " jobs (scenarios × values of every axis); a sweep has at most " +
                   std::to_string(static_cast<long long>(kMaxSweepJobs)) +
                   " (split it into several sweeps)");
  if (root.has("only_algorithms"))
    read_only_algorithms(root.existing_member("only_algorithms"), spec);
  return spec;
}

SweepSpec load_sweep_spec(const std::string& path) {
  return parse_sweep_spec(read_sweep_file(path), path);
}

}  // namespace hb
