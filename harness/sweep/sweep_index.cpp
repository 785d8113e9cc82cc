#include "harness/sweep/sweep_index.h"

#include <fstream>
#include <iterator>
#include <stdexcept>

#include "algorithms/core/replacing_file.h"

namespace hb {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

const char* sweep_job_status_name(SweepJobStatus status) {
  switch (status) {
    case SweepJobStatus::kPending:
      return "pending";
    case SweepJobStatus::kOk:
      return "ok";
    case SweepJobStatus::kBudgetFailed:
      return "budget_failed";
    case SweepJobStatus::kFailed:
      return "failed";
    case SweepJobStatus::kCrashed:
      return "crashed";
  }
  return "pending";
}

SweepJobState sweep_job_state_on_disk(const fs::path& run_folder) {
  SweepJobState state;
  std::ifstream in(run_folder / "summary.json");
  if (!in) return state;
  const Json summary = Json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (summary.is_discarded() || !summary.contains("runs") || !summary["runs"].is_array())
    return state;
  if (summary.contains("scenario") && summary["scenario"].is_object() &&
      summary["scenario"].contains("hash") && summary["scenario"]["hash"].is_string())
    state.scenario_hash = summary["scenario"]["hash"].get<std::string>();
  bool pass = true;
  for (const Json& run : summary["runs"]) {
    // An unstable run that was not expected to be fails the job as a budget does.
    const Json::json_pointer verdict_pass("/stability/verdict/pass");
    if (run.contains(verdict_pass) && run[verdict_pass] == false) pass = false;
    if (!run.contains("budgets") || !run["budgets"].is_array()) continue;
    for (const Json& budget : run["budgets"])
      pass = pass && budget.contains("pass") && budget["pass"] == true;
  }
  state.status = pass ? SweepJobStatus::kOk : SweepJobStatus::kBudgetFailed;
  return state;
}

Json sweep_index_json(const SweepSpec& spec, const std::vector<SweepJob>& jobs,
                      const std::vector<SweepJobState>& states, const SweepShard& shard) {
  Json grid = Json::object();
  for (const SweepGridAxis& axis : spec.grid) grid[axis.pointer] = axis.values;
  Json index = {{"name", spec.name},
                {"sweep_file", fs::absolute(spec.path).lexically_normal().string()},
                {"scenarios", spec.scenario_entries},
                {"grid", grid}};
  if (!spec.only_algorithms.empty()) index["only_algorithms"] = spec.only_algorithms;
  index["written_by_shard"] = shard_text(shard);
  Json list = Json::array();
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const SweepJob& job = jobs[i];
    Json values = Json::object();
    for (const auto& [pointer, value] : job.grid_values) values[pointer] = value;
    Json entry = {{"index", job.index},
                  {"name", job.name},
                  {"scenario", spec.scenario_entries[job.scenario_index]},
                  {"grid", values},
                  {"status", sweep_job_status_name(states[i].status)}};
    if (states[i].done_earlier) entry["done_earlier"] = true;
    if (!states[i].detail.empty()) entry["detail"] = states[i].detail;
    list.push_back(std::move(entry));
  }
  index["jobs"] = std::move(list);
  return index;
}

void write_sweep_index(const fs::path& out_dir, const Json& index) {
  const fs::path destination = out_dir / "sweep.json";
  write_file_replacing(destination, index.dump(2) + "\n");
}

bool is_sweep_index_file(const fs::path& path) {
  // A sweep index of a million jobs is some hundreds of MB; more is not one.
  constexpr std::uintmax_t kMaxBytes = std::uintmax_t{1} << 30;
  std::error_code error;
  const std::uintmax_t size = fs::file_size(path, error);
  if (error || size > kMaxBytes) return false;
  std::ifstream in(path, std::ios::binary);
  const Json index = Json::parse(in, nullptr, /*allow_exceptions=*/false);
  return index.is_object() && index.contains("jobs") && index.contains("written_by_shard");
}

}  // namespace hb
