// What every command does with its arguments: a usage mistake is thrown as
// UsageError and printed with the command's usage text (exit 2); -h/--help
// is thrown as HelpRequested and prints the usage text (exit 0).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

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
/// UsageError "OPTION needs a value" when there is none.
const std::string& option_value(const std::vector<std::string>& args, std::size_t& i);

/// The whole text as a finite number, in C locale notation ("0.5", "1e-6";
/// no spaces, no sign "+", no "inf"); nullopt otherwise. Every command
/// reads its numeric options with this or parse_whole_number.
std::optional<double> parse_number(std::string_view text);

/// The whole text as a whole number in [min, max]; nullopt otherwise.
std::optional<long long> parse_whole_number(std::string_view text, long long min, long long max);

/// Throws HelpRequested when `arg` is -h or --help.
void check_help(const std::string& arg);

/// The usage lines of --progress and --quiet, for commands that take them.
inline constexpr std::string_view kProgressUsage =
    "  --progress STYLE  how progress shows on stderr: bar (a live line; the default on a\n"
    "                  terminal), plain (a line per phase; the default otherwise) or none\n"
    "  --quiet         no progress, as --progress none\n";

/// Reads --progress STYLE or --quiet at args[i] into `style` (advancing i
/// past the value); false when args[i] is neither. Throws UsageError for a
/// style other than bar, plain or none.
bool parse_progress_option(const std::vector<std::string>& args, std::size_t& i,
                           std::optional<ProgressStyle>& style);

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
