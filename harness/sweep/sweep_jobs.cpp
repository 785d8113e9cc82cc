#include "harness/sweep/sweep_jobs.h"

#include <fstream>
#include <iterator>
#include <map>
#include <optional>

#include "hapticbench/input_error.h"
#include "harness/process/input_file.h"
#include "harness/scenario/input_error_context.h"
#include "harness/scenario/json_fields.h"
#include "harness/sweep/job_name.h"

namespace hb {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

std::string read_text(const std::string& path) {
  require_regular_file(path, "a scenario file (.json)");  // a FIFO would block
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open scenario file");
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace

namespace {

// Mesh, trace and plugin file paths as absolute paths, so that the job's
// JSON means the same from any folder.
void make_file_paths_absolute(Json& scenario, const fs::path& base_dir) {
  auto absolute = [&](Json& holder, const char* key) {
    if (!holder.is_object() || !holder.contains(key) || !holder[key].is_string()) return;
    const fs::path path(holder[key].get<std::string>());
    if (path.empty() || path.is_absolute()) return;
    holder[key] = (base_dir / path).lexically_normal().string();
  };
  if (scenario.contains("scene") && scenario["scene"].is_array())
    for (Json& object : scenario["scene"]) absolute(object, "mesh");
  if (scenario.contains("tool")) absolute(scenario["tool"], "mesh");
  if (scenario.contains("trace")) absolute(scenario["trace"], "file");
  if (scenario.contains("plugins") && scenario["plugins"].is_array())
    for (Json& entry : scenario["plugins"])
      if (entry.is_string() && !entry.get<std::string>().empty() &&
          fs::path(entry.get<std::string>()).is_relative())
        entry = (base_dir / entry.get<std::string>()).lexically_normal().string();
}

std::string algorithm_label(const Json& entry) {
  if (!entry.is_object()) return "";
  if (entry.contains("label") && entry["label"].is_string()) return entry["label"];
  if (entry.contains("name") && entry["name"].is_string()) return entry["name"];
  return "";
}

std::string joined_labels(const Json& algorithms) {
  std::string labels;
  for (const Json& entry : algorithms)
    labels += (labels.empty() ? "" : ", ") + algorithm_label(entry);
  return labels;
}

// The scenario files as JSON, each checked to be an object with a name.
struct ScenarioDocument {
  Json json;
  std::string name;
  fs::path base_dir;
};

ScenarioDocument read_scenario_document(const std::string& path) {
  ScenarioDocument document;
  document.json = parse_json_document(read_text(path), path);
  const JsonField root(document.json, path, "");
  root.require_object("expected a JSON object with the scenario's keys");
  document.name = root.member("name", "the scenario's name").string("expected a string");
  document.base_dir = fs::absolute(path).parent_path().lexically_normal();
  return document;
}

// Odometer over the grid: the last axis turns fastest.
bool advance(std::vector<std::size_t>& position, const std::vector<SweepGridAxis>& grid) {
  for (std::size_t axis = grid.size(); axis-- > 0;) {
    if (++position[axis] < grid[axis].values.size()) return true;
    position[axis] = 0;
  }
  return false;
}

std::string grid_key_location(const std::string& pointer) {
  return "/grid/" + json_pointer_token(pointer);
}

}  // namespace

void SweepErrors::add(const InputError& error) {
  for (const Entry& entry : entries_)
    if (entry.jobs.empty() && std::string(entry.error.what()) == error.what()) return;
  entries_.push_back({error, {}});
}

void SweepErrors::add_for_job(const std::string& job_name, const InputError& error) {
  for (Entry& entry : entries_)
    if (!entry.jobs.empty() && std::string(entry.error.what()) == error.what()) {
      entry.jobs.push_back(job_name);
      return;
    }
  entries_.push_back({error, {job_name}});
}

void SweepErrors::throw_if_any() const {
  if (entries_.empty()) return;
  // How many job names a repeated error lists before "and N more".
  static constexpr std::size_t kJobsNamed = 3;
  auto job_list = [](const std::vector<std::string>& jobs) {
    std::string text = jobs.size() == 1 ? "job " : "jobs ";
    for (std::size_t i = 0; i < std::min(jobs.size(), kJobsNamed); ++i)
      text += (i == 0 ? "" : ", ") + jobs[i];
    if (jobs.size() > kJobsNamed)
      text += " and " + std::to_string(jobs.size() - kJobsNamed) + " more";
    return text;
  };
  if (entries_.size() == 1) {
    const Entry& only = entries_.front();
    if (only.jobs.empty()) throw only.error;
    throw InputError(sweep_file_, job_list(only.jobs), only.error.what());
  }
  std::string text = std::to_string(entries_.size()) + " errors:";
  for (const Entry& entry : entries_) {
    // The sweep file is named once, in front of the list.
    const InputError& error = entry.error;
    const std::string own = error.source() == sweep_file_ && !error.location().empty()
                                ? error.location() + ": " + error.message()
                                : std::string(error.what());
    text += "\n  " + (entry.jobs.empty() ? own : job_list(entry.jobs) + ": " + own);
  }
  throw InputError(sweep_file_, "", text);
}

std::vector<SweepJob> expand_sweep_jobs(const SweepSpec& spec) {
  SweepErrors errors(spec.path);
  std::vector<SweepJob> jobs;
  std::vector<bool> label_used(spec.only_algorithms.size(), false);
  std::map<std::string, std::size_t> job_of_name;
  for (std::size_t s = 0; s < spec.scenario_paths.size(); ++s) {
    ScenarioDocument document;
    try {
      document = read_scenario_document(spec.scenario_paths[s]);
    } catch (const InputError& error) {
      errors.add(with_reference_note(error, spec.path, "/scenarios/" + std::to_string(s)));
      continue;
    }
    std::vector<bool> axis_failed(spec.grid.size(), false);
    // Labels are looked for in the file's algorithms, whether or not its
    // jobs expand (so that a bad grid key is not also reported as labels).
    if (document.json.contains("algorithms") && document.json["algorithms"].is_array())
      for (const Json& entry : document.json["algorithms"])
        for (std::size_t i = 0; i < spec.only_algorithms.size(); ++i)
          if (algorithm_label(entry) == spec.only_algorithms[i]) label_used[i] = true;
    const std::string& scenario_entry = spec.scenario_entries[s];
    const std::string scenario_named = scenario_entry == spec.scenario_paths[s]
                                           ? scenario_entry
                                           : scenario_entry + " (" + spec.scenario_paths[s] + ")";
    std::vector<std::size_t> position(spec.grid.size(), 0);
    do {
      bool job_failed = false;
      SweepJob job;
      job.index = jobs.size();
      job.scenario_index = s;
      job.scenario_path = spec.scenario_paths[s];
      job.base_dir = document.base_dir;
      job.scenario = document.json;
      for (std::size_t axis = 0; axis < spec.grid.size(); ++axis) {
        const SweepGridAxis& grid_axis = spec.grid[axis];
        const Json& value = grid_axis.values[position[axis]];
        job.grid_values.emplace_back(grid_axis.pointer, value);
        const std::optional<std::string> failure =
            set_at_pointer(job.scenario, *json_pointer_tokens(grid_axis.pointer), value);
        if (failure) {
          if (!axis_failed[axis])  // the same for every value of the key
            errors.add(InputError(spec.path, grid_key_location(grid_axis.pointer),
                                  "grid key \"" + grid_axis.pointer +
                                      "\" does not exist in scenario " + scenario_named + ": " +
                                      *failure + "; only the last component may be new"));
          axis_failed[axis] = true;
          job_failed = true;
        }
      }
      if (job_failed) continue;

      if (!spec.only_algorithms.empty()) {
        Json& algorithms = job.scenario["algorithms"];
        if (!algorithms.is_array()) {
          errors.add(InputError(
              spec.path, "/only_algorithms",
              "scenario " + scenario_named + " has no \"algorithms\" array to choose labels from"));
          continue;
        }
        Json kept = Json::array();
        for (const Json& entry : algorithms) {
          const std::string label = algorithm_label(entry);
          for (std::size_t i = 0; i < spec.only_algorithms.size(); ++i)
            if (label == spec.only_algorithms[i]) {
              kept.push_back(entry);
              label_used[i] = true;
            }
        }
        if (kept.empty()) {
          errors.add(InputError(
              spec.path, "/only_algorithms",
              "scenario " + scenario_named +
                  " has none of these labels (its labels: " + joined_labels(algorithms) + ")"));
          continue;
        }
        algorithms = std::move(kept);
      }

      job.name = sweep_job_name(document.name, job.grid_values);
      if (!is_safe_folder_name(job.name)) {
        errors.add(InputError(spec.path, "/scenarios/" + std::to_string(s),
                              "job name \"" + job.name +
                                  "\" cannot name a folder (at most 255 letters, digits, '_', "
                                  "'.', '-' and '='); shorten the scenario name or the grid keys"));
        continue;
      }
      const auto [earlier, inserted] = job_of_name.emplace(job.name, job.index);
      if (!inserted) {
        errors.add(InputError(spec.path, "/grid",
                              "jobs " + std::to_string(earlier->second) + " and " +
                                  std::to_string(job.index) + " are both named \"" + job.name +
                                  "\"; their run folders would collide (grid values that differ "
                                  "only in characters a folder name drops, or two scenarios with "
                                  "one name)"));
        continue;
      }
      job.scenario["name"] = job.name;
      make_file_paths_absolute(job.scenario, job.base_dir);
      jobs.push_back(std::move(job));
    } while (advance(position, spec.grid));
  }
  for (std::size_t i = 0; i < spec.only_algorithms.size(); ++i)
    if (!label_used[i])
      errors.add(
          InputError(spec.path, "/only_algorithms/" + std::to_string(i),
                     "label \"" + spec.only_algorithms[i] + "\" is in none of the scenarios"));
  errors.throw_if_any();
  return jobs;
}

std::string sweep_job_scenario_text(const SweepJob& job) { return job.scenario.dump(2) + "\n"; }

InputError sweep_job_error(const SweepSpec& spec, const SweepJob& job, const InputError& error) {
  return InputError(spec.path, "job " + job.name, error.what());
}

}  // namespace hb
