// Where and how a result was produced: carried by every summary.
#pragma once

#include <string>

namespace hb {

struct RunContext {
  std::string commit;      ///< source commit the binary was configured from
  std::string build_type;  ///< CMake build type, e.g. "Release"
  std::string compiler;
  std::string cpu;   ///< model name from /proc/cpuinfo
  std::string date;  ///< UTC, ISO 8601
  std::string hapticbench_version;
};

RunContext current_run_context();

}  // namespace hb
