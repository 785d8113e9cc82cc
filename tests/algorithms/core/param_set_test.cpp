// Tests for algorithms/core/param_set.cpp: values within range are returned,
// everything else is an InputError that names the field (prefix + key) and
// says what was expected.
#include "hapticbench/param_set.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "hapticbench/input_error.h"

namespace hb {
namespace {

const std::string kPrefix = "/algorithms/1/params";

// Runs f, which must throw InputError; returns it for inspection.
template <typename F>
InputError input_error_from(F&& f) {
  try {
    f();
  } catch (const InputError& error) {
    return error;
  }
  FAIL("expected InputError");
  return InputError("", "", "");
}

}  // namespace

TEST_CASE("numbers: value, fallback, range errors naming the field", "[param_set]") {
  ParamSet params(kPrefix);
  params.set("k", 12.0);
  params.set("b", 0.5);
  params.set("text", std::string("stiff"));
  params.set("nan", NAN);
  CHECK(params.number("b", 1.0, 0.0, 1.0) == 0.5);
  CHECK(params.number("absent", 7.0, 0.0, 10.0) == 7.0);
  CHECK(params.field("k") == "/algorithms/1/params/k");

  InputError error = input_error_from([&] { params.number("k", 1.0, 0.0, 10.0); });
  CHECK(error.location() == "/algorithms/1/params/k");
  CHECK_THAT(error.what(), Catch::Contains("/algorithms/1/params/k") &&
                               Catch::Contains("[0, 10]") && Catch::Contains("got 12"));
  error = input_error_from([&] { params.number("text", 1.0, 0.0, 10.0); });
  CHECK(error.location() == "/algorithms/1/params/text");
  CHECK_THAT(error.what(), Catch::Contains("expected a number"));
  error = input_error_from([&] { params.number("nan", 1.0, -1e300, 1e300); });
  CHECK(error.location() == "/algorithms/1/params/nan");
}

TEST_CASE("integers must be whole and in range", "[param_set]") {
  ParamSet params(kPrefix);
  params.set("levels", 3.0);
  params.set("half", 2.5);
  params.set("big", 200.0);
  CHECK(params.integer("levels", 1, 0, 8) == 3);
  CHECK(params.integer("absent", 4, 0, 8) == 4);
  CHECK_THAT(input_error_from([&] { params.integer("half", 1, 0, 8); }).what(),
             Catch::Contains("/algorithms/1/params/half") && Catch::Contains("whole number"));
  CHECK_THAT(input_error_from([&] { params.integer("big", 1, 0, 8); }).what(),
             Catch::Contains("/algorithms/1/params/big") && Catch::Contains("[0, 8]"));
}

TEST_CASE("choices list the allowed values", "[param_set]") {
  ParamSet params(kPrefix);
  params.set("integrator", std::string("rk4"));
  params.set("flagged", true);
  const std::vector<std::string> allowed = {"explicit_euler", "implicit_euler"};
  const InputError error = input_error_from([&] { params.choice("integrator", "", allowed); });
  CHECK(error.location() == "/algorithms/1/params/integrator");
  CHECK_THAT(error.what(), Catch::Contains("\"explicit_euler\", \"implicit_euler\"") &&
                               Catch::Contains("got \"rk4\""));
  CHECK_THAT(input_error_from([&] { params.choice("flagged", "", allowed); }).what(),
             Catch::Contains("expected one of"));
  CHECK(params.choice("absent", "implicit_euler", allowed) == "implicit_euler");
  params.set("integrator", std::string("explicit_euler"));
  CHECK(params.choice("integrator", "", allowed) == "explicit_euler");
}

TEST_CASE("flags and number lists", "[param_set]") {
  ParamSet params(kPrefix);
  params.set("on", true);
  params.set("word", std::string("yes"));
  params.set("axis", std::vector<double>{0, 0, -1});
  params.set("short", std::vector<double>{1, 2});
  params.set("bad", std::vector<double>{1, INFINITY, 2});
  CHECK(params.flag("on", false));
  CHECK(params.flag("absent", true));
  CHECK_THROWS_WITH(params.flag("word", false), Catch::Contains("/algorithms/1/params/word"));
  CHECK(params.numbers("axis", {}, 3) == std::vector<double>{0, 0, -1});
  CHECK(params.numbers("absent", {1, 2, 3}, 3) == std::vector<double>{1, 2, 3});
  CHECK_THROWS_WITH(params.numbers("short", {}, 3),
                    Catch::Contains("/algorithms/1/params/short") && Catch::Contains("3"));
  CHECK_THROWS_WITH(params.numbers("bad", {}, 3), Catch::Contains("finite"));
}

TEST_CASE("integer_or_word", "[param_set]") {
  ParamSet params(kPrefix);
  params.set("latency", std::string("measured"));
  params.set("ticks", 2.0);
  params.set("typo", std::string("measure"));
  params.set("fraction", 1.5);
  params.set("negative", -1.0);
  CHECK_FALSE(params.integer_or_word("latency", 1, 0, 100, "measured").has_value());
  CHECK(params.integer_or_word("ticks", 1, 0, 100, "measured") == 2);
  CHECK(params.integer_or_word("absent", 1, 0, 100, "measured") == 1);
  const InputError error =
      input_error_from([&] { params.integer_or_word("typo", 1, 0, 100, "measured"); });
  CHECK(error.location() == "/algorithms/1/params/typo");
  CHECK_THAT(error.what(), Catch::Contains("\"measured\"") && Catch::Contains("got \"measure\""));
  CHECK_THROWS_AS(params.integer_or_word("fraction", 1, 0, 100, "measured"), InputError);
  CHECK_THROWS_WITH(params.integer_or_word("negative", 1, 0, 100, "measured"),
                    Catch::Contains("/algorithms/1/params/negative"));
  // Every key has now been read, whatever its outcome.
  CHECK_NOTHROW(params.reject_unknown());
}

TEST_CASE("unknown keys are rejected by name, listing the known ones", "[param_set]") {
  ParamSet params(kPrefix);
  params.set("voxel_size", 0.002);
  params.set("voxle_size", 0.001);
  params.number("voxel_size", 0.001, 1e-5, 1.0);
  params.flag("braking", true);  // read even though absent
  const InputError error = input_error_from([&] { params.reject_unknown(); });
  CHECK(error.location() == "/algorithms/1/params/voxle_size");
  CHECK_THAT(error.what(),
             Catch::Contains("unknown parameter") && Catch::Contains("braking, voxel_size"));
  params.number("voxle_size", 0.0, 0.0, 1.0);
  CHECK_NOTHROW(params.reject_unknown());
}

TEST_CASE("the accessors declare each parameter once, with its default and what it accepts") {
  ParamSet params("/p");
  params.integer("count", 3, 1, 10);
  params.number("count", 5.0, 0.0, 100.0);  // asked again: the first declaration stands
  params.choice("mode", "fast", {"fast", "exact"});
  params.flag("verbose", false);
  params.numbers("start", {0, 0, 0.03}, 3);
  params.integer_or_word("latency", 1, 1, 100, "measured");
  const std::vector<ParamDeclaration>& d = params.declared();
  REQUIRE(d.size() == 5);
  CHECK(d[0].key == "count");
  CHECK(d[0].default_value == "3");
  CHECK(d[0].accepted == "whole number in [1, 10]");
  CHECK(d[1].default_value == "\"fast\"");
  CHECK(d[1].accepted == "one of \"fast\", \"exact\"");
  CHECK(d[2].default_value == "false");
  CHECK(d[3].default_value == "[0, 0, 0.03]");
  CHECK(d[3].accepted == "list of 3 numbers");
  CHECK(d[4].accepted == "whole number in [1, 100] or \"measured\"");
}

}  // namespace hb
