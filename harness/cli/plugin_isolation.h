// Plugins run in a child process: a plugin's crash, its exit() or _exit()
// inside step(), or an exception it throws ends the child, and the parent
// names the plugin and the label that was running, and never reports
// success without the output the command promised. The child tells the
// parent what it runs through activity_report.h.
#pragma once

#include <string>
#include <vector>

namespace hb {

/// Whether a command that will run these algorithms (names) should run in
/// a child: one comes from a plugin, and this process is not such a child.
bool should_isolate_plugins(const std::vector<std::string>& algorithm_names);

/// Runs `<this executable> <command> <args>` in a child with this
/// process's stdout and stderr (the plugins loaded here reach it through
/// HAPTICBENCH_PLUGINS), passes SIGINT and SIGTERM on, waits, and returns
/// the exit code for this command: the child's when it ended by returning
/// from main (its message printed), else kExitInternal (3) after a message
/// naming the plugin and the label that was running.
int run_plugins_isolated(const std::string& command, const std::vector<std::string>& args);

}  // namespace hb
