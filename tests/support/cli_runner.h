// Test support: runs the command line tool of the tests' own build in a
// folder and returns its exit code and output.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

#include "tests/support/scratch_dir.h"

namespace hb::test {

/// `relative` inside the build this test executable belongs to (the build
/// folder holds it as <build>/tests/<executable>), found at run time, so
/// that a test object compiled in one build and linked into another's
/// executable (the quick sanitizer pass links the Release build's,
/// cmake/hapticbench.cmake) uses what the build it was linked into made;
/// `fallback`, the compiling build's path, when nothing is there.
inline std::filesystem::path in_own_build(const std::filesystem::path& relative,
                                          const std::filesystem::path& fallback) {
  std::error_code error;
  const std::filesystem::path executable = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) return fallback;
  const std::filesystem::path there = executable.parent_path().parent_path() / relative;
  return std::filesystem::exists(there, error) ? there : fallback;
}

/// The command line tool of the build this test executable belongs to.
inline const std::string& hapticbench_bin() {
  static const std::string tool = in_own_build("harness/cli/hapticbench", HAPTICBENCH_BIN).string();
  return tool;
}

}  // namespace hb::test

// Whether the command line tool under test runs with AddressSanitizer: true
// when this process has AddressSanitizer's runtime, which a sanitized
// build links into every executable, also into tests whose own code is
// compiled without it (the quick sanitizer pass), so that the compiler's
// __SANITIZE_ADDRESS__ does not say.
extern "C" void __asan_init() __attribute__((weak));

namespace hb::test {

inline bool tool_runs_with_asan() { return &__asan_init != nullptr; }

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
  const std::string command = "cd '" + work.string() + "' && (" + setup + " '" + hapticbench_bin() +
                              "' " + args + ") > '" + out.string() + "' 2> '" + err.string() + "'";
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
                                             const std::filesystem::path& work, long memory_kib) {
  // AddressSanitizer reserves terabytes of address space up front: no limit
  // can be set; the checks on exit code and message still run.
  if (tool_runs_with_asan()) return run_hapticbench(args, work);
  return run_hapticbench_after("ulimit -v " + std::to_string(memory_kib) + " &&", args, work);
}

}  // namespace hb::test
