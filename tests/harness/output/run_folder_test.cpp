#include "harness/output/run_folder.h"

#include <catch2/catch.hpp>
#include <fstream>
#include <stdexcept>

namespace hb {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("hb_run_folder_test_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string read(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST_CASE("a committed run folder replaces the old one completely") {
  const fs::path root = fresh_dir("commit");
  const fs::path run = root / "run";
  fs::create_directories(run);
  std::ofstream(run / "stale.csv") << "old";
  {
    StagedRunFolder staged(run);
    staged.write_file("summary.json", "{}");
    CHECK(fs::exists(run / "stale.csv"));  // untouched until commit
    staged.commit();
  }
  CHECK(read(run / "summary.json") == "{}");
  CHECK_FALSE(fs::exists(run / "stale.csv"));
  for (const auto& entry : fs::directory_iterator(root)) CHECK(entry.path() == run);
}

TEST_CASE("a run that fails before commit leaves nothing behind") {
  const fs::path root = fresh_dir("abort");
  const fs::path run = root / "run";
  try {
    StagedRunFolder staged(run);
    staged.write_file("ticks_a.csv", "tick\n");
    throw std::runtime_error("failure in the middle of a run");
  } catch (const std::runtime_error&) {
  }
  CHECK(fs::is_empty(root));
}

}  // namespace
}  // namespace hb
