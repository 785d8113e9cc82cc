#include "harness/sweep/worker_pool.h"

#include <chrono>
#include <fstream>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <thread>

#include "harness/process/interrupt.h"

namespace hb {

namespace {

namespace fs = std::filesystem;
using SteadyClock = std::chrono::steady_clock;
constexpr auto kPollPeriod = std::chrono::milliseconds(50);

std::string take_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  std::error_code ignored;
  fs::remove(path, ignored);
  return text;
}

struct RunningWorker {
  std::size_t launch = 0;
  std::unique_ptr<ChildProcess> process;
  SteadyClock::time_point start;
  fs::path stdout_path;
  fs::path stderr_path;
};

}  // namespace

std::vector<WorkerResult> run_worker_processes(const std::vector<WorkerLaunch>& launches,
                                               std::size_t parallel, const fs::path& scratch_dir,
                                               const WorkerCallbacks& callbacks) {
  if (parallel == 0) parallel = 1;
  std::vector<WorkerResult> results(launches.size());
  std::vector<RunningWorker> running;
  std::size_t next = 0;
  while (next < launches.size() || !running.empty()) {
    // Stopped (SIGINT, SIGTERM): the workers still running are stopped by
    // their destructors (SIGTERM, then reaped) as this unwinds.
    throw_if_interrupted();
    while (next < launches.size() && running.size() < parallel) {
      RunningWorker worker;
      worker.launch = next;
      worker.stdout_path = scratch_dir / (std::to_string(next) + ".stdout");
      worker.stderr_path = scratch_dir / (std::to_string(next) + ".stderr");
      worker.start = SteadyClock::now();
      // A start failure unwinds `running`, whose destructors stop the others.
      worker.process = std::make_unique<ChildProcess>(launches[next].argv, worker.stdout_path,
                                                      worker.stderr_path);
      running.push_back(std::move(worker));
      if (callbacks.on_start) callbacks.on_start(next);
      ++next;
    }
    bool any_ended = false;
    for (std::size_t i = 0; i < running.size();) {
      const std::optional<ProcessEnd> end = running[i].process->poll();
      if (!end) {
        ++i;
        continue;
      }
      any_ended = true;
      RunningWorker worker = std::move(running[i]);
      running.erase(running.begin() + static_cast<std::ptrdiff_t>(i));
      WorkerResult& result = results[worker.launch];
      result.end = *end;
      result.seconds = std::chrono::duration<double>(SteadyClock::now() - worker.start).count();
      result.stdout_text = take_file(worker.stdout_path);
      result.stderr_text = take_file(worker.stderr_path);
      if (callbacks.on_finish) callbacks.on_finish(worker.launch, result);
    }
    if (!any_ended && !running.empty()) {
      if (callbacks.on_wait) callbacks.on_wait();
      std::this_thread::sleep_for(kPollPeriod);
    }
  }
  return results;
}

}  // namespace hb
