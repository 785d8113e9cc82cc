// What every command does with its arguments: a usage mistake is thrown as
// UsageError and printed with the command's usage text (exit 2); -h/--help
// is thrown as HelpRequested and prints the usage text (exit 0). Each
// command's arguments are read by its option table (option_table.h), which
// reads values and numbers with these.
#pragma once

#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "harness/cli/command_syntax.h"
#include "harness/progress/progress_display.h"

namespace hb {

/// A usage mistake on the command line, e.g. "--jobs needs a value".
struct UsageError {
  std::string message;
};

/// -h or --help was given.
struct HelpRequested {};

/// Prints "error: MESSAGE" and `usage` to stderr; returns exit code 2.
int print_usage_error(const UsageError& error, std::string_view usage);
/// Prints `usage` to stdout; returns exit code 0.
int print_help(std::string_view usage);

/// The value after the option args[i]; advances i past it. Throws
/// UsageError "OPTION needs a value" when there is none (OPTION: `option`,
/// or args[i] when empty: the second value of "--range LO HI" names the
/// option, not the first value).
const std::string& option_value(const std::vector<std::string>& args, std::size_t& i,
                                const std::string& option = "");

/// The whole text as a finite number, in C locale notation ("0.5", "1e-6";
/// no spaces, no sign "+", no "inf"); nullopt otherwise. Every command
/// reads its numeric options with this or parse_whole_number.
std::optional<double> parse_number(std::string_view text);

/// The whole text as a whole number in [min, max]; nullopt otherwise.
std::optional<long long> parse_whole_number(std::string_view text, long long min, long long max);

/// Throws HelpRequested when `arg` is -h or --help.
void check_help(const std::string& arg);

/// Walks `args` by `rows`: calls store(row index, values) for each option
/// and each positional value, in order. Throws HelpRequested at -h or
/// --help, UsageError for an unknown option ("unknown option --x"), a
/// missing value ("--x needs a value"), a positional too many, a missing
/// positional or required option ("missing ..."), and whatever `store`
/// throws.
void parse_by_rows(const std::vector<OptionSpec>& rows, const std::vector<std::string>& args,
                   const std::function<void(std::size_t, const std::vector<std::string>&)>& store);

/// Numbers a numeric option accepts: finite, within the bounds.
struct NumberRange {
  double low = -HUGE_VAL, high = HUGE_VAL;
  bool low_open = false, high_open = false;  ///< the bound itself is refused
  std::string what;  ///< what the message calls them; empty: "a number > 0" from the bounds
  bool contains(double value) const;
  std::string description() const;
};
inline NumberRange any_number() { return {}; }
inline NumberRange at_least(double low) { return {low, HUGE_VAL, false, false, ""}; }
inline NumberRange above(double low) { return {low, HUGE_VAL, true, false, ""}; }
inline NumberRange probability() { return {0, 1, true, false, "a probability in (0, 1]"}; }

/// Whole numbers a numeric option accepts: [low, high].
struct WholeRange {
  long long low = 0, high = std::numeric_limits<long long>::max();
  std::string what;  ///< what the message calls them; empty: "a whole number in [1, 8]"
  std::string description() const;
};

/// `text` in `range`; throws UsageError `NAME: expected a number > 0, got "x"`.
double number_in(const std::string& name, const std::string& text, const NumberRange& range);
long long whole_number_in(const std::string& name, const std::string& text,
                          const WholeRange& range);
/// The style --progress names; throws UsageError naming the styles.
ProgressStyle progress_style_in(const std::string& text);

/// A progress display on stderr in the style asked for, or the default
/// one; `quiet_for_s`: see ProgressSettings.
ProgressDisplay make_progress_display(std::optional<ProgressStyle> style, double quiet_for_s = 0);

/// Runs `parse()` (which may throw UsageError or HelpRequested) and returns
/// what it returns; on a usage error or a request for help prints it with
/// `usage`, sets `exit_code` (2 or 0) and returns nullopt.
template <class Parse>
auto parse_command_line(Parse parse, std::string_view usage, int& exit_code)
    -> std::optional<decltype(parse())> {
  try {
    return parse();
  } catch (const UsageError& error) {
    exit_code = print_usage_error(error, usage);
  } catch (const HelpRequested&) {
    exit_code = print_help(usage);
  }
  return std::nullopt;
}

}  // namespace hb
