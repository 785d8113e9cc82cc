// Tests for harness/process/liveness_lock.cpp: a folder whose lock a live
// holder keeps is never removed; once the holder is gone it is; a folder
// without a lock file is never removed.
#include "harness/process/liveness_lock.h"

#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "tests/support/scratch_dir.h"

namespace hb {
namespace {

namespace fs = std::filesystem;

bool remove_when_abandoned(const fs::path& folder) {
  return remove_if_abandoned(folder, [](const fs::path& path) { fs::remove_all(path); });
}

TEST_CASE("a folder is removed only when no live process holds its lock") {
  const test::ScratchDir root("liveness_lock");
  const fs::path folder = root / "work";
  fs::create_directories(folder);
  std::ofstream(folder / "ticks.csv") << "tick\n";

  CHECK_FALSE(remove_when_abandoned(folder));  // no lock file: not known to be ours
  {
    const LivenessLock held(folder);
    CHECK_FALSE(remove_when_abandoned(folder));
    CHECK(fs::exists(folder / "ticks.csv"));
    // A second lock on a held folder is refused, naming the file.
    CHECK_THROWS_WITH(LivenessLock(folder), Catch::Contains(".hapticbench-lock"));
  }
  // Held by another process, which then ends without a word (as SIGKILL).
  int ready[2];
  REQUIRE(::pipe(ready) == 0);
  const pid_t child = ::fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    const LivenessLock held(folder);
    const char byte = 1;
    if (::write(ready[1], &byte, 1) != 1) ::_exit(1);
    ::pause();
    ::_exit(0);
  }
  ::close(ready[1]);
  char byte = 0;
  REQUIRE(::read(ready[0], &byte, 1) == 1);  // the child holds the lock
  ::close(ready[0]);
  CHECK_FALSE(remove_when_abandoned(folder));
  ::kill(child, SIGKILL);
  ::waitpid(child, nullptr, 0);
  CHECK(remove_when_abandoned(folder));
  CHECK_FALSE(fs::exists(folder));
}

TEST_CASE("the lock file is never a symlink or anything but a regular file") {
  const test::ScratchDir root("liveness_lock_symlink");
  const fs::path folder = root / "work";
  fs::create_directories(folder);
  std::ofstream(root / "victim.txt") << "precious";
  fs::create_symlink(root / "victim.txt", folder / kLivenessLockName);
  CHECK_THROWS_AS(LivenessLock(folder), fs::filesystem_error);
  CHECK_FALSE(remove_when_abandoned(folder));
  CHECK(test::read_text_file(root / "victim.txt") == "precious");
}

}  // namespace
}  // namespace hb
