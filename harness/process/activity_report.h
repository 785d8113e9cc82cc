// What a command run in a child process is doing, told to its parent line
// by line through an inherited file descriptor, so that the parent can say
// what was running when the child crashed or ended without its output
// (commands that run plugins run them in a child: plugin_isolation.h).
// Each line is one write(2): it reaches the parent even when the child dies
// right after.
#pragma once

#include <string>

namespace hb {

/// The environment variable that gives a child the descriptor to report to.
inline constexpr const char* kActivityFdVariable = "HAPTICBENCH_ACTIVITY_FD";

/// Takes the descriptor from the environment (once, at start-up): removes
/// the variable and closes the descriptor on exec, so that processes this
/// one starts do not report in its name.
void take_activity_report_fd();

/// Whether this process reports to a parent.
bool reports_activity();

/// Sends one line ("running <label>\t<plugin path or nothing>", "idle",
/// "ended <code>"); does nothing when this process reports to nobody.
void report_activity(const std::string& line);

}  // namespace hb
