// hapticbench list: algorithms, generators and the scenarios shipped in scenarios/.
#include <algorithm>
#include <filesystem>
#include <iostream>

#include "algorithms/registry.h"
#include "harness/cli/commands.h"
#include "harness/trace/generators.h"

namespace hb {

namespace fs = std::filesystem;

int list_command(const std::vector<std::string>& args) {
  std::string scenario_root = "scenarios";
  if (!args.empty()) scenario_root = args.front();

  std::cout << "algorithms:\n";
  for (const AlgorithmEntry& entry : algorithm_table())
    std::cout << "  " << entry.name << "  -  " << entry.summary << "\n";
  std::cout << "generators:\n";
  for (const GeneratorEntry& entry : generator_table())
    std::cout << "  " << entry.name << "  -  " << entry.summary << "\n";

  std::cout << "scenarios (" << scenario_root << "/):\n";
  std::vector<std::string> files;
  std::error_code error;
  if (fs::is_directory(scenario_root, error)) {
    for (const auto& entry : fs::recursive_directory_iterator(scenario_root, error))
      if (entry.path().extension() == ".json") files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) std::cout << "  (none found; run from the project folder or pass a folder)\n";
  for (const std::string& file : files) std::cout << "  " << file << "\n";
  return kExitOk;
}

}  // namespace hb
