#include "harness/replay/slow_loop_schedule.h"

#include <charconv>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>

#include "hapticbench/input_error.h"

namespace hb {

namespace {

constexpr std::string_view kHeader = "start_tick,install_tick,update_ns";
// A schedule of a day at one update per tick; more is not a schedule.
constexpr std::uintmax_t kMaxScheduleBytes = std::uintmax_t{1} << 32;

bool parse_integer(std::string_view text, int64_t& value) {
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return !text.empty() && error == std::errc() && end == text.data() + text.size();
}

}  // namespace

std::string schedule_csv(const SlowLoopSchedule& schedule) {
  std::string text(kHeader);
  text += '\n';
  for (const SlowLoopUpdate& u : schedule.updates)
    text += std::to_string(u.start_tick) + ',' + std::to_string(u.install_tick) + ',' +
            std::to_string(u.update_ns) + '\n';
  return text;
}

SlowLoopSchedule parse_schedule_csv(const std::string& text, const std::string& path) {
  SlowLoopSchedule schedule;
  std::istringstream in(text);
  std::string line;
  int64_t line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string where = "line " + std::to_string(line_number);
    if (line_number == 1) {
      if (line != kHeader)
        throw InputError(path, where, "expected the header " + std::string(kHeader));
      continue;
    }
    if (line.empty()) continue;
    SlowLoopUpdate update;
    int64_t* fields[] = {&update.start_tick, &update.install_tick, &update.update_ns};
    std::string_view rest = line;
    for (int i = 0; i < 3; ++i) {
      const std::size_t comma = i < 2 ? rest.find(',') : std::string_view::npos;
      if (i < 2 && comma == std::string_view::npos)
        throw InputError(path, where,
                         "expected 3 whole numbers: start_tick,install_tick,update_ns");
      if (!parse_integer(rest.substr(0, comma), *fields[i]) || *fields[i] < 0)
        throw InputError(path, where,
                         "expected 3 whole numbers >= 0: start_tick,install_tick,update_ns");
      if (i < 2) rest.remove_prefix(comma + 1);
    }
    if (update.install_tick <= update.start_tick)
      throw InputError(path, where, "install_tick must be after start_tick");
    if (!schedule.updates.empty() && update.start_tick < schedule.updates.back().install_tick)
      throw InputError(path, where,
                       "starts at tick " + std::to_string(update.start_tick) +
                           ", before the previous update is installed (tick " +
                           std::to_string(schedule.updates.back().install_tick) + ")");
    schedule.updates.push_back(update);
  }
  if (line_number == 0)
    throw InputError(path, "", "empty; expected the header " + std::string(kHeader));
  return schedule;
}

SlowLoopSchedule read_schedule_file(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error))
    throw InputError(path, "", "expected a schedule file (schedule_<label>.csv)");
  if (std::filesystem::file_size(path, error) > kMaxScheduleBytes)
    throw InputError(path, "", "larger than 4 GiB; not a schedule");
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) throw InputError(path, "", "cannot read the file");
  return parse_schedule_csv(text.str(), path);
}

}  // namespace hb
