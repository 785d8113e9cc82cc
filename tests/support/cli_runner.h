// Test support: runs the hapticbench binary (HAPTICBENCH_BIN) in a folder
// and returns its exit code and output.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "tests/support/scratch_dir.h"

// Whether the command line tool under test runs with AddressSanitizer: the
// tests' own code may be compiled without it (the quick sanitizer pass,
// cmake/hapticbench.cmake), so its own __SANITIZE_ADDRESS__ does not say.
#if defined(__SANITIZE_ADDRESS__) || defined(HAPTICBENCH_TOOL_ASAN)
#define HB_TOOL_ASAN 1
#else
#define HB_TOOL_ASAN 0
#endif

namespace hb::test {

struct CommandResult {
  int exit_code = -1;
  std::string stdout_text;
  std::string stderr_text;
};

/// Runs `hapticbench ARGS` with `work` as the current folder, after the
/// shell command `setup` (e.g. a ulimit) when one is given; ARGS is passed
/// to the shell as written.
inline CommandResult run_hapticbench_after(const std::string& setup, const std::string& args,
                                           const std::filesystem::path& work) {
  const std::filesystem::path out = work / "stdout.txt", err = work / "stderr.txt";
  const std::string command = "cd '" + work.string() + "' && (" + setup + " '" +
                              std::string(HAPTICBENCH_BIN) + "' " + args + ") > '" + out.string() +
                              "' 2> '" + err.string() + "'";
  const int status = std::system(command.c_str());
  CommandResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.stdout_text = read_text_file(out);
  result.stderr_text = read_text_file(err);
  return result;
}

inline CommandResult run_hapticbench(const std::string& args, const std::filesystem::path& work) {
  return run_hapticbench_after("", args, work);
}

/// As run_hapticbench, with the address space limited to `memory_kib`
/// (ulimit -v): an input that makes the process grab more than that ends
/// in a crash or bad_alloc instead of passing.
inline CommandResult run_hapticbench_limited(const std::string& args,
                                             const std::filesystem::path& work,
                                             [[maybe_unused]] long memory_kib) {
#if HB_TOOL_ASAN
  // AddressSanitizer reserves terabytes of address space up front: no limit
  // can be set; the checks on exit code and message still run.
  return run_hapticbench(args, work);
#else
  return run_hapticbench_after("ulimit -v " + std::to_string(memory_kib) + " &&", args, work);
#endif
}

}  // namespace hb::test
