#include "harness/process/liveness_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

namespace hb {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void throw_lock_error(const char* what, const fs::path& file, int error) {
  throw fs::filesystem_error(what, file, std::error_code(error, std::generic_category()));
}

// Opens the lock file without following a symlink; -1 when it cannot be
// opened or is not a regular file (errno says why).
int open_lock_file(const fs::path& file, int flags) {
  const int fd = ::open(file.c_str(), flags | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK, 0600);
  if (fd < 0) return -1;
  struct stat status {};
  if (::fstat(fd, &status) != 0 || !S_ISREG(status.st_mode)) {
    ::close(fd);
    errno = EINVAL;
    return -1;
  }
  return fd;
}

int lock_without_waiting(int fd) {
  int result;
  do {
    result = ::flock(fd, LOCK_EX | LOCK_NB);
  } while (result != 0 && errno == EINTR);
  return result;
}

}  // namespace

LivenessLock::LivenessLock(const fs::path& folder) {
  const fs::path file = folder / kLivenessLockName;
  fd_ = open_lock_file(file, O_RDWR | O_CREAT);
  if (fd_ < 0) throw_lock_error("cannot create the folder's lock file", file, errno);
  if (lock_without_waiting(fd_) != 0) {
    const int error = errno == EWOULDBLOCK ? EBUSY : errno;
    ::close(fd_);
    fd_ = -1;
    throw_lock_error("the folder is in use by another live process", file, error);
  }
}

LivenessLock::~LivenessLock() {
  if (fd_ >= 0) ::close(fd_);
}

void LivenessLock::release_and_remove(const fs::path& folder) {
  ::unlink((folder / kLivenessLockName).c_str());
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

bool remove_if_abandoned(const fs::path& folder,
                         const std::function<void(const fs::path&)>& remove) {
  const int fd = open_lock_file(folder / kLivenessLockName, O_RDONLY);
  if (fd < 0) return false;
  const bool abandoned = lock_without_waiting(fd) == 0;
  if (abandoned) remove(folder);
  ::close(fd);
  return abandoned;
}

}  // namespace hb
