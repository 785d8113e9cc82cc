#include "algorithms/core/replacing_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>
#include <vector>

namespace hb {

namespace {

[[noreturn]] void throw_errno(int error, const std::filesystem::path& path) {
  throw std::filesystem::filesystem_error("cannot write", path,
                                          std::error_code(error, std::generic_category()));
}

}  // namespace

TemporarySibling::TemporarySibling(std::filesystem::path destination)
    : destination_(std::move(destination)) {
  std::filesystem::path folder = destination_.parent_path();
  if (folder.empty()) folder = ".";
  // A file name has at most 255 bytes: the destination's name is cut short
  // in the temporary one where it would not fit (a 245-byte name is the
  // user's right; the suffix is ours).
  constexpr std::size_t kMaxName = 255;
  const std::string suffix = ".tmp-XXXXXX";
  std::string stem = destination_.filename().string();
  if (1 + stem.size() + suffix.size() > kMaxName) stem.resize(kMaxName - 1 - suffix.size());
  std::string name = (folder / ("." + stem + suffix)).string();
  std::vector<char> buffer(name.begin(), name.end());
  buffer.push_back('\0');
  fd_ = ::mkstemp(buffer.data());
  if (fd_ < 0) throw_errno(errno, destination_);
  path_ = std::filesystem::path(buffer.data());
  // mkstemp makes the file private (0600); the destination gets the mode
  // any new file of the user's would.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd_, 0666 & ~mask);
}

TemporarySibling::~TemporarySibling() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) ::unlink(path_.c_str());
}

void TemporarySibling::write(std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t written = ::write(fd_, bytes.data(), bytes.size());
    if (written < 0) {
      if (errno == EINTR) continue;
      throw_errno(errno, path_);
    }
    bytes.remove_prefix(static_cast<std::size_t>(written));
  }
}

void TemporarySibling::commit() {
  // No fsync: a full disk shows in write() (ext4's delayed allocation
  // reserves the blocks there, tmpfs allocates them), and a run folder's
  // dozen small files would each wait for the disk.
  const int closed = ::close(fd_);
  fd_ = -1;
  if (closed != 0) throw_errno(errno, destination_);
  if (::rename(path_.c_str(), destination_.c_str()) != 0) throw_errno(errno, destination_);
  committed_ = true;
}

void write_file_replacing(const std::filesystem::path& destination, std::string_view bytes) {
  TemporarySibling file(destination);
  file.write(bytes);
  file.commit();
}

}  // namespace hb
