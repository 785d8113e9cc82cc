// What the mesh benchmarks share: the extracted models they load (models/,
// written by scripts/extract-models) and their --once flag.
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

/// True when the first argument is `flag` (such as "--once", a bench's
/// own flag), which is then taken out of argc and argv so that Google
/// Benchmark sees only its own.
inline bool take_leading_flag(int& argc, char**& argv, const std::string& flag) {
  if (argc < 2 || argv[1] != flag) return false;
  argv[1] = argv[0];
  ++argv;
  --argc;
  return true;
}

}  // namespace hb::bench
