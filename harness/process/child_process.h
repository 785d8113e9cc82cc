// A worker process: started with its output sent to files, polled without
// blocking, and classified when it ends (exit code or the signal that
// killed it), so a crash in one job is reported, not shared.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
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

/// Where a child's output goes and how it is found.
struct ChildOptions {
  /// Files for stdout and stderr (created or truncated; "/dev/null" to
  /// drop it); empty: the parent's.
  std::filesystem::path stdout_path, stderr_path;
  /// Look argv[0] up on PATH when it has no slash (else it is a path).
  bool search_path = false;
  /// (parent fd, child fd): the child gets the parent's fd under that number
  /// (a pipe's write end as the child's fd 3, say).
  std::vector<std::pair<int, int>> inherit_fds;
  /// In a process group of its own: a terminal's Ctrl-C reaches only the
  /// parent, which passes it on once.
  bool own_process_group = false;
};

class ChildProcess {
 public:
  /// Starts argv[0] with the given arguments as `options` say. Throws
  /// std::runtime_error when the process cannot start.
  ChildProcess(const std::vector<std::string>& argv, const ChildOptions& options);
  /// Starts argv[0] (a path, not searched in PATH), stdout and stderr
  /// written to the two files.
  ChildProcess(const std::vector<std::string>& argv, const std::filesystem::path& stdout_path,
               const std::filesystem::path& stderr_path)
      : ChildProcess(argv, ChildOptions{stdout_path, stderr_path, false, {}, false}) {}
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
