// A worker process: started with its output sent to files, polled without
// blocking, and classified when it ends (exit code or the signal that
// killed it), so a crash in one job is reported, not shared.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace hb {

/// How a process ended.
struct ProcessEnd {
  bool exited = false;  ///< ended by exit(); otherwise killed by `signal`
  int exit_code = 0;    ///< when exited
  int signal = 0;       ///< when killed
  /// "exit code 3" or "killed by signal 11 (Segmentation fault)".
  std::string description() const;
};

class ChildProcess {
 public:
  /// Starts argv[0] (a path, not searched in PATH) with the given arguments,
  /// stdout and stderr written to the two files (created or truncated).
  /// Throws std::runtime_error when the process cannot start.
  ChildProcess(const std::vector<std::string>& argv, const std::filesystem::path& stdout_path,
               const std::filesystem::path& stderr_path);
  /// Kills and reaps a process still running (an interrupted caller leaves
  /// no orphan behind).
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// The end, once the process has ended; nullopt while it runs. Never blocks.
  std::optional<ProcessEnd> poll();
  /// Blocks until the process ends.
  ProcessEnd wait();
  pid_t pid() const { return pid_; }

 private:
  pid_t pid_ = -1;
  std::optional<ProcessEnd> end_;
};

}  // namespace hb
