#include "harness/output/run_context.h"

#include <ctime>
#include <fstream>

#ifndef HAPTICBENCH_COMMIT
#define HAPTICBENCH_COMMIT "unknown"
#endif
#ifndef HAPTICBENCH_BUILD_TYPE
#define HAPTICBENCH_BUILD_TYPE "unknown"
#endif
#ifndef HAPTICBENCH_VERSION
#define HAPTICBENCH_VERSION "unknown"
#endif

namespace hb {

namespace {
std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(' ', colon + 1));
    }
  }
  return "unknown";
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}
}  // namespace

RunContext current_run_context() {
  RunContext c;
  c.commit = HAPTICBENCH_COMMIT;
  c.build_type = HAPTICBENCH_BUILD_TYPE;
  c.compiler = std::string("g++ ") + __VERSION__;
  c.cpu = cpu_model();
  c.date = utc_now();
  c.hapticbench_version = HAPTICBENCH_VERSION;
  return c;
}

}  // namespace hb
