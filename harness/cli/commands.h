// The subcommands of `hapticbench`. Each takes the arguments after its name
// and returns the process exit code: 0 ok / within budget, 1 a budget or
// regression failed, 2 bad input or usage, 3 internal error. Each has an
// option table (option_table.h) whose rows and text its *_syntax() gives;
// command_table.h lists them.
#pragma once

#include <string>
#include <vector>

namespace hb {

struct CommandSyntax;

enum ExitCode : int { kExitOk = 0, kExitBudgetFailed = 1, kExitBadInput = 2, kExitInternal = 3 };

int run_command(const std::vector<std::string>& args);        ///< hapticbench run
int validate_command(const std::vector<std::string>& args);   ///< hapticbench validate
int list_command(const std::vector<std::string>& args);       ///< hapticbench list
int generate_command(const std::vector<std::string>& args);   ///< hapticbench generate
int report_command(const std::vector<std::string>& args);     ///< hapticbench report
int compare_command(const std::vector<std::string>& args);    ///< hapticbench compare
int sweep_command(const std::vector<std::string>& args);      ///< hapticbench sweep
int ccd_command(const std::vector<std::string>& args);        ///< hapticbench ccd
int export_command(const std::vector<std::string>& args);     ///< hapticbench export
int stability_command(const std::vector<std::string>& args);  ///< hapticbench stability
int zwidth_command(const std::vector<std::string>& args);     ///< hapticbench zwidth
int init_command(const std::vector<std::string>& args);       ///< hapticbench init
int history_command(const std::vector<std::string>& args);    ///< hapticbench history
/// hapticbench count-instructions (internal: the child of run --instructions)
int count_instructions_command(const std::vector<std::string>& args);

const CommandSyntax& run_syntax();
const CommandSyntax& validate_syntax();
const CommandSyntax& list_syntax();
const CommandSyntax& generate_syntax();
const CommandSyntax& report_syntax();
const CommandSyntax& compare_syntax();
const CommandSyntax& sweep_syntax();
const CommandSyntax& ccd_syntax();
const CommandSyntax& export_syntax();
const CommandSyntax& stability_syntax();
const CommandSyntax& zwidth_syntax();
const CommandSyntax& init_syntax();
const CommandSyntax& history_syntax();
const CommandSyntax& count_instructions_syntax();

}  // namespace hb
