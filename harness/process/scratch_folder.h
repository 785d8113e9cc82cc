// A private temporary folder for one command's scratch files (worker
// output, callgrind dumps), removed on every path out of its scope.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "harness/process/liveness_lock.h"

namespace hb {

class ScratchFolder {
 public:
  /// Creates <temp>/<prefix>-<pid>-XXXXXX holding a marker file and a lock
  /// held for the folder's life, after removing the folders of that form
  /// whose lock no live process holds (SIGKILL, a second SIGINT: hundreds
  /// of MB of ticks each). Throws InputError naming TMPDIR when the
  /// temporary folder is unusable, std::filesystem::filesystem_error when
  /// the marker or the lock cannot be written.
  explicit ScratchFolder(const std::string& prefix);
  ~ScratchFolder();
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  std::unique_ptr<LivenessLock> lock_;
};

/// The running hapticbench binary, to start more of itself (sweep workers,
/// the instruction-counting run).
std::filesystem::path this_executable();

}  // namespace hb
