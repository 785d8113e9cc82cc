// End-to-end: what `run`, `report` and `compare` show on stderr. On a
// terminal (a pseudo-terminal here): one live line redrawn in place with
// the phases, ticks and an ETA, erased at the end. Elsewhere: no redraws,
// nothing at all with --quiet; --progress overrides the guess.
#include <fcntl.h>
#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cerrno>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"

namespace {

using hb::test::contains;
using hb::test::kBoxPress;
using hb::test::kSource;

namespace fs = std::filesystem;
using hb::test::run_hapticbench;

// The smoke box press for one god-object, 60 s long and without the
// oracle: both passes last long enough (tenths of a second) to be redrawn
// with ticks done whatever the machine, since a phase shorter than the
// 0.1 s between redraws may never be drawn.
fs::path write_long_press(const fs::path& work) {
  nlohmann::json scenario = nlohmann::json::parse(hb::test::read_text_file(kBoxPress));
  scenario["trace"]["duration_s"] = 60;
  scenario["reference"] = {{"oracle", "none"}, {"analytic", "auto"}};
  nlohmann::json kept = nlohmann::json::array();
  for (const nlohmann::json& algorithm : scenario["algorithms"])
    if (algorithm["label"] == "god_object") kept.push_back(algorithm);
  scenario["algorithms"] = kept;
  const fs::path file = work / "long_press.json";
  std::ofstream(file) << scenario.dump(2);
  return file;
}

struct TerminalRun {
  int exit_code = -1;
  std::string terminal;  ///< what was written to the terminal (stderr)
  std::string stdout_text;
};

// Runs hapticbench with `args` in `work`, stderr on a pseudo-terminal and
// stdout to a file.
TerminalRun run_on_terminal(const std::vector<std::string>& args, const fs::path& work) {
  const fs::path out = work / "terminal_stdout.txt";
  winsize size{};
  size.ws_col = 160;
  size.ws_row = 40;
  int master = -1;
  const pid_t pid = forkpty(&master, nullptr, nullptr, &size);
  REQUIRE(pid >= 0);
  if (pid == 0) {
    const int file = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (file < 0 || ::chdir(work.c_str()) != 0) _exit(127);
    ::dup2(file, STDOUT_FILENO);
    std::vector<char*> argv{const_cast<char*>(hb::test::hapticbench_bin().c_str())};
    for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
    argv.push_back(nullptr);
    ::execv(hb::test::hapticbench_bin().c_str(), argv.data());
    _exit(127);
  }
  TerminalRun run;
  char buffer[4096];
  for (;;) {
    const ssize_t got = ::read(master, buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;  // EIO once the child and its terminal are gone
    run.terminal.append(buffer, static_cast<std::size_t>(got));
  }
  ::close(master);
  int status = 0;
  ::waitpid(pid, &status, 0);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.stdout_text = hb::test::read_text_file(out);
  return run;
}

}  // namespace

TEST_CASE("on a terminal, run shows one live line with phase, ticks and ETA, then erases it") {
  const hb::test::ScratchDir work("e2e_progress_terminal");
  const TerminalRun run =
      run_on_terminal({"run", write_long_press(work).string(), "--out", "press"}, work.path());
  INFO(run.terminal);
  REQUIRE(run.exit_code == 0);
  // The first phase is drawn as it starts; the passes as they go.
  CHECK(run.terminal.rfind("\r\033[K" + (work / "long_press.json").string() + ": loading", 0) == 0);
  for (const char* phase :
       {"box_press_box / god_object: timing pass [1-9][0-9,]*/60,000 ticks",
        "box_press_box / god_object: evaluation pass [1-9][0-9,]*/60,000 ticks"})
    CHECK(std::regex_search(run.terminal, std::regex(phase)));
  CHECK(std::regex_search(run.terminal, std::regex("[0-9,]+/60,000 ticks [0-9]+% elapsed "
                                                   "[0-9]{2}:[0-9]{2}, ETA [0-9]{2}:[0-9]{2}")));
  // Redrawn in place: carriage returns and erase-line, never a new line,
  // and the last thing written erases the line.
  CHECK(contains(run.terminal, "\r\033[K"));
  CHECK_FALSE(contains(run.terminal, "\n"));
  REQUIRE(run.terminal.size() >= 4);
  CHECK(run.terminal.substr(run.terminal.size() - 4) == "\r\033[K");
  // The table goes to stdout as without a terminal.
  CHECK(contains(run.stdout_text, "scenario box_press_box -> press/"));
  CHECK(contains(run.stdout_text, "god_object"));
}

TEST_CASE("on a terminal, --quiet and --progress plain draw nothing in place") {
  const hb::test::ScratchDir work("e2e_progress_terminal_quiet");
  const TerminalRun quiet =
      run_on_terminal({"run", kBoxPress, "--out", "a", "--quiet"}, work.path());
  CHECK(quiet.exit_code == 0);
  CHECK(quiet.terminal.empty());
  const TerminalRun plain =
      run_on_terminal({"run", kBoxPress, "--out", "b", "--progress", "plain"}, work.path());
  CHECK(plain.exit_code == 0);
  CHECK_FALSE(contains(plain.terminal, "\033["));
}

TEST_CASE("to a file, run redraws nothing, --quiet says nothing, --progress bar forces the bar") {
  const hb::test::ScratchDir work("e2e_progress_pipe");
  const auto plain = run_hapticbench("run " + kBoxPress + " --out a", work.path());
  INFO(plain.stderr_text);
  REQUIRE(plain.exit_code == 0);
  CHECK_FALSE(contains(plain.stderr_text, "\r"));
  CHECK_FALSE(contains(plain.stderr_text, "\033["));
  // A plain line names its phase and is a whole line.
  CHECK(std::regex_search(
      plain.stderr_text,
      std::regex("^(\\[[0-9]{2}:[0-9]{2}\\] box_press_box / [a-z_]+: [^\\n]+\\n)*$")));
  const auto quiet = run_hapticbench("run " + kBoxPress + " --out b --quiet", work.path());
  CHECK(quiet.exit_code == 0);
  CHECK(quiet.stderr_text.empty());
  CHECK(contains(quiet.stdout_text, "scenario box_press_box -> b/"));
  const auto bar = run_hapticbench("run " + kBoxPress + " --out c --progress bar", work.path());
  CHECK(bar.exit_code == 0);
  CHECK(contains(bar.stderr_text, "\r\033[Kbox_press_box / "));
}

TEST_CASE("a bad --progress style is a usage error naming the styles") {
  const hb::test::ScratchDir work("e2e_progress_usage");
  for (const char* command : {"run", "validate", "report", "compare", "stability", "sweep"}) {
    const auto result =
        run_hapticbench(std::string(command) + " x.json --progress fancy", work.path());
    INFO(command << ": " << result.stderr_text);
    CHECK(result.exit_code == 2);
    CHECK(contains(result.stderr_text, "--progress: expected bar, plain or none, got \"fancy\""));
  }
}

TEST_CASE("report on a terminal draws only in place, and writes the page") {
  const hb::test::ScratchDir work("e2e_progress_report");
  REQUIRE(
      run_hapticbench("run " + kBoxPress + " --out runs/press --quiet", work.path()).exit_code ==
      0);
  const TerminalRun report =
      run_on_terminal({"report", "runs", "--out", "report.html", "--progress", "bar"}, work.path());
  INFO(report.terminal);
  REQUIRE(report.exit_code == 0);
  CHECK(fs::is_regular_file(work / "report.html"));
  CHECK(contains(report.stdout_text, "report: report.html (1 run folder)"));
  // Whatever was drawn (a report of one folder may take less than the
  // quiet second) was drawn in place and erased; the renderer's own
  // progress lines are checked by tests/reports/hapticbench_report/inputs_test.py.
  CHECK_FALSE(contains(report.terminal, "\n"));
  if (!report.terminal.empty()) {
    CHECK(report.terminal.rfind("\r\033[Kreport: ", 0) == 0);
    CHECK(report.terminal.substr(report.terminal.size() - 4) == "\r\033[K");
  }
}
