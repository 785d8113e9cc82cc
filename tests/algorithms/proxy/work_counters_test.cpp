// Tests for WorkCounters (hapticbench/renderer.h): counts read back by
// the names the algorithm gives its slots; nothing without names.
#include <catch2/catch.hpp>

#include "hapticbench/renderer.h"

namespace hb {
namespace {

TEST_CASE("work counters read back by the names of their slots") {
  static constexpr WorkCounters::Names kNames = {"gjk_calls", "piece_tests"};
  WorkCounters work;
  CHECK(work.get("gjk_calls") == 0);  // no names yet: nothing counted
  work.names = &kNames;
  work.add(0, 3);
  work.add(1);
  work.add(0, 2);
  CHECK(work.get("gjk_calls") == 5);
  CHECK(work.get("piece_tests") == 1);
  CHECK(work.get("points_looked_up") == 0);
  CHECK(work.get("") == 0);  // unused slots have no name
}

}  // namespace
}  // namespace hb
