// The one reader of numeric options: the whole text, finite, in range.
#include "harness/cli/command_line.h"

#include <catch2/catch.hpp>

namespace hb {
namespace {

TEST_CASE("parse_number takes the whole text as a finite number") {
  CHECK(parse_number("0.5") == 0.5);
  CHECK(parse_number("1e-6") == 1e-6);
  CHECK(parse_number("-3") == -3.0);
  for (const char* bad : {"", " 1", "1 ", "1x", "0x10", "inf", "nan", "1e999", "+1", "1,5"}) {
    INFO(bad);
    CHECK_FALSE(parse_number(bad));
  }
}

TEST_CASE("parse_whole_number takes the whole text as a whole number within its range") {
  CHECK(parse_whole_number("3", 1, 10) == 3);
  CHECK(parse_whole_number("1", 1, 10) == 1);
  CHECK(parse_whole_number("10", 1, 10) == 10);
  for (const char* bad : {"0", "11", "", "1.0", "3x", "-1", "99999999999999999999"}) {
    INFO(bad);
    CHECK_FALSE(parse_whole_number(bad, 1, 10));
  }
}

}  // namespace
}  // namespace hb
