#include "harness/output/run_context.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <fstream>
#include <vector>

#ifndef HAPTICBENCH_COMMIT
#define HAPTICBENCH_COMMIT "unknown"
#endif
#ifndef HAPTICBENCH_BUILD_TYPE
#define HAPTICBENCH_BUILD_TYPE "unknown"
#endif
#ifndef HAPTICBENCH_VERSION
#define HAPTICBENCH_VERSION "unknown"
#endif
#ifndef HAPTICBENCH_CXX_FLAGS
#define HAPTICBENCH_CXX_FLAGS "unknown"
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

std::string first_line_of(const char* path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

std::optional<double> load_average_1m() {
  std::ifstream in("/proc/loadavg");
  double value = 0;
  if (in >> value) return value;
  return std::nullopt;
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

double measure_clock_overhead_ns() {
  constexpr int kBatches = 101, kReadsPerBatch = 64;
  std::vector<double> per_read;
  per_read.reserve(kBatches);
  for (int b = 0; b < kBatches; ++b) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < kReadsPerBatch - 1; ++i) {
      const auto t = std::chrono::steady_clock::now();
      asm volatile("" : : "g"(&t) : "memory");  // keep every read
    }
    const auto t1 = std::chrono::steady_clock::now();
    per_read.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / kReadsPerBatch);
  }
  std::nth_element(per_read.begin(), per_read.begin() + kBatches / 2, per_read.end());
  return per_read[kBatches / 2];
}

std::string version_line() {
  return std::string("hapticbench ") + HAPTICBENCH_VERSION + " (commit " + HAPTICBENCH_COMMIT +
         ", " + HAPTICBENCH_BUILD_TYPE + " build)";
}

RunContext current_run_context() {
  RunContext c;
  c.commit = HAPTICBENCH_COMMIT;
  c.build_type = HAPTICBENCH_BUILD_TYPE;
  c.compiler = std::string("g++ ") + __VERSION__;
  c.compiler_flags = HAPTICBENCH_CXX_FLAGS;
  c.cpu = cpu_model();
  c.logical_cores = static_cast<int>(::sysconf(_SC_NPROCESSORS_ONLN));
  c.cpu_governor = first_line_of("/sys/devices/system/cpu/cpu0/cpufreq/scaling_governor");
  c.load_average_1m = load_average_1m();
  c.clock_overhead_ns = measure_clock_overhead_ns();
  c.date = utc_now();
  c.hapticbench_version = HAPTICBENCH_VERSION;
  return c;
}

}  // namespace hb
