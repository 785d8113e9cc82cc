#include "hapticbench/disk_cache.h"

#include <sys/resource.h>
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
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

}  // namespace
}  // namespace hb
