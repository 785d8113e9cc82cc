// The subcommands of `hapticbench`. Each takes the arguments after its name
// and returns the process exit code: 0 ok / within budget, 1 a budget or
// regression failed, 2 bad input or usage, 3 internal error.
#pragma once

#include <string>
#include <vector>

namespace hb {

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

}  // namespace hb
