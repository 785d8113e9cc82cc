#include "harness/cli/command_line.h"

#include <charconv>
#include <cmath>
#include <iostream>

#include "harness/cli/commands.h"

namespace hb {

int print_usage_error(const UsageError& error, std::string_view usage) {
  std::cerr << "error: " << error.message << "\n" << usage;
  return kExitBadInput;
}

int print_help(std::string_view usage) {
  std::cout << usage;
  return kExitOk;
}

const std::string& option_value(const std::vector<std::string>& args, std::size_t& i) {
  if (i + 1 >= args.size()) throw UsageError{args[i] + " needs a value"};
  // "--out --quiet" is a forgotten value, not a folder named --quiet (a
  // value that starts with "--" can be given as ./--name).
  if (args[i + 1].rfind("--", 0) == 0)
    throw UsageError{args[i] + " needs a value, got the option " + args[i + 1]};
  return args[++i];
}

std::optional<double> parse_number(std::string_view text) {
  double value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() ||
      !std::isfinite(value))
    return std::nullopt;
  return value;
}

std::optional<long long> parse_whole_number(std::string_view text, long long min, long long max) {
  long long value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() || value < min ||
      value > max)
    return std::nullopt;
  return value;
}

void check_help(const std::string& arg) {
  if (arg == "-h" || arg == "--help") throw HelpRequested{};
}

bool parse_progress_option(const std::vector<std::string>& args, std::size_t& i,
                           std::optional<ProgressStyle>& style) {
  if (args[i] == "--quiet") {
    style = ProgressStyle::kNone;
    return true;
  }
  if (args[i] != "--progress") return false;
  const std::string& value = option_value(args, i);
  style = progress_style_named(value);
  if (!style) throw UsageError{"--progress: expected bar, plain or none, got \"" + value + "\""};
  return true;
}

ProgressDisplay make_progress_display(std::optional<ProgressStyle> style, double quiet_for_s) {
  ProgressSettings settings;
  settings.style = style.value_or(default_progress_style());
  settings.quiet_for_s = quiet_for_s;
  return ProgressDisplay(std::cerr, std::move(settings));
}

}  // namespace hb
