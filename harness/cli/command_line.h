// What every command does with its arguments: a usage mistake is thrown as
// UsageError and printed with the command's usage text (exit 2); -h/--help
// is thrown as HelpRequested and prints the usage text (exit 0).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

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

/// Throws HelpRequested when `arg` is -h or --help.
void check_help(const std::string& arg);

}  // namespace hb
