#include "harness/compare/step_times.h"

#include <charconv>
#include <cstdint>
#include <fstream>
#include <string>
#include <string_view>

#include "hapticbench/input_error.h"
#include "harness/process/input_file.h"
#include "harness/process/interrupt.h"

namespace hb {

namespace {

// The index-th comma-separated field of a line (no quoting in ticks files).
std::optional<std::string_view> csv_field(std::string_view line, std::size_t index) {
  std::size_t begin = 0;
  for (std::size_t i = 0; i < index; ++i) {
    const std::size_t comma = line.find(',', begin);
    if (comma == std::string_view::npos) return std::nullopt;
    begin = comma + 1;
  }
  const std::size_t end = line.find(',', begin);
  return line.substr(begin, end == std::string_view::npos ? std::string_view::npos : end - begin);
}

}  // namespace

std::optional<std::vector<double>> read_ticks_step_ns(const std::filesystem::path& ticks_csv) {
  if (!std::filesystem::exists(ticks_csv)) return std::nullopt;
  const std::string source = ticks_csv.string();
  require_regular_file(ticks_csv, "a ticks CSV");
  std::ifstream in(ticks_csv, std::ios::binary);
  if (!in) throw InputError(source, "", "cannot open file");

  std::string line;
  std::getline(in, line);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  std::optional<std::size_t> column;
  for (std::size_t i = 0;; ++i) {
    const std::optional<std::string_view> name = csv_field(line, i);
    if (!name) break;
    if (*name == "step_ns") {
      column = i;
      break;
    }
  }
  if (!column) throw InputError(source, "line 1", "expected a header with a step_ns column");

  std::vector<double> step_ns;
  for (std::size_t line_number = 2; std::getline(in, line); ++line_number) {
    // Ticks files run to millions of lines: a stop signal is heeded here.
    if (line_number % 4096 == 0) throw_if_interrupted();
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::optional<std::string_view> field = csv_field(line, *column);
    int64_t value = -1;
    const char* end = field ? field->data() + field->size() : nullptr;
    const bool parsed = field && !field->empty() &&
                        std::from_chars(field->data(), end, value).ptr == end && value >= 0;
    if (!parsed)
      throw InputError(source, "line " + std::to_string(line_number),
                       "step_ns: expected a whole, non-negative number of ns, got \"" +
                           std::string(field ? *field : "") + "\"");
    step_ns.push_back(static_cast<double>(value));
  }
  return step_ns;
}

}  // namespace hb
