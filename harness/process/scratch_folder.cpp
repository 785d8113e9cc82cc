#include "harness/process/scratch_folder.h"

#include <stdlib.h>
#include <unistd.h>

#include <system_error>

#include "algorithms/core/replacing_file.h"
#include "algorithms/core/temporary_folder.h"
#include "hapticbench/input_error.h"
#include "harness/process/liveness_lock.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

constexpr const char* kScratchMarker = ".hapticbench-scratch";

// Removes the <temp>/<prefix>-<pid>-XXXXXX folders that hold the marker and
// whose process is gone: no live process holds their lock (liveness_lock.h).
// The process id in the name is not trusted: in another PID namespace (a
// container sharing /tmp) a live process's id looks gone. A folder of
// someone else's, without the marker, is never touched.
void remove_stale_scratch(const fs::path& temp, const std::string& prefix) {
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(temp, error)) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= prefix.size() + 1 || name.compare(0, prefix.size() + 1, prefix + "-") != 0)
      continue;
    std::error_code ignored;
    if (fs::symlink_status(entry.path() / kScratchMarker, ignored).type() != fs::file_type::regular)
      continue;
    remove_if_abandoned(entry.path(), [](const fs::path& folder) {
      std::error_code not_removed;
      fs::remove_all(folder, not_removed);
    });
  }
}

}  // namespace

ScratchFolder::ScratchFolder(const std::string& prefix) {
  const fs::path temp = temporary_folder();
  remove_stale_scratch(temp, prefix);
  std::string pattern = (temp / (prefix + "-" + std::to_string(::getpid()) + "-XXXXXX")).string();
  if (!::mkdtemp(pattern.data()))
    throw InputError(
        temp.string(), "TMPDIR",
        "cannot create a scratch folder there (" + std::system_category().message(errno) + ")");
  path_ = pattern;
  // The lock is held before the marker exists, so that no other process
  // ever sees this folder marked and unlocked.
  lock_ = std::make_unique<LivenessLock>(path_);
  write_file_replacing(path_ / kScratchMarker, "scratch folder of hapticbench process " +
                                                   std::to_string(::getpid()) + "\n");
}

ScratchFolder::~ScratchFolder() {
  std::error_code ignored;
  fs::remove_all(path_, ignored);
}

fs::path this_executable() {
  std::error_code error;
  const fs::path path = fs::read_symlink("/proc/self/exe", error);
  return error ? fs::path("/proc/self/exe") : path;
}

}  // namespace hb
