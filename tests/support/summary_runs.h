// Looking up runs in a parsed summary.json, for end-to-end tests.
#pragma once

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>

namespace hb::test {

/// The entry of summary["runs"] with this label; fails the test when there is none.
inline const nlohmann::json& run_labelled(const nlohmann::json& summary, const std::string& label) {
  for (const nlohmann::json& run : summary.at("runs"))
    if (run.at("label") == label) return run;
  FAIL("no run labelled " << label);
  static const nlohmann::json none;
  return none;
}

}  // namespace hb::test
