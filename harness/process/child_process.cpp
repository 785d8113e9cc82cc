#include "harness/process/child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

extern char** environ;

namespace hb {

namespace {

ProcessEnd end_from_status(int status) {
  ProcessEnd end;
  if (WIFEXITED(status)) {
    end.exited = true;
    end.exit_code = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    end.signal = WTERMSIG(status);
  }
  return end;
}

// posix_spawn's actions and attributes, released on every path.
class SpawnFileActions {
 public:
  SpawnFileActions() { posix_spawn_file_actions_init(&actions_); }
  ~SpawnFileActions() { posix_spawn_file_actions_destroy(&actions_); }
  SpawnFileActions(const SpawnFileActions&) = delete;
  SpawnFileActions& operator=(const SpawnFileActions&) = delete;
  posix_spawn_file_actions_t* get() { return &actions_; }

 private:
  posix_spawn_file_actions_t actions_;
};

}  // namespace

std::string ProcessEnd::description() const {
  if (exited) return "exit code " + std::to_string(exit_code);
  if (signal == 0) return "ended with its status lost";
  return "killed by signal " + std::to_string(signal) + " (" + strsignal(signal) + ")";
}

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const ChildOptions& options) {
  if (argv.empty()) throw std::runtime_error("cannot start a process without a program");
  SpawnFileActions actions;
  const int flags = O_WRONLY | O_CREAT | O_TRUNC;
  if (!options.stdout_path.empty())
    posix_spawn_file_actions_addopen(actions.get(), STDOUT_FILENO, options.stdout_path.c_str(),
                                     flags, 0644);
  if (!options.stderr_path.empty())
    posix_spawn_file_actions_addopen(actions.get(), STDERR_FILENO, options.stderr_path.c_str(),
                                     flags, 0644);
  for (const auto& [parent_fd, child_fd] : options.inherit_fds)
    posix_spawn_file_actions_adddup2(actions.get(), parent_fd, child_fd);
  std::vector<char*> arguments;
  for (const std::string& argument : argv) arguments.push_back(const_cast<char*>(argument.c_str()));
  arguments.push_back(nullptr);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  if (options.own_process_group) {
    posix_spawnattr_setpgroup(&attributes, 0);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
  }
  const auto spawn = options.search_path ? &posix_spawnp : &posix_spawn;
  const int error =
      spawn(&pid_, argv[0].c_str(), actions.get(), &attributes, arguments.data(), environ);
  posix_spawnattr_destroy(&attributes);
  if (error != 0) {
    pid_ = -1;
    throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(error));
  }
}

ChildProcess::~ChildProcess() {
  if (pid_ > 0 && !end_) {
    ::kill(pid_, SIGTERM);
    wait();
  }
}

std::optional<ProcessEnd> ChildProcess::poll() {
  if (end_ || pid_ <= 0) return end_;
  int status = 0;
  pid_t result;
  do {
    result = ::waitpid(pid_, &status, WNOHANG);
  } while (result < 0 && errno == EINTR);
  if (result == pid_) end_ = end_from_status(status);
  if (result < 0) end_ = ProcessEnd{};  // reaped elsewhere: its status is lost
  return end_;
}

ProcessEnd ChildProcess::wait() {
  if (end_ || pid_ <= 0) return end_.value_or(ProcessEnd{});
  int status = 0;
  pid_t result;
  do {
    result = ::waitpid(pid_, &status, 0);
  } while (result < 0 && errno == EINTR);
  end_ = result == pid_ ? end_from_status(status) : ProcessEnd{};
  return *end_;
}

}  // namespace hb
