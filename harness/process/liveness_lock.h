// Whether the process that made a folder still works in it, decided by an
// advisory lock (flock) it holds on a file in the folder for its whole life.
// Unlike a process id, a lock cannot be faked by another PID namespace (a
// container sharing /tmp, another node sharing a scratch folder): the
// kernel, or the file server, releases it only when its holder is gone.
#pragma once

#include <filesystem>
#include <functional>

namespace hb {

/// Name of the lock file inside a folder a process is working in.
inline constexpr const char* kLivenessLockName = ".hapticbench-lock";

/// An exclusive lock on <folder>/.hapticbench-lock, held until destroyed.
class LivenessLock {
 public:
  /// Opens (or creates) the lock file, never through a symlink, and takes
  /// the lock. Throws std::filesystem::filesystem_error naming the file
  /// when it cannot be opened, is not a regular file, or another live
  /// process holds its lock (errc::device_or_resource_busy).
  explicit LivenessLock(const std::filesystem::path& folder);
  /// Releases the lock; the file stays (release_and_remove() removes it).
  ~LivenessLock();
  LivenessLock(const LivenessLock&) = delete;
  LivenessLock& operator=(const LivenessLock&) = delete;

  /// Removes the lock file from `folder` (where the locked folder is now,
  /// after a rename), then releases the lock.
  void release_and_remove(const std::filesystem::path& folder);

 private:
  int fd_ = -1;
};

/// When `folder` holds a lock file that no live process holds, calls
/// `remove(folder)` while holding it, so that nobody can start using the
/// folder meanwhile, and returns true. A folder without a lock file (one
/// still being set up, or of another program) is never passed to `remove`.
bool remove_if_abandoned(const std::filesystem::path& folder,
                         const std::function<void(const std::filesystem::path&)>& remove);

}  // namespace hb
