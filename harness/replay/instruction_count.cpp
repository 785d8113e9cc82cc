#include "harness/replay/instruction_count.h"

#include <valgrind/callgrind.h>
#include <valgrind/valgrind.h>

#include <fstream>
#include <optional>
#include <stdexcept>

namespace hb {

bool running_on_valgrind() { return RUNNING_ON_VALGRIND != 0; }

void toggle_instruction_collection() { CALLGRIND_TOGGLE_COLLECT; }

void start_instrumentation() { CALLGRIND_START_INSTRUMENTATION; }

void dump_instruction_counts(const std::string& tag) { CALLGRIND_DUMP_STATS_AT(tag.c_str()); }

std::map<std::string, int64_t> read_callgrind_dumps(const std::filesystem::path& folder) {
  constexpr std::string_view kTrigger = "desc: Trigger: Client Request: ";
  std::map<std::string, int64_t> totals;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    std::ifstream in(entry.path());
    std::string line, tag;
    std::optional<int64_t> total;
    while (std::getline(in, line)) {
      if (line.rfind(kTrigger, 0) == 0) tag = line.substr(kTrigger.size());
      for (std::string_view key : {"totals: ", "summary: "})
        if (line.rfind(key, 0) == 0) total = std::stoll(line.substr(key.size()));
    }
    if (tag.empty()) continue;  // the dump at exit, or one not asked for
    if (!total)
      throw std::runtime_error(entry.path().string() + ": a callgrind dump without a total");
    totals[tag] = *total;
  }
  return totals;
}

}  // namespace hb
