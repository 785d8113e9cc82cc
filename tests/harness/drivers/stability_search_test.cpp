// Tests for search_largest_stable (harness/drivers/stability_search.cpp)
// on verdicts made up here: a single threshold is bracketed within the
// tolerance; a verdict that changes more than once is reported as such,
// with no bracket, instead of a wrong one.
#include "harness/drivers/stability_search.h"

#include <catch2/catch.hpp>
#include <functional>

namespace hb {
namespace {

std::function<StabilityProbe(double)> verdicts(const std::function<bool(double)>& stable) {
  return [stable](double value) {
    StabilityProbe probe;
    probe.settings = {{"/coupling/k_t", value}};
    probe.stable = stable(value);
    return probe;
  };
}

TEST_CASE("a single threshold is bracketed within the tolerance, and checked beyond it") {
  const StabilityBracket bracket =
      search_largest_stable(verdicts([](double k) { return k < 1000; }), 100, 10000, 0.02);
  REQUIRE(bracket.largest_stable);
  REQUIRE(bracket.smallest_unstable);
  CHECK(*bracket.largest_stable < 1000);
  CHECK(*bracket.smallest_unstable >= 1000);
  CHECK(*bracket.smallest_unstable / *bracket.largest_stable - 1 <= 0.02);
  CHECK(bracket.non_monotonic.empty());
  CHECK(bracket_note(bracket, 100, 10000).empty());
}

TEST_CASE("a verdict that changes more than once gives no bracket, and says so") {
  // Stable below 500 and again between 2,000 and 5,000 (a second band, as
  // a bounce that friction holds stable for a while): the bisection alone
  // reported the first threshold as the limit.
  const StabilityBracket bracket = search_largest_stable(
      verdicts([](double k) { return k < 500 || (k >= 2000 && k < 5000); }), 100, 10000, 0.02);
  CHECK_FALSE(bracket.largest_stable);
  CHECK_FALSE(bracket.smallest_unstable);
  CHECK_THAT(bracket.non_monotonic, Catch::Contains("not monotonic"));
  CHECK_THAT(bracket_note(bracket, 100, 10000), Catch::Contains("not monotonic"));
}

}  // namespace
}  // namespace hb
