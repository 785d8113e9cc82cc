#include "harness/process/scratch_folder.h"

#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <cerrno>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace hb {

namespace fs = std::filesystem;

namespace {

constexpr const char* kScratchMarker = ".hapticbench-scratch";

// Removes <temp>/<prefix>-<pid>-XXXXXX folders of processes that are gone
// and that hold the marker (a folder of someone else's is never touched).
void remove_stale_scratch(const fs::path& temp, const std::string& prefix) {
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(temp, error)) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= prefix.size() + 1 || name.compare(0, prefix.size() + 1, prefix + "-") != 0)
      continue;
    const std::size_t pid_end = name.find('-', prefix.size() + 1);
    if (pid_end == std::string::npos || pid_end == prefix.size() + 1) continue;
    const std::string pid_text = name.substr(prefix.size() + 1, pid_end - prefix.size() - 1);
    if (pid_text.find_first_not_of("0123456789") != std::string::npos || pid_text.size() > 9)
      continue;
    std::error_code ignored;
    if (process_is_gone(std::stol(pid_text)) &&
        fs::is_regular_file(entry.path() / kScratchMarker, ignored))
      fs::remove_all(entry.path(), ignored);
  }
}

}  // namespace

bool process_is_gone(long pid) {
  return pid > 0 && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
}

ScratchFolder::ScratchFolder(const std::string& prefix) {
  remove_stale_scratch(fs::temp_directory_path(), prefix);
  std::string pattern =
      (fs::temp_directory_path() / (prefix + "-" + std::to_string(::getpid()) + "-XXXXXX"))
          .string();
  if (!::mkdtemp(pattern.data()))
    throw std::runtime_error("cannot create a scratch folder in " +
                             fs::temp_directory_path().string());
  path_ = pattern;
  std::ofstream(path_ / kScratchMarker)
      << "scratch folder of hapticbench process " << ::getpid() << "\n";
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
