// Shards: every job in exactly one shard, and bad I/N rejected.
#include "harness/sweep/sweep_shard.h"

#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "hapticbench/input_error.h"

TEST_CASE("the shards of a sweep are disjoint and together hold every job") {
  for (std::size_t count = 1; count <= 6; ++count)
    for (std::size_t jobs = 0; jobs <= 13; ++jobs) {
      INFO(jobs << " jobs in " << count << " shards");
      std::vector<int> owners(jobs, 0);
      std::vector<std::size_t> sizes(count, 0);
      for (std::size_t shard = 0; shard < count; ++shard)
        for (std::size_t job = 0; job < jobs; ++job)
          if (hb::in_shard(job, {shard, count})) {
            ++owners[job];
            ++sizes[shard];
          }
      for (std::size_t job = 0; job < jobs; ++job) CHECK(owners[job] == 1);
      // Round-robin: shard sizes differ by at most one job.
      for (std::size_t shard = 0; shard < count; ++shard) {
        CHECK(sizes[shard] >= jobs / count);
        CHECK(sizes[shard] <= (jobs + count - 1) / count);
      }
    }
  // A Slurm array task I of N runs jobs I, I + N, I + 2N, ...
  std::vector<std::size_t> second_of_four;
  for (std::size_t job = 0; job < 10; ++job)
    if (hb::in_shard(job, {1, 4})) second_of_four.push_back(job);
  CHECK(second_of_four == std::vector<std::size_t>{1, 5, 9});
}

TEST_CASE("a shard I/N is parsed, and anything else is rejected naming --shard") {
  const hb::SweepShard shard = hb::parse_sweep_shard("3/4");
  CHECK(shard.index == 3);
  CHECK(shard.count == 4);
  CHECK(hb::shard_text(shard) == "3/4");
  CHECK(hb::parse_sweep_shard("0/1").count == 1);
  for (const std::string bad :
       {"4/4", "5/4", "1/0", "0/0", "-1/4", "1", "1/2/3", "a/b", "/4", "1/", "", " 1/4", "1/4 "}) {
    INFO("\"" << bad << "\"");
    try {
      hb::parse_sweep_shard(bad);
      FAIL("expected an InputError");
    } catch (const hb::InputError& error) {
      CHECK(error.location() == "--shard");
      CHECK(error.message().find("0 <= I < N") != std::string::npos);
    }
  }
}
