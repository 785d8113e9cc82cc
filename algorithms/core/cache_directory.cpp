#include "hapticbench/cache_directory.h"

#include <cstdlib>
#include <string>

namespace hb {

namespace {
std::optional<std::string> environment(const char* name) {
  const char* value = std::getenv(name);
  if (value == nullptr || *value == '\0') return std::nullopt;
  return std::string(value);
}
}  // namespace

std::optional<std::filesystem::path> default_cache_directory() {
  if (auto dir = environment("HAPTICBENCH_CACHE_DIR")) return std::filesystem::path(*dir);
  if (auto dir = environment("XDG_CACHE_HOME")) return std::filesystem::path(*dir) / "hapticbench";
  if (auto home = environment("HOME"))
    return std::filesystem::path(*home) / ".cache" / "hapticbench";
  return std::nullopt;
}

}  // namespace hb
