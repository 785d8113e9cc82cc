#include "hapticbench/disk_cache.h"

#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "tests/support/scratch_dir.h"

namespace hb {
namespace {

namespace fs = std::filesystem;

void overwrite_byte(const fs::path& file, std::uintmax_t offset_from_end, char value) {
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(static_cast<std::streamoff>(fs::file_size(file) - offset_from_end));
  f.put(value);
}

TEST_CASE("a stored payload reads back under its key, byte for byte") {
  const test::ScratchDir folder("disk_cache_hit");
  const DiskCache cache(folder.path(), "grid");
  const std::string payload("\0binary\xff payload\n", 18);
  CHECK_FALSE(cache.read("key 1").payload);  // nothing yet: a miss without a problem
  CHECK(cache.read("key 1").problem.empty());
  CHECK(cache.write("key 1", payload).empty());
  const DiskCache::Lookup hit = cache.read("key 1");
  REQUIRE(hit.payload);
  CHECK(*hit.payload == payload);
  CHECK_FALSE(cache.read("key 2").payload);
  CHECK(cache.path_of("key 1").filename().string().rfind("grid-", 0) == 0);
  // No temporary file is left beside it.
  int files = 0;
  for (const auto& entry : fs::directory_iterator(folder.path())) {
    ++files;
    CHECK(entry.path().extension() == ".hbcache");
  }
  CHECK(files == 1);
}

TEST_CASE("a damaged, truncated or foreign file is a miss that says why") {
  const test::ScratchDir folder("disk_cache_damage");
  const DiskCache cache(folder.path(), "grid");
  const std::string payload(1000, 'x');
  const fs::path file = cache.path_of("k");

  SECTION("a flipped payload byte") {
    cache.write("k", payload);
    overwrite_byte(file, 10, 'y');
    const DiskCache::Lookup lookup = cache.read("k");
    CHECK_FALSE(lookup.payload);
    CHECK_THAT(lookup.problem, Catch::Contains("damaged"));
  }
  SECTION("a truncated file") {
    cache.write("k", payload);
    fs::resize_file(file, fs::file_size(file) - 100);
    CHECK_THAT(cache.read("k").problem, Catch::Contains("wrong length"));
  }
  SECTION("another kind's file under this name") {
    const DiskCache other(folder.path(), "mesh");
    other.write("k", payload);
    fs::rename(other.path_of("k"), file);
    CHECK_THAT(cache.read("k").problem, Catch::Contains("header"));
  }
  SECTION("a file that holds another key") {
    cache.write("other key", payload);
    fs::rename(cache.path_of("other key"), file);
    CHECK_THAT(cache.read("k").problem, Catch::Contains("another key"));
  }
  SECTION("a FIFO in its place: a miss at once, not a read that waits for a writer") {
    REQUIRE(::mkfifo(file.c_str(), 0600) == 0);
    CHECK_THAT(cache.read("k").problem, Catch::Contains("regular file"));
  }
  SECTION("a 2 GB file of something else: refused by its header, never paged in") {
    { std::ofstream(file, std::ios::binary) << "not a cache file\n"; }
    fs::resize_file(file, std::uintmax_t{2} << 30);  // sparse: no disk used
    rusage before{};
    ::getrusage(RUSAGE_SELF, &before);
    CHECK_THAT(cache.read("k").problem, Catch::Contains("header"));
    rusage after{};
    ::getrusage(RUSAGE_SELF, &after);
    CHECK(after.ru_maxrss - before.ru_maxrss < 100 * 1024);  // KiB: under 100 MB more
  }
  // Written again, it reads back.
  CHECK(cache.write("k", payload).empty());
  CHECK(cache.read("k").payload == payload);
}

TEST_CASE("without a folder the cache is off") {
  const DiskCache cache(std::nullopt, "grid");
  CHECK_FALSE(cache.enabled());
  CHECK(cache.write("k", "payload").empty());
  CHECK_FALSE(cache.read("k").payload);
  CHECK(cache.path_of("k").empty());
}

TEST_CASE("a file anyone else wrote or can write is not trusted, whatever its checksum") {
  // The checksum can be recomputed by anyone: the bytes below are a valid
  // cache file, but a stranger could have written them.
  const test::ScratchDir folder("disk_cache_trust");
  const DiskCache cache(folder.path(), "force_reference");
  const fs::path file = cache.path_of("k");
  REQUIRE(cache.write("k", "0.0025 N").empty());
  REQUIRE(cache.read("k").payload);

  SECTION("writable by every user") {
    fs::permissions(file, fs::perms::others_write, fs::perm_options::add);
    const DiskCache::Lookup lookup = cache.read("k");
    CHECK_FALSE(lookup.payload);
    CHECK_THAT(lookup.problem, Catch::Contains("writable by other users"));
  }
  SECTION("written by another user") {
    if (::geteuid() != 0) {
      WARN("skipped: only root can give a file to another user here");
      return;
    }
    REQUIRE(::chown(file.c_str(), 65534, 65534) == 0);
    const DiskCache::Lookup lookup = cache.read("k");
    CHECK_FALSE(lookup.payload);
    CHECK_THAT(lookup.problem, Catch::Contains("written by user 65534"));
  }
  SECTION("in a folder every user can change") {
    fs::permissions(folder.path(), fs::perms::others_write, fs::perm_options::add);
    const DiskCache::Lookup lookup = cache.read("k");
    CHECK_FALSE(lookup.payload);
    CHECK_THAT(lookup.problem, Catch::Contains("is writable by every user"));
  }
  SECTION("a symlink in the file's place") {
    const fs::path elsewhere = folder.path() / "elsewhere.hbcache";
    fs::rename(file, elsewhere);
    fs::create_symlink(elsewhere, file);
    CHECK_FALSE(cache.read("k").payload);
  }
}

TEST_CASE("a cache write follows no name planted beside it") {
  // Names the writer once used (<file>.tmp-<pid>-<n>), each a symlink to a
  // file of the victim's: none is written through.
  const test::ScratchDir folder("disk_cache_planted");
  const DiskCache cache(folder.path(), "grid");
  const fs::path victim = folder.path() / "victim.txt";
  std::ofstream(victim) << "precious";
  const fs::path file = cache.path_of("k");
  for (int n = 0; n < 4; ++n)
    fs::create_symlink(
        victim, file.string() + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(n));
  for (int n = 0; n < 4; ++n) CHECK(cache.write("k", std::string(100, 'x')).empty());
  CHECK(test::read_text_file(victim) == "precious");
  CHECK(cache.read("k").payload == std::string(100, 'x'));
}

TEST_CASE("a payload written and read in parts equals the whole, and damage is found") {
  const test::ScratchDir folder("disk_cache_parts");
  const DiskCache cache(folder.path(), "track");
  // Parts of odd sizes, across the checksum's 32-byte blocks and the
  // reader's 1 MB parts.
  std::string whole;
  for (int i = 0; whole.size() < 3 * DiskCache::kPartBytes; ++i)
    whole += std::string(static_cast<std::size_t>(1 + i % 97), static_cast<char>('a' + i % 26));
  const auto produce = [&](const std::function<void(std::string_view)>& put) {
    for (std::size_t at = 0; at < whole.size(); at += 70001)
      put(std::string_view(whole).substr(at, 70001));
  };
  REQUIRE(cache.write_parts("k", whole.size(), produce).empty());
  CHECK(cache.read("k").payload == whole);  // the same file as a whole write
  std::string read;
  CHECK(cache.read_parts("k", [&](std::string_view part) { read.append(part); }));
  CHECK(read == whole);
  overwrite_byte(cache.path_of("k"), 5, '#');
  std::string problem;
  CHECK_FALSE(cache.read_parts(
      "k", [](std::string_view) {}, &problem));
  CHECK_THAT(problem, Catch::Contains("damaged"));
}

}  // namespace
}  // namespace hb
