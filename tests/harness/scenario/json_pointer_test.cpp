// JSON pointers into a scenario document: tokens (RFC 6901), and a value
// set at one, with the sections that have documented defaults created.
#include "harness/scenario/json_pointer.h"

#include <catch2/catch.hpp>
#include <string>
#include <vector>

TEST_CASE("JSON pointers split into unescaped tokens (RFC 6901)") {
  using Tokens = std::vector<std::string>;
  CHECK(hb::json_pointer_tokens("/a~1b/0") == Tokens{"a/b", "0"});
  CHECK(hb::json_pointer_tokens("/m~0n") == Tokens{"m~n"});
  CHECK(hb::json_pointer_tokens("/~01") == Tokens{"~1"});  // ~0 first, then a literal 1
  CHECK(hb::json_pointer_tokens("/") == Tokens{""});
  CHECK(hb::json_pointer_tokens("/a//b") == Tokens{"a", "", "b"});
  CHECK_FALSE(hb::json_pointer_tokens(""));
  CHECK_FALSE(hb::json_pointer_tokens("a/b"));
  CHECK_FALSE(hb::json_pointer_tokens("/a~"));
  CHECK_FALSE(hb::json_pointer_tokens("/a~2"));
}

TEST_CASE("a value is set at a pointer, a defaulted section created, anything else named") {
  nlohmann::ordered_json scenario = {{"algorithms", {{{"name", "god_object"}}}}};
  CHECK_FALSE(hb::set_at_pointer(scenario, *hb::json_pointer_tokens("/coupling/k_t"), 3000));
  CHECK(scenario["coupling"]["k_t"] == 3000);
  CHECK_FALSE(hb::set_at_pointer(scenario, *hb::json_pointer_tokens("/algorithms/0/params/x"), 1));
  CHECK(scenario["algorithms"][0]["params"]["x"] == 1);
  const auto missing = hb::set_at_pointer(scenario, *hb::json_pointer_tokens("/tool/mass_kg"), 1);
  REQUIRE(missing);
  CHECK(*missing == "the scenario's top level has no key \"tool\"");
  const auto beyond =
      hb::set_at_pointer(scenario, *hb::json_pointer_tokens("/algorithms/1/name"), 1);
  REQUIRE(beyond);
  CHECK(*beyond == "\"/algorithms\" has 1 elements, no element 1");
}
