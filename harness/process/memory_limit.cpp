#include "harness/process/memory_limit.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>

// AddressSanitizer's runtime initialiser: a weak reference, null unless the
// runtime is in the process.
extern "C" void __asan_init() __attribute__((weak));

namespace hb {

namespace {

// Whether AddressSanitizer runs in this process: its shadow memory needs
// terabytes of address space, which a ceiling would refuse. Asked of the
// process, not of this unit's flags: the quick sanitizer pass links this
// unit uninstrumented into a sanitized tool.
bool address_sanitizer_running() {
#if defined(__SANITIZE_ADDRESS__)
  return true;
#else
  return &__asan_init != nullptr;
#endif
}

std::uint64_t applied_mb = 0;

// The address space this process maps now (VmSize, bytes); 0 if unknown.
std::uint64_t mapped_bytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmSize:", 0) == 0) return std::strtoull(line.c_str() + 7, nullptr, 10) << 10;
  return 0;
}

}  // namespace

std::uint64_t default_memory_limit_mb() {
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page_bytes = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page_bytes <= 0) return 0;
  const std::uint64_t physical_mb =
      static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page_bytes) >> 20;
  return std::max<std::uint64_t>(physical_mb / 2, 1024);
}

bool apply_memory_limit(std::uint64_t mb) {
  if (address_sanitizer_running() || mb == 0) return false;
  rlimit limit{};
  if (::getrlimit(RLIMIT_AS, &limit) != 0) return false;
  const rlim_t bytes = static_cast<rlim_t>(mapped_bytes() + (mb << 20));
  if (limit.rlim_max != RLIM_INFINITY && limit.rlim_max < bytes) return false;
  limit.rlim_cur = bytes;
  if (::setrlimit(RLIMIT_AS, &limit) != 0) return false;
  applied_mb = mb;
  return true;
}

void outside_memory_limit(const std::function<void()>& reserve) {
  rlimit limit{};
  if (applied_mb == 0 || ::getrlimit(RLIMIT_AS, &limit) != 0) {
    reserve();
    return;
  }
  const rlim_t ceiling = limit.rlim_cur;
  const std::uint64_t before = mapped_bytes();
  limit.rlim_cur = limit.rlim_max;
  ::setrlimit(RLIMIT_AS, &limit);
  const auto restore = [&] {
    const std::uint64_t after = mapped_bytes();
    limit.rlim_cur = ceiling + (after > before ? after - before : 0);
    if (limit.rlim_max != RLIM_INFINITY) limit.rlim_cur = std::min(limit.rlim_cur, limit.rlim_max);
    ::setrlimit(RLIMIT_AS, &limit);
  };
  try {
    reserve();
  } catch (...) {
    restore();
    throw;
  }
  restore();
}

std::uint64_t applied_memory_limit_mb() { return applied_mb; }

std::string memory_limit_message() {
  if (applied_mb == 0) return "the input needs more memory than the machine has";
  return "the input needs more than " + std::to_string(applied_mb) +
         " MB of memory (the limit, beyond the program's own code and libraries; "
         "--memory-limit MB raises it)";
}

}  // namespace hb
