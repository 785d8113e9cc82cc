// Where and how a result was produced, and how noisy the machine was when
// it started: carried by every summary, so that timings from two summaries
// are compared knowing what lies behind them.
#pragma once

#include <optional>
#include <string>

namespace hb {

struct RunContext {
  std::string commit;      ///< source commit the binary was configured from
  std::string build_type;  ///< CMake build type, e.g. "Release"
  std::string compiler;
  std::string compiler_flags;  ///< CMAKE_CXX_FLAGS with the build type's flags
  std::string cpu;             ///< model name from /proc/cpuinfo
  int logical_cores = 0;       ///< online logical CPUs
  std::string cpu_governor;    ///< cpufreq scaling governor of CPU 0; empty when unreadable
  std::optional<double> load_average_1m;  ///< /proc/loadavg at the start of the run
  double clock_overhead_ns = 0;  ///< cost of one steady_clock read, measured at the start (ns)
  std::string date;              ///< UTC, ISO 8601
  std::string hapticbench_version;
};

RunContext current_run_context();

/// What `hapticbench --version` prints: "hapticbench 0.1.0 (commit …, Release build)".
std::string version_line();

/// Median cost of one std::chrono::steady_clock::now() (ns), from a few
/// thousand back-to-back reads.
double measure_clock_overhead_ns();

}  // namespace hb
