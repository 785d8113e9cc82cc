// A pipe from a child process to this one, read line by line: the child
// gets the write end as one of its fds (ChildOptions::inherit_fds), and
// this process reads what it writes without ever blocking longer than it
// asks, so that it can watch for a stop signal or the child's end between
// reads. The report renderer writes its progress this way; a command run
// in a child for its plugins says what it runs (plugin_isolation.h).
#pragma once

#include <functional>
#include <string>
#include <utility>

namespace hb {

class ChildLinePipe {
 public:
  /// Throws std::runtime_error when no pipe can be made.
  ChildLinePipe();
  /// Closes what is still open.
  ~ChildLinePipe();
  ChildLinePipe(const ChildLinePipe&) = delete;
  ChildLinePipe& operator=(const ChildLinePipe&) = delete;

  /// The write end as the child's fd `child_fd`: an entry of
  /// ChildOptions::inherit_fds.
  std::pair<int, int> child_end(int child_fd) const { return {write_fd_, child_fd}; }

  /// Closes this process's copy of the write end, once the child has its
  /// own: the pipe ends when the child's copies close.
  void close_write_end();

  /// Waits up to `timeout_ms` for what the child writes (the whole time
  /// once the pipe has ended) and hands each complete line, without its
  /// '\n', to `line`. False once the pipe has ended.
  bool read_lines(int timeout_ms, const std::function<void(const std::string&)>& line);

 private:
  int read_fd_ = -1, write_fd_ = -1;
  bool open_ = true;
  std::string partial_;  ///< a line not yet ended by '\n'
};

}  // namespace hb
