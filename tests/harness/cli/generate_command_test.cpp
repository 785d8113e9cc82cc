// `hapticbench generate`: the command writes exactly the generator's trace,
// parses parameter values, and maps usage and input errors to exit code 2.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "harness/cli/commands.h"
#include "harness/trace/generators.h"
#include "harness/trace/trace.h"

namespace {

namespace fs = std::filesystem;

/// Runs the command with stderr captured.
struct CommandResult {
  int exit_code;
  std::string error_text;
};

CommandResult run_generate(const std::vector<std::string>& args) {
  std::ostringstream captured_err, captured_out;
  std::streambuf* old_err = std::cerr.rdbuf(captured_err.rdbuf());
  std::streambuf* old_out = std::cout.rdbuf(captured_out.rdbuf());
  const int code = hb::generate_command(args);
  std::cerr.rdbuf(old_err);
  std::cout.rdbuf(old_out);
  return {code, captured_err.str()};
}

fs::path scratch_directory() {
  const fs::path dir =
      fs::temp_directory_path() / ("hb_generate_command_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

}  // namespace

TEST_CASE("generate writes the generator's trace with the given seed and parameters") {
  const fs::path dir = scratch_directory();
  const std::string out = (dir / "rub.csv").string();
  const CommandResult result =
      run_generate({"rub", "--duration", "0.5", "--seed", "9", "--param", "centre=0.1,0,0.05",
                    "--param", "turns=1.5", "--param", "radius=0.004", "--out", out});
  REQUIRE(result.exit_code == hb::kExitOk);
  CHECK(fs::exists(dir / "rub.json"));

  hb::ParamSet params;
  params.set("centre", std::vector<double>{0.1, 0, 0.05});
  params.set("turns", 1.5);
  params.set("radius", 0.004);
  const hb::Trace expected = hb::generate_trace("rub", {0.5, 9, params}, "generator");
  const hb::Trace read = hb::read_trace_file(out, hb::TraceFileFormat::kHapticbenchCsv);
  REQUIRE(read.samples.size() == expected.samples.size());
  for (std::size_t k = 0; k < read.samples.size(); ++k) {
    CHECK(read.samples[k].t_ns == expected.samples[k].t_ns);
    CHECK(read.samples[k].pose.p == expected.samples[k].pose.p);
    CHECK(read.samples[k].pose.q.coeffs() == expected.samples[k].pose.q.coeffs());
    CHECK(read.samples[k].twist->v == expected.samples[k].twist->v);
  }
  CHECK(read.info.source == "generator:rub");
  fs::remove_all(dir);
}

TEST_CASE("generate reports bad usage and bad input with exit code 2") {
  const fs::path dir = scratch_directory();
  const std::string out = (dir / "x.csv").string();
  struct Bad {
    std::vector<std::string> args;
    std::string says;
  };
  const std::vector<Bad> cases = {
      {{"press", "--duration", "1"}, "missing --out"},
      {{"press", "--out", out}, "missing --duration"},
      {{"--duration", "1", "--out", out}, "missing the generator NAME"},
      {{"press", "--duration", "soon", "--out", out}, "--duration"},
      {{"press", "--duration", "1", "--seed", "-3", "--out", out}, "--seed"},
      {{"press", "--duration", "1", "--param", "depth", "--out", out}, "key=value"},
      {{"press", "--duration", "1", "--param", "depth=1", "--param", "depth=2", "--out", out},
       "more than once"},
      {{"press", "--duration", "1", "--colour", "red", "--out", out}, "unknown option --colour"},
      {{"press", "slide", "--duration", "1", "--out", out}, "unexpected argument"},
      {{"wobble", "--duration", "1", "--out", out}, "unknown generator \"wobble\""},
      {{"press", "--duration", "1", "--param", "dpeth=0.01", "--out", out},
       "--param/dpeth: unknown parameter"},
      {{"press", "--duration", "1", "--param", "start=0,0,x", "--out", out}, "--param/start"},
      {{"press", "--duration", "1e6", "--out", out}, "duration_s"},
  };
  for (const Bad& bad : cases) {
    INFO(bad.says);
    const CommandResult result = run_generate(bad.args);
    CHECK(result.exit_code == hb::kExitBadInput);
    CHECK(result.error_text.find(bad.says) != std::string::npos);
    INFO(result.error_text);
  }
  // Nothing was written by a failing command.
  CHECK_FALSE(fs::exists(out));
  fs::remove_all(dir);
}
