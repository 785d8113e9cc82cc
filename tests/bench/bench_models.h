// The extracted models the mesh benchmarks load (models/, written by
// scripts/extract-models).
#pragma once

#include <cstdio>
#include <filesystem>
#include <initializer_list>
#include <string>

namespace hb::bench {

/// The models folder with a trailing slash.
inline std::string models_folder() { return std::string(HAPTICBENCH_SOURCE_DIR) + "/models/"; }

/// True when every named file is in models/; otherwise says on stderr how
/// to get them and returns false.
inline bool models_present(std::initializer_list<const char*> files) {
  for (const char* file : files) {
    if (!std::filesystem::exists(models_folder() + file)) {
      std::fprintf(stderr, "models/%s is missing: run scripts/extract-models\n", file);
      return false;
    }
  }
  return true;
}

}  // namespace hb::bench
