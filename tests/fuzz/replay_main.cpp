// A main() for the fuzz targets in ordinary builds: feeds every file named
// on the command line (or found in the folders named) to the target once,
// and checks each input against the memory rule (kInputMemoryPerByte,
// harness/process/memory_limit.h): the heap the target takes for an input
// of n bytes stays within kInputMemoryPerByte · n + kInputMemoryAllowance.
// CTest runs each target over its seed corpus and its regression inputs.
#include <malloc.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <new>
#include <string>
#include <vector>

#include "harness/process/memory_limit.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size);
// Defined by the targets that set the process up first (as libFuzzer calls it).
extern "C" __attribute__((weak)) int LLVMFuzzerInitialize(int* argc, char*** argv);

// The heap in use and its peak, counted by the replaced operators below
// (every allocation through new, which is all the parsers use).
namespace {
std::atomic<std::size_t> heap_in_use{0};
std::atomic<std::size_t> heap_peak{0};

void* counted_allocation(std::size_t size) {
  void* p = std::malloc(size == 0 ? 1 : size);
  if (p == nullptr) throw std::bad_alloc();
  const std::size_t now = heap_in_use += malloc_usable_size(p);
  std::size_t peak = heap_peak.load();
  while (now > peak && !heap_peak.compare_exchange_weak(peak, now)) {
  }
  return p;
}

void counted_release(void* p) {
  if (p == nullptr) return;
  heap_in_use -= malloc_usable_size(p);
  std::free(p);
}
}  // namespace

void* operator new(std::size_t size) { return counted_allocation(size); }
void* operator new[](std::size_t size) { return counted_allocation(size); }
void operator delete(void* p) noexcept { counted_release(p); }
void operator delete[](void* p) noexcept { counted_release(p); }
void operator delete(void* p, std::size_t) noexcept { counted_release(p); }
void operator delete[](void* p, std::size_t) noexcept { counted_release(p); }

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  if (LLVMFuzzerInitialize) LLVMFuzzerInitialize(&argc, &argv);
  std::vector<fs::path> files;
  for (int i = 1; i < argc; ++i) {
    const fs::path path = argv[i];
    if (fs::is_directory(path)) {
      for (const auto& entry : fs::recursive_directory_iterator(path))
        if (entry.is_regular_file()) files.push_back(entry.path());
    } else if (fs::is_regular_file(path)) {
      files.push_back(path);
    }
  }
  std::sort(files.begin(), files.end());
  int over_rule = 0;
  double worst_share = 0;  // of the rule's bound
  for (const fs::path& file : files) {
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t before = heap_in_use.load();
    heap_peak = before;
    LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
    const std::size_t used = heap_peak.load() - before;
    const std::uint64_t bound = hb::kInputMemoryPerByte * bytes.size() + hb::kInputMemoryAllowance;
    worst_share = std::max(worst_share, static_cast<double>(used) / static_cast<double>(bound));
    if (used > bound) {
      ++over_rule;
      std::cout << file.string() << ": " << bytes.size() << " bytes took " << used
                << " bytes of heap; the memory rule allows " << bound << "\n";
    }
  }
  std::cout << files.size() << " inputs replayed; the largest heap took "
            << static_cast<int>(100 * worst_share + 0.5) << " % of the memory rule's bound\n";
  return files.empty() || over_rule > 0 ? 1 : 0;
}
