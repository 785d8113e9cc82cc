#include "harness/cli/plugin_isolation.h"

#include <signal.h>

#include <cstdlib>
#include <iostream>
#include <optional>
#include <stdexcept>

#include "algorithms/registry.h"
#include "harness/cli/child_line_pipe.h"
#include "harness/cli/commands.h"
#include "harness/process/activity_report.h"
#include "harness/process/child_process.h"
#include "harness/process/interrupt.h"
#include "harness/process/memory_limit.h"
#include "harness/process/scratch_folder.h"

namespace hb {

namespace {

// What the child said, line by line.
struct ChildActivity {
  std::string label, origin;      // the last "running" line
  std::optional<int> ended_with;  // "ended <code>": main returned normally

  void take(const std::string& line) {
    if (line.rfind("running ", 0) == 0) {
      const std::string rest = line.substr(8);
      const std::size_t tab = rest.find('\t');
      label = rest.substr(0, tab);
      origin = tab == std::string::npos ? "" : rest.substr(tab + 1);
    } else if (line.rfind("ended ", 0) == 0) {
      ended_with = std::atoi(line.c_str() + 6);
    } else if (line == "idle") {
      label.clear();
      origin.clear();
    }
  }
};

std::string running_text(const ChildActivity& activity) {
  if (activity.label.empty()) return "outside any algorithm's code";
  return "while running label \"" + activity.label + "\"" +
         (activity.origin.empty() ? " (a built-in algorithm)" : " of plugin " + activity.origin);
}

}  // namespace

bool should_isolate_plugins(const std::vector<std::string>& algorithm_names) {
  if (reports_activity()) return false;  // already the child
  for (const std::string& name : algorithm_names)
    if (!algorithm_origin(name).empty()) return true;
  return false;
}

int run_plugins_isolated(const std::string& command, const std::vector<std::string>& args) {
  std::optional<ChildLinePipe> pipe;
  try {
    pipe.emplace();
  } catch (const std::runtime_error&) {
    std::cerr << "internal error: cannot make a pipe for the plugin's process\n";
    return kExitInternal;
  }
  std::vector<std::string> argv = {this_executable().string(), command};
  argv.insert(argv.end(), args.begin(), args.end());
  if (applied_memory_limit_mb() != 0) {
    argv.push_back("--memory-limit");
    argv.push_back(std::to_string(applied_memory_limit_mb()));
  }
  constexpr int kChildFd = 3;
  ::setenv(kActivityFdVariable, std::to_string(kChildFd).c_str(), 1);
  std::optional<ChildProcess> child;
  try {
    child.emplace(argv, ChildOptions{{}, {}, false, {pipe->child_end(kChildFd)}, true});
  } catch (...) {
    ::unsetenv(kActivityFdVariable);
    throw;
  }
  ::unsetenv(kActivityFdVariable);
  pipe->close_write_end();

  ChildActivity activity;
  const auto take = [&activity](const std::string& line) { activity.take(line); };
  bool open = true, passed_on = false;
  std::optional<ProcessEnd> end;
  for (;;) {
    open = pipe->read_lines(50, take);
    // A signal sent to this process only (timeout, a job scheduler) goes on
    // to the child, which stops as a run does.
    if (const int signal = interrupt_signal(); signal != 0 && !passed_on) {
      ::kill(child->pid(), signal);
      passed_on = true;
    }
    if ((end = child->poll())) {
      // What the child wrote before it ended is in the pipe; a process it
      // started may still hold the pipe open, so do not wait for its end.
      if (open) pipe->read_lines(0, take);
      break;
    }
  }

  if (end->exited && activity.ended_with && *activity.ended_with == end->exit_code) {
    if (end->exit_code == kExitInternal && !activity.origin.empty())
      std::cerr << "error: the failure above happened " << running_text(activity) << "\n";
    return end->exit_code;
  }
  std::cerr << "error: hapticbench " << command << " ended (" << end->description() << ") "
            << running_text(activity)
            << ", without finishing its output; what it had not finished was not written\n";
  return kExitInternal;
}

}  // namespace hb
