// End-to-end: writing onto a full filesystem (a 64 kB tmpfs mounted for the
// test; needs root, as CI runs) is exit 2 naming the path and the cause, "No
// space left on device", and leaves nothing half-written behind.
#include <sys/mount.h>

#include <catch2/catch.hpp>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"

namespace {

using hb::test::kPress;
using hb::test::kSource;

namespace fs = std::filesystem;
using hb::test::CommandResult;
using hb::test::run_hapticbench;

/// A small tmpfs at `path` for the life of the object.
class SmallFilesystem {
 public:
  SmallFilesystem(fs::path path, const std::string& size) : path_(std::move(path)) {
    fs::create_directories(path_);
    const std::string options = "size=" + size;
    if (::mount("tmpfs", path_.c_str(), "tmpfs", 0, options.c_str()) != 0)
      failure_ = std::strerror(errno);
  }
  ~SmallFilesystem() {
    if (failure_.empty()) ::umount2(path_.c_str(), MNT_DETACH);
  }
  /// Why it could not be mounted ("" when it is).
  const std::string& failure() const { return failure_; }

  /// Fills what is left of it with one file of the test's.
  void fill(const std::string& name) const {
    std::ofstream out(path_ / name, std::ios::binary);
    const std::string block(4096, 'x');
    while (out.write(block.data(), static_cast<std::streamsize>(block.size()))) {
    }
  }

  std::set<std::string> listing() const {
    std::set<std::string> names;
    for (const auto& entry : fs::directory_iterator(path_))
      names.insert(entry.path().filename().string());
    return names;
  }

 private:
  fs::path path_;
  std::string failure_;
};

void check_full_disk(const CommandResult& result, const std::string& path_part) {
  INFO(result.stdout_text << result.stderr_text);
  CHECK(result.exit_code == 2);
  CHECK(result.stderr_text.find("No space left on device") != std::string::npos);
  CHECK(result.stderr_text.find(path_part) != std::string::npos);
  CHECK(result.stderr_text.find("Input/output error") == std::string::npos);
}

TEST_CASE("a full disk is named as such, and nothing half-written is left on it") {
  const hb::test::ScratchDir work_dir("e2e_full_disk");
  const fs::path& work = work_dir.path();
  REQUIRE(run_hapticbench("run " + kPress + " --out run --quiet", work).exit_code == 0);
  const SmallFilesystem disk(work / "full", "64k");
  INFO("mounting a tmpfs: " << disk.failure());
  REQUIRE(disk.failure().empty());

  // A trace larger than the filesystem: nothing of it stays.
  check_full_disk(run_hapticbench("generate press --duration 5 --out full/t.csv", work), "full/");
  CHECK(disk.listing().empty());
  // Room for the run folder's marker, not for its ticks: the ticks file is
  // copied across filesystems from TMPDIR, and the copy says why it failed
  // (the library's copy said "Input/output error").
  check_full_disk(run_hapticbench("run " + kPress + " --out full/run --quiet", work), "full/");
  CHECK(disk.listing().empty());
  // A sweep whose jobs fail on the full disk: each job "failed" on an error
  // it named, exit 2; none "crashed".
  hb::test::write_file(work / "sweep.json", R"({"name": "full", "scenarios": [")" + kPress +
                                                R"("], "grid": {"/coupling/k_t": [1000, 2000]}})");
  const CommandResult sweep = run_hapticbench("sweep sweep.json --out full/sweep --quiet", work);
  INFO(sweep.stdout_text << sweep.stderr_text);
  CHECK(sweep.exit_code == 2);
  CHECK(sweep.stderr_text.find("No space left on device") != std::string::npos);
  CHECK(sweep.stdout_text.find(" 0 crashed") != std::string::npos);
  fs::remove_all(work / "full" / "sweep");

  disk.fill("filler");
  const std::set<std::string> filled = {"filler"};
  check_full_disk(run_hapticbench("export --format gbench run --out full/bench.json", work),
                  "full/");
  CHECK(disk.listing() == filled);
  check_full_disk(run_hapticbench("run " + kPress + " --out full/run --quiet", work), "full/");
  CHECK(disk.listing() == filled);
}

}  // namespace
