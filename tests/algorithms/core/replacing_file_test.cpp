// Tests for algorithms/core/replacing_file.cpp: whole files or nothing,
// through temporary files that are never anything of the user's.
#include "algorithms/core/replacing_file.h"

#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "tests/support/scratch_dir.h"

namespace hb {
namespace {

namespace fs = std::filesystem;

std::set<std::string> names_in(const fs::path& folder) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder))
    names.insert(entry.path().filename().string());
  return names;
}

TEST_CASE("a replacing write leaves the whole file and nothing else") {
  const test::ScratchDir folder("replacing_file");
  const fs::path out = folder / "out.json";
  write_file_replacing(out, "first");
  write_file_replacing(out, "second, longer");
  CHECK(test::read_text_file(out) == "second, longer");
  CHECK(names_in(folder) == std::set<std::string>{"out.json"});
  // The mode a new file of the user's gets (umask applied), not mkstemp's 0600.
  struct stat status {};
  REQUIRE(::stat(out.c_str(), &status) == 0);
  const mode_t mask = ::umask(0);
  ::umask(mask);
  CHECK((status.st_mode & 0777) == (0666 & ~mask));
}

TEST_CASE("a symlink at the destination is replaced, never written through") {
  const test::ScratchDir folder("replacing_symlink");
  std::ofstream(folder / "precious.txt") << "keep";
  fs::create_symlink("precious.txt", folder / "out.json");
  write_file_replacing(folder / "out.json", "new");
  CHECK(test::read_text_file(folder / "precious.txt") == "keep");
  CHECK_FALSE(fs::is_symlink(folder / "out.json"));
  CHECK(test::read_text_file(folder / "out.json") == "new");
}

TEST_CASE("an uncommitted temporary file is removed, and a missing folder is named") {
  const test::ScratchDir folder("replacing_uncommitted");
  {
    TemporarySibling file(folder / "out.csv");
    file.write("half");
    CHECK(fs::exists(file.path()));
    CHECK(file.path().filename().string().rfind(".out.csv.tmp-", 0) == 0);
  }
  CHECK(names_in(folder).empty());
  try {
    write_file_replacing(folder / "no/such/folder/out.csv", "x");
    FAIL("expected filesystem_error");
  } catch (const fs::filesystem_error& error) {
    CHECK(error.code() == std::errc::no_such_file_or_directory);
    CHECK_THAT(error.path1().string(), Catch::Contains("no/such/folder"));
  }
}

}  // namespace
}  // namespace hb
