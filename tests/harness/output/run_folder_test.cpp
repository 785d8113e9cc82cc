#include "harness/output/run_folder.h"

#include <sys/stat.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <fstream>
#include <stdexcept>

#include "hapticbench/input_error.h"
#include "harness/output/output_ownership.h"
#include "tests/support/scratch_dir.h"

namespace hb {
namespace {

namespace fs = std::filesystem;
using test::read_text_file;

void write_run(const fs::path& run, const std::string& summary) {
  StagedRunFolder staged(run, OutputFolderKind::kRun);
  staged.write_file("summary.json", summary);
  staged.commit();
}

TEST_CASE("a committed run folder replaces an earlier run folder completely") {
  const test::ScratchDir root("run_folder_commit");
  const fs::path run = root / "run";
  {
    StagedRunFolder staged(run, OutputFolderKind::kRun);
    staged.write_file("summary.json", "{}");
    staged.write_file("ticks_a.csv", "tick\n");
    CHECK_FALSE(staged.commit());  // nothing was there
  }
  CHECK(is_owned_folder(run, OutputFolderKind::kRun));
  {
    StagedRunFolder staged(run, OutputFolderKind::kRun);
    staged.write_file("summary.json", "{\"second\": 1}");
    CHECK(fs::exists(run / "ticks_a.csv"));  // untouched until commit
    CHECK(staged.commit());                  // an earlier run folder was replaced
  }
  CHECK(read_text_file(run / "summary.json") == "{\"second\": 1}");
  CHECK_FALSE(fs::exists(run / "ticks_a.csv"));
  for (const auto& entry : fs::directory_iterator(root.path())) CHECK(entry.path() == run);
}

TEST_CASE("a run that fails before commit leaves nothing behind") {
  const test::ScratchDir root("run_folder_abort");
  const fs::path run = root / "run";
  try {
    StagedRunFolder staged(run, OutputFolderKind::kRun);
    staged.write_file("ticks_a.csv", "tick\n");
    throw std::runtime_error("failure in the middle of a run");
  } catch (const std::runtime_error&) {
  }
  CHECK(fs::is_empty(root.path()));
}

TEST_CASE("an empty folder becomes a run folder") {
  const test::ScratchDir root("run_folder_empty");
  const fs::path run = root / "made_by_user";
  fs::create_directory(run);
  write_run(run, "{}");
  CHECK(read_text_file(run / "summary.json") == "{}");
}

TEST_CASE("a folder hapticbench did not write is never replaced") {
  const test::ScratchDir root("run_folder_foreign");
  const fs::path folder = root / "mine";
  fs::create_directory(folder);
  std::ofstream(folder / "precious.txt") << "keep me";
  CHECK_THROWS_AS(write_run(folder, "{}"), InputError);
  CHECK(read_text_file(folder / "precious.txt") == "keep me");
  CHECK_FALSE(fs::exists(folder / "summary.json"));
  // Nothing was staged beside it either.
  for (const auto& entry : fs::directory_iterator(root.path())) CHECK(entry.path() == folder);
}

TEST_CASE("a run folder the user added a file to is never replaced") {
  const test::ScratchDir root("run_folder_added");
  const fs::path run = root / "run";
  write_run(run, "{}");
  std::ofstream(run / "notes.txt") << "my analysis";
  try {
    write_run(run, "{\"second\": 1}");
    FAIL("expected the run folder to be refused");
  } catch (const InputError& error) {
    CHECK(error.source() == run.string());
    CHECK_THAT(error.message(), Catch::Contains("did not write"));
  }
  CHECK(read_text_file(run / "notes.txt") == "my analysis");
  CHECK(read_text_file(run / "summary.json") == "{}");
}

TEST_CASE("a folder of another kind is not replaced") {
  const test::ScratchDir root("run_folder_kind");
  const fs::path run = root / "run";
  write_run(run, "{}");
  try {
    StagedRunFolder staged(run, OutputFolderKind::kComparison);
    FAIL("expected a run folder to be refused as a comparison folder");
  } catch (const InputError& error) {
    CHECK_THAT(error.message(), Catch::Contains("run folder"));
  }
  CHECK(read_text_file(run / "summary.json") == "{}");
}

TEST_CASE("regular files, symlinks and FIFOs are never replaced by a folder") {
  const test::ScratchDir root("run_folder_nodes");
  const fs::path file = root / "file";
  std::ofstream(file) << "data";
  const fs::path target = root / "target";
  write_run(target, "{}");
  const fs::path link = root / "link";
  fs::create_directory_symlink(target, link);
  const fs::path fifo = root / "fifo";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  for (const fs::path& path : {file, link, fifo}) {
    INFO(path.string());
    CHECK_THROWS_AS(write_run(path, "{}"), InputError);
  }
  CHECK(read_text_file(file) == "data");
  CHECK(fs::is_symlink(link));
  CHECK(fs::is_fifo(fifo));
  CHECK(read_text_file(target / "summary.json") == "{}");
}

TEST_CASE("a file hapticbench writes replaces only a file it recognises") {
  const test::ScratchDir root("run_folder_files");
  const fs::path page = root / "report.html";
  const auto ours = [](const fs::path& path) { return read_text_file(path) == "ours"; };
  CHECK_NOTHROW(require_replaceable_file(page, "report", ours));  // nothing there
  std::ofstream(page) << "ours";
  CHECK_NOTHROW(require_replaceable_file(page, "report", ours));
  std::ofstream(page) << "theirs";
  CHECK_THROWS_AS(require_replaceable_file(page, "report", ours), InputError);
  CHECK_THROWS_AS(require_replaceable_file(root.path(), "report", ours), InputError);
  CHECK_THROWS_AS(require_replaceable_file("", "report", ours), InputError);
}

TEST_CASE("an output container is created, or must be a folder") {
  const test::ScratchDir root("run_folder_container");
  CHECK_NOTHROW(create_output_container(root / "a" / "b"));
  CHECK(fs::is_directory(root / "a" / "b"));
  std::ofstream(root / "file") << "x";
  CHECK_THROWS_AS(create_output_container(root / "file"), InputError);
  CHECK_THROWS_AS(create_output_container(root / "file" / "below"), InputError);
}

}  // namespace
}  // namespace hb
