#include "harness/cli/command_line.h"

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
  return args[++i];
}

void check_help(const std::string& arg) {
  if (arg == "-h" || arg == "--help") throw HelpRequested{};
}

}  // namespace hb
