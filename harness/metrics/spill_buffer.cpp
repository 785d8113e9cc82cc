#include "harness/metrics/spill_buffer.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <string>
#include <system_error>

#include "algorithms/core/temporary_folder.h"

namespace hb {

namespace {
[[noreturn]] void fail(const std::string& what, const std::filesystem::path& path) {
  throw std::filesystem::filesystem_error(what, path,
                                          std::error_code(errno, std::generic_category()));
}
}  // namespace

SpillFile::SpillFile() {
  const std::filesystem::path folder = temporary_folder();
  std::string name = (folder / "hapticbench-spill-XXXXXX").string();
  fd_ = ::mkstemp(name.data());
  if (fd_ < 0) fail("cannot create a temporary file for a run's per-tick values in", folder);
  ::unlink(name.c_str());  // anonymous: gone when closed, whatever ends the process
}

SpillFile::~SpillFile() {
  if (fd_ >= 0) ::close(fd_);
}

void SpillFile::append(const void* data, std::size_t bytes) {
  const char* next = static_cast<const char*>(data);
  while (bytes > 0) {
    const ssize_t written = ::pwrite(fd_, next, bytes, static_cast<off_t>(size_));
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0)
      fail("cannot write a run's per-tick values to a temporary file in", temporary_folder());
    next += written;
    bytes -= static_cast<std::size_t>(written);
    size_ += static_cast<uint64_t>(written);
  }
}

void SpillFile::read(uint64_t offset, void* data, std::size_t bytes) const {
  char* next = static_cast<char*>(data);
  while (bytes > 0) {
    const ssize_t got = ::pread(fd_, next, bytes, static_cast<off_t>(offset));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0)
      fail("cannot read back a run's per-tick values from a temporary file in", temporary_folder());
    next += got;
    bytes -= static_cast<std::size_t>(got);
    offset += static_cast<uint64_t>(got);
  }
}

}  // namespace hb
