#include "harness/cli/child_line_pipe.h"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <stdexcept>

namespace hb {

ChildLinePipe::ChildLinePipe() {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("cannot make a pipe");
  read_fd_ = fds[0];
  write_fd_ = fds[1];
  ::fcntl(read_fd_, F_SETFL, O_NONBLOCK);
}

ChildLinePipe::~ChildLinePipe() {
  close_write_end();
  if (read_fd_ >= 0) ::close(read_fd_);
}

void ChildLinePipe::close_write_end() {
  if (write_fd_ >= 0) ::close(write_fd_);
  write_fd_ = -1;
}

bool ChildLinePipe::read_lines(int timeout_ms,
                               const std::function<void(const std::string&)>& line) {
  pollfd waiting{read_fd_, POLLIN, 0};
  ::poll(&waiting, open_ ? 1 : 0, timeout_ms);
  // At most 64 KiB a call: a child that writes without pause still lets
  // the caller look at its signals.
  char buffer[4096];
  for (int reads = 0; open_ && reads < 16; ++reads) {
    const ssize_t got = ::read(read_fd_, buffer, sizeof buffer);
    if (got > 0) {
      partial_.append(buffer, static_cast<std::size_t>(got));
      continue;
    }
    if (got < 0 && errno == EINTR) continue;
    if (got < 0 && errno == EAGAIN) break;
    open_ = false;  // end of file, or a pipe that cannot be read
  }
  for (std::size_t end; (end = partial_.find('\n')) != std::string::npos;) {
    const std::string complete = partial_.substr(0, end);
    partial_.erase(0, end + 1);
    line(complete);
  }
  return open_;
}

}  // namespace hb
