// The proximity search's flat key set against std::set: the same answer
// to every insertion, through many growths of the table, with keys that
// collide in the hash's top bits and the table's own empty marker.
#include "algorithms/ccd/key_set.h"

#include <catch2/catch.hpp>
#include <cstdint>
#include <random>
#include <set>

namespace hb::ccd_detail {
namespace {

TEST_CASE("the key set answers every insertion as std::set does") {
  const std::size_t expected = GENERATE(std::size_t{1}, std::size_t{128}, std::size_t{5000});
  INFO("room for " << expected << " keys at the start");
  std::mt19937_64 rng(7);
  // A pool of 3,000 keys, so that most of the 20,000 insertions repeat one:
  // random ones, the extremes (~0 marks an empty slot), and keys differing
  // only in their low bits (the pair keys' scene features), which a hash
  // taken from the top bits alone would pile into one slot.
  std::vector<uint64_t> pool = {0, 1, ~uint64_t{0}, ~uint64_t{0} - 1, uint64_t{1} << 63};
  for (uint64_t k = 0; k < 1000; ++k) pool.push_back((uint64_t{2} << 62) | k);
  while (pool.size() < 3000) pool.push_back(rng());
  std::uniform_int_distribution<std::size_t> pick(0, pool.size() - 1);
  KeySet keys(expected);
  std::set<uint64_t> reference;
  for (int i = 0; i < 20000; ++i) {
    const uint64_t key = pool[pick(rng)];
    INFO("insertion " << i << ", key " << key);
    REQUIRE(keys.insert(key) == reference.insert(key).second);
    REQUIRE(keys.size() == reference.size());
  }
  CHECK(reference.size() > 2900);  // nearly every key of the pool went in, most more than once
  CHECK(reference.count(~uint64_t{0}) == 1);
}

}  // namespace
}  // namespace hb::ccd_detail
