#include "harness/run/instruction_counting.h"

#include <stdlib.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "hapticbench/input_error.h"
#include "harness/process/child_process.h"
#include "harness/process/scratch_folder.h"
#include "harness/replay/instruction_count.h"
#include "harness/run/run_request.h"
#include "harness/scenario/scenario.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

fs::path find_on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream folders(path ? path : "/usr/bin:/bin");
  for (std::string folder; std::getline(folders, folder, ':');) {
    const fs::path candidate = fs::path(folder.empty() ? "." : folder) / program;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return {};
}

std::string tail_of(const fs::path& file) {
  std::ifstream in(file);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return text.size() > 2000 ? text.substr(text.size() - 2000) : text;
}

// Replays whatever it is given without looking at it, only counting the
// ticks for the progress display as the timing pass does.
class IgnoringObserver : public TickObserver {
 public:
  explicit IgnoringObserver(ProgressDisplay* progress) : progress_(progress) {}
  void on_tick(const TickRecord& record) override {
    if (progress_) progress_->advance(record.device->tick + 1);
  }

 private:
  ProgressDisplay* progress_;
};

}  // namespace

void count_instructions(const std::string& scenario_path, const AlgorithmSelection& only,
                        ScenarioOutcome& outcome) {
  const fs::path valgrind = find_on_path("valgrind");
  if (valgrind.empty())
    throw InputError("", "--instructions",
                     "needs valgrind on PATH (Debian package valgrind; scripts/setup installs it)");
  const ScratchFolder folder("hapticbench-instructions");
  fs::create_directory(folder.path() / "dumps");
  for (std::size_t i = 0; i < outcome.report.runs.size(); ++i)
    if (!outcome.report.runs[i].schedule_file.empty())
      std::ofstream(folder.path() / outcome.report.runs[i].schedule_file)
          << outcome.schedule_csv[i];

  std::vector<std::string> argv = {
      valgrind.string(),
      "--tool=callgrind",
      "--instr-atstart=no",
      "--collect-atstart=no",
      "--dump-instr=no",
      "--dump-line=no",
      "--callgrind-out-file=" + (folder.path() / "dumps" / "callgrind.%p").string(),
      this_executable().string(),
      "count-instructions",
      scenario_path,
      "--schedule",
      folder.path().string(),
      "--out",
      (folder.path() / "counts.json").string()};
  for (const std::string& name : only) {
    argv.push_back("--algo");
    argv.push_back(name);
  }
  ChildProcess child(argv, folder.path() / "stdout.txt", folder.path() / "stderr.txt");
  const ProcessEnd end = child.wait();
  if (!end.exited || end.exit_code != 0)
    throw std::runtime_error("counting instructions under valgrind failed (" + end.description() +
                             "):\n" + tail_of(folder.path() / "stderr.txt"));

  std::ifstream in(folder.path() / "counts.json");
  const nlohmann::json counts = nlohmann::json::parse(in);
  const std::map<std::string, int64_t> dumps = read_callgrind_dumps(folder.path() / "dumps");
  for (AlgorithmRun& run : outcome.report.runs) {
    if (!counts.contains(run.label)) continue;
    const auto step = dumps.find("step:" + run.label);
    if (step == dumps.end())
      throw std::runtime_error("callgrind wrote no count for the steps of " + run.label);
    InstructionCounts c;
    c.ticks = counts[run.label].at("ticks").get<int64_t>();
    c.step_total = step->second;
    c.has_slow_loop = counts[run.label].at("slow_updates").is_number();
    if (c.has_slow_loop) {
      const auto slow = dumps.find("slow:" + run.label);
      if (slow == dumps.end())
        throw std::runtime_error("callgrind wrote no count for the slow updates of " + run.label);
      c.slow_updates = counts[run.label]["slow_updates"].get<int64_t>();
      c.slow_update_total = slow->second;
    }
    run.instructions = c;
  }
}

void count_instructions_here(const std::string& scenario_path, const AlgorithmSelection& only,
                             const std::string& schedule_dir, const std::string& out,
                             ProgressDisplay* progress) {
  RunRequest request;
  request.scenario = ScenarioSource::file(scenario_path);
  request.algorithms = only;
  request.ground_truth = false;  // no ground truth is counted, so none is built
  request.schedule = schedule_dir;
  const Scenario scenario = read_scenario(request);
  PreparedScenario prepared = prepare_request(scenario, request);

  start_instrumentation();
  nlohmann::json counts = nlohmann::json::object();
  for (PreparedAlgorithm& algorithm : prepared.algorithms) {
    ReplaySettings settings = algorithm.replay;
    if (algorithm.replayed_schedule) {
      settings.slow_loop_timing = SlowLoopTiming::kReplayed;
      settings.replayed_schedule = algorithm.replayed_schedule.get();
    }
    IgnoringObserver ignore(progress);
    const int64_t ticks = scenario.trajectory.ticks();
    if (progress) progress->task(scenario.name + " / " + algorithm.spec->label);
    // A first pass warms what a renderer builds lazily; the counted passes
    // then see the state every later replay sees.
    if (progress) progress->phase("warm-up pass", ticks, true);
    replay(*algorithm.renderer, scenario.trajectory, settings, ignore);
    settings.counted = CountedCalls::kStep;
    if (progress) progress->phase("counted pass", ticks, true);
    const SlowLoopSchedule schedule =
        replay(*algorithm.renderer, scenario.trajectory, settings, ignore);
    dump_instruction_counts("step:" + algorithm.spec->label);
    nlohmann::json entry = {{"ticks", scenario.trajectory.ticks()}, {"slow_updates", nullptr}};
    if (algorithm.has_slow_loop()) {
      settings.counted = CountedCalls::kSlowUpdate;
      if (progress) progress->phase("counted slow-loop pass", ticks, true);
      replay(*algorithm.renderer, scenario.trajectory, settings, ignore);
      dump_instruction_counts("slow:" + algorithm.spec->label);
      entry["slow_updates"] = schedule.updates.size();
    }
    counts[algorithm.spec->label] = entry;
    if (progress) progress->finish_task();
  }
  std::ofstream(out) << counts.dump() << "\n";
}

}  // namespace hb
