// Test support shared by the end-to-end tests: the source tree they read
// scenarios from, and small helpers on files and text.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace hb::test {

/// The repository's root folder.
inline const std::filesystem::path kSource = HAPTICBENCH_SOURCE_DIR;

/// The smoke suite's sphere pressed into a box, and box pressed onto a box.
inline const std::string kPress = (kSource / "scenarios/smoke/sphere_press_box.json").string();
inline const std::string kBoxPress = (kSource / "scenarios/smoke/box_press_box.json").string();

inline bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// Writes `text` to `path` as given, creating its folder.
inline void write_file(const std::filesystem::path& path, const std::string& text) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

/// Names in `folder` other than the captured output of the command run
/// there (stdout.txt, stderr.txt; tests/support/cli_runner.h).
inline std::set<std::string> listing(const std::filesystem::path& folder) {
  std::set<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (name != "stdout.txt" && name != "stderr.txt") names.insert(name);
  }
  return names;
}

/// The columns of a ticks CSV by name, one value per row (an empty field
/// reads as 0).
inline std::map<std::string, std::vector<double>> read_tick_columns(
    const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream header(line);
  for (std::string name; std::getline(header, name, ',');) names.push_back(name);
  std::map<std::string, std::vector<double>> columns;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string field;
    for (std::size_t i = 0; i < names.size() && std::getline(row, field, ','); ++i)
      columns[names[i]].push_back(field.empty() ? 0.0 : std::strtod(field.c_str(), nullptr));
  }
  return columns;
}

}  // namespace hb::test
