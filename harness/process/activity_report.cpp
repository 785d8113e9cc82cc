#include "harness/process/activity_report.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>

namespace hb {

namespace {

int& activity_fd() {
  static int fd = -1;
  return fd;
}

}  // namespace

void take_activity_report_fd() {
  const char* value = std::getenv(kActivityFdVariable);
  if (value == nullptr) return;
  char* end = nullptr;
  const long fd = std::strtol(value, &end, 10);
  ::unsetenv(kActivityFdVariable);
  if (end == value || *end != '\0' || fd < 3 || fd > 1024) return;
  if (::fcntl(static_cast<int>(fd), F_SETFD, FD_CLOEXEC) != 0) return;
  activity_fd() = static_cast<int>(fd);
}

bool reports_activity() { return activity_fd() >= 0; }

void report_activity(const std::string& line) {
  if (activity_fd() < 0) return;
  const std::string text = line + "\n";
  ssize_t written;
  do {
    written = ::write(activity_fd(), text.data(), text.size());
  } while (written < 0 && errno == EINTR);
}

}  // namespace hb
