#include "harness/cli/command_line.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <iostream>
#include <sstream>

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

const std::string& option_value(const std::vector<std::string>& args, std::size_t& i,
                                const std::string& option) {
  const std::string& name = option.empty() ? args[i] : option;
  if (i + 1 >= args.size()) throw UsageError{name + " needs a value"};
  // "--out --quiet" is a forgotten value, not a folder named --quiet (a
  // value that starts with "--" can be given as ./--name).
  if (args[i + 1].rfind("--", 0) == 0)
    throw UsageError{name + " needs a value, got the option " + args[i + 1]};
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

namespace {

bool is_option_like(const std::string& arg) {
  return arg.size() > 1 && arg[0] == '-' && !std::isdigit(static_cast<unsigned char>(arg[1])) &&
         arg[1] != '.';
}

std::string number_text(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

}  // namespace

void parse_by_rows(const std::vector<OptionSpec>& rows, const std::vector<std::string>& args,
                   const std::function<void(std::size_t, const std::vector<std::string>&)>& store) {
  std::vector<std::size_t> counts(rows.size(), 0);
  std::optional<std::size_t> last_positional;
  std::string last_value;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    check_help(arg);
    std::size_t row = 0;
    if (is_option_like(arg)) {
      while (row < rows.size() && (rows[row].positional || rows[row].name != arg)) ++row;
      if (row == rows.size()) throw UsageError{"unknown option " + arg};
      std::vector<std::string> values;
      for (std::size_t k = 0; k < rows[row].arity(); ++k)
        values.push_back(option_value(args, i, arg));
      ++counts[row];
      store(row, values);
      continue;
    }
    while (row < rows.size() && (!rows[row].positional || counts[row] >= rows[row].max_count))
      ++row;
    if (row == rows.size()) {
      std::string message = "unexpected argument \"" + arg + "\"";
      if (last_positional && rows[*last_positional].max_count == 1)
        message += " (" + rows[*last_positional].name + " is \"" + last_value + "\")";
      throw UsageError{message};
    }
    ++counts[row];
    last_positional = row;
    last_value = arg;
    store(row, {arg});
  }
  for (std::size_t row = 0; row < rows.size(); ++row)
    if (rows[row].positional && counts[row] < rows[row].min_count)
      throw UsageError{"missing " +
                       (rows[row].missing.empty() ? rows[row].name : rows[row].missing)};
  for (std::size_t row = 0; row < rows.size(); ++row)
    if (rows[row].required && counts[row] == 0) throw UsageError{"missing " + rows[row].label()};
}

bool NumberRange::contains(double value) const {
  return (low_open ? value > low : value >= low) && (high_open ? value < high : value <= high);
}

std::string NumberRange::description() const {
  if (!what.empty()) return what;
  const bool bounded_low = std::isfinite(low), bounded_high = std::isfinite(high);
  if (bounded_low && bounded_high)
    return std::string("a number in ") + (low_open ? "(" : "[") + number_text(low) + ", " +
           number_text(high) + (high_open ? ")" : "]");
  if (bounded_low) return std::string("a number ") + (low_open ? "> " : ">= ") + number_text(low);
  if (bounded_high)
    return std::string("a number ") + (high_open ? "< " : "<= ") + number_text(high);
  return "a number";
}

std::string WholeRange::description() const {
  if (!what.empty()) return what;
  if (high == std::numeric_limits<long long>::max())
    return "a whole number >= " + std::to_string(low);
  return "a whole number in [" + std::to_string(low) + ", " + std::to_string(high) + "]";
}

double number_in(const std::string& name, const std::string& text, const NumberRange& range) {
  const std::optional<double> value = parse_number(text);
  if (!value || !range.contains(*value))
    throw UsageError{name + ": expected " + range.description() + ", got \"" + text + "\""};
  return *value;
}

long long whole_number_in(const std::string& name, const std::string& text,
                          const WholeRange& range) {
  const std::optional<long long> value = parse_whole_number(text, range.low, range.high);
  if (!value)
    throw UsageError{name + ": expected " + range.description() + ", got \"" + text + "\""};
  return *value;
}

ProgressStyle progress_style_in(const std::string& text) {
  const std::optional<ProgressStyle> style = progress_style_named(text);
  if (!style) throw UsageError{"--progress: expected bar, plain or none, got \"" + text + "\""};
  return *style;
}

ProgressDisplay make_progress_display(std::optional<ProgressStyle> style, double quiet_for_s) {
  ProgressSettings settings;
  settings.style = style.value_or(default_progress_style());
  settings.quiet_for_s = quiet_for_s;
  return ProgressDisplay(std::cerr, std::move(settings));
}

}  // namespace hb
