#include "harness/sweep/sweep_shard.h"

#include <optional>

#include "hapticbench/input_error.h"

namespace hb {

namespace {

constexpr std::size_t kMaxShards = 1000000;

std::optional<std::size_t> whole_number(const std::string& text) {
  if (text.empty() || text.size() > 7) return std::nullopt;
  std::size_t value = 0;
  for (char c : text) {
    if (c < '0' || c > '9') return std::nullopt;
    value = value * 10 + static_cast<std::size_t>(c - '0');
  }
  return value;
}

}  // namespace

SweepShard parse_sweep_shard(const std::string& text) {
  const std::string expected =
      "expected I/N with whole numbers 0 <= I < N <= " + std::to_string(kMaxShards) +
      " (e.g. 0/4), got \"" + text + "\"";
  const std::size_t slash = text.find('/');
  if (slash == std::string::npos) throw InputError("", "--shard", expected);
  const std::optional<std::size_t> index = whole_number(text.substr(0, slash));
  const std::optional<std::size_t> count = whole_number(text.substr(slash + 1));
  if (!index || !count || *count == 0 || *count > kMaxShards || *index >= *count)
    throw InputError("", "--shard", expected);
  return {*index, *count};
}

bool in_shard(std::size_t job_index, const SweepShard& shard) {
  return job_index % shard.count == shard.index;
}

std::string shard_text(const SweepShard& shard) {
  return std::to_string(shard.index) + "/" + std::to_string(shard.count);
}

}  // namespace hb
