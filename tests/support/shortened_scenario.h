// Test support: a shipped scenario replayed over fewer ticks, for end-to-end
// tests whose checks do not need the whole trace.
#pragma once

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/scratch_dir.h"

namespace hb::test {

/// Writes the scenario at `path` to `folder` (same file name) with its
/// generated trace cut to at most `max_duration_s`, a periodic trace's
/// `cycles` cut in proportion (so each cycle keeps its length), and its mesh
/// paths made absolute: the same scene, tool, algorithms and references.
/// Returns the written file.
inline std::filesystem::path shortened_scenario(const std::filesystem::path& path,
                                                double max_duration_s,
                                                const std::filesystem::path& folder) {
  nlohmann::json scenario = nlohmann::json::parse(read_text_file(path));
  nlohmann::json& trace = scenario.at("trace");
  const double duration = trace.at("duration_s").get<double>();
  if (duration > max_duration_s) {
    trace["duration_s"] = max_duration_s;
    if (trace.contains("params") && trace["params"].contains("cycles")) {
      const double cycles = trace["params"]["cycles"].get<double>();
      trace["params"]["cycles"] =
          std::max(1.0, std::floor(cycles * max_duration_s / duration + 0.5));
    }
  }
  auto absolute_mesh = [&](nlohmann::json& object) {
    if (object.contains("mesh"))
      object["mesh"] = (path.parent_path() / object["mesh"].get<std::string>()).string();
  };
  for (nlohmann::json& object : scenario.at("scene")) absolute_mesh(object);
  absolute_mesh(scenario.at("tool"));
  const std::filesystem::path out = folder / path.filename();
  std::ofstream(out) << scenario.dump(2);
  return out;
}

}  // namespace hb::test
