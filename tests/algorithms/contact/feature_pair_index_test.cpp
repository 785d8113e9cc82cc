// FeaturePairIndex finds what a linear search finds: the first equal pair
// of the list, or none.
#include "algorithms/contact/feature_pair_index.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <random>
#include <vector>

namespace {

using hb::ContactFeatureKind;
using hb::ContactFeatures;

ContactFeatures random_pair(std::mt19937& random, int range) {
  std::uniform_int_distribution<int> kind(0, 2), index(0, range);
  return ContactFeatures{static_cast<ContactFeatureKind>(kind(random)), index(random) % 4,
                         index(random), index(random)};
}

int linear_find(const std::vector<ContactFeatures>& list, const ContactFeatures& pair) {
  const auto found = std::find(list.begin(), list.end(), pair);
  return found == list.end() ? -1 : static_cast<int>(found - list.begin());
}

}  // namespace

TEST_CASE("the pair index finds the first equal pair, as a linear search does") {
  std::mt19937 random(7);
  hb::FeaturePairIndex index;
  // Small ranges give repeats within a list and pairs the list lacks.
  for (const int size : {0, 1, 3, 4, 5, 64, 256, 1000}) {
    for (const int range : {3, 40, 100000}) {
      std::vector<ContactFeatures> list;
      for (int i = 0; i < size; ++i) list.push_back(random_pair(random, range));
      index.build(list);
      int found = 0;
      for (int q = 0; q < 500; ++q) {
        const ContactFeatures pair = q % 2 == 0 && !list.empty()
                                         ? list[static_cast<std::size_t>(q) % list.size()]
                                         : random_pair(random, range);
        const int expected = linear_find(list, pair);
        INFO("size " << size << ", range " << range << ", query " << q);
        REQUIRE(index.find(pair) == expected);
        found += expected >= 0;
      }
      if (size > 0) CHECK(found >= 250);  // every listed query is found
    }
  }
}

TEST_CASE("an index never built finds nothing") {
  const hb::FeaturePairIndex index;
  CHECK(index.find(ContactFeatures{}) == -1);
}
