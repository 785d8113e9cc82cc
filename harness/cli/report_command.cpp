// `hapticbench report`: one self-contained HTML page (figures inline, no
// external resources) from run folders. Finds every summary.json beneath the
// folders given, checks that each is a schema 1 summary, and hands the run
// folders to reports/render_report.py (Python 3 with matplotlib), which
// draws the figures and writes the page under a temporary name; the page is
// renamed into place only when complete.
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "algorithms/core/file_trust.h"
#include "algorithms/core/replacing_file.h"
#include "hapticbench/input_error.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/cli/run_folder_search.h"
#include "harness/history/history_store.h"
#include "harness/metrics/metric_table.h"
#include "harness/output/output_ownership.h"
#include "harness/process/child_process.h"
#include "harness/process/interrupt.h"
#include "harness/process/scratch_folder.h"
#include "harness/scenario/json_fields.h"

namespace hb {

namespace {

namespace fs = std::filesystem;

const std::string kReportUsage =
    "usage: hapticbench report RUN_DIR... [--history DIR] [--out report.html]\n"
    "                          [--progress STYLE] [--quiet]\n"
    "  RUN_DIR: a run folder (with summary.json) or a folder holding run folders at any depth;\n"
    "           stability.json files beneath it (hapticbench stability) make the margin table,\n"
    "           zwidth.json files (hapticbench zwidth) the Z-width figures\n"
    "  --out FILE: the HTML page to write (default report.html in the current folder)\n"
    "  --history DIR: runs kept by commit (hapticbench history add): each metric's trend\n"
    "           per scenario and label, and where it first moved; RUN_DIR may then be left out\n"
    "  environment: HAPTICBENCH_PYTHON (default /usr/bin/python3, needs matplotlib),\n"
    "               HAPTICBENCH_REPORTS_DIR (where render_report.py is; default\n"
    "               ../share/hapticbench/reports from the binary's folder)\n" +
    std::string(kProgressUsage);

constexpr const char* kDefaultPython = "/usr/bin/python3";

// In the head of every page (reports/report_template.html): how a later
// report recognises a page it may replace.
constexpr const char* kReportGeneratorMeta =
    "<meta name=\"generator\" content=\"hapticbench report\">";
constexpr const char* kRendererScript = "render_report.py";

struct ReportOptions {
  std::vector<fs::path> inputs;
  fs::path out = "report.html";
  std::optional<fs::path> history;  ///< --history: a history folder
  std::optional<ProgressStyle> progress;
};

ReportOptions parse_report_options(const std::vector<std::string>& args) {
  ReportOptions options;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    check_help(arg);
    if (arg == "--out") {
      options.out = option_value(args, i);
    } else if (arg == "--history") {
      options.history = option_value(args, i);
    } else if (parse_progress_option(args, i, options.progress)) {
    } else if (arg.size() > 1 && arg[0] == '-') {
      throw UsageError{"unknown option " + arg};
    } else {
      options.inputs.emplace_back(arg);
    }
  }
  if (options.inputs.empty() && !options.history) throw UsageError{"missing RUN_DIR"};
  if (options.out.filename().empty()) throw UsageError{"--out: expected a file name"};
  return options;
}

/// Runs a program (looked up on PATH when the name has no slash) and waits
/// for it. quiet: its output goes to /dev/null. Returns its exit code, or
/// -1 when it could not be started or did not exit normally.
int run_program(const std::vector<std::string>& argv, bool quiet) {
  ChildOptions options;
  options.search_path = true;
  if (quiet) options.stdout_path = options.stderr_path = "/dev/null";
  try {
    const ProcessEnd end = ChildProcess(argv, options).wait();
    return end.exited ? end.exit_code : -1;
  } catch (const std::runtime_error&) {
    return -1;
  }
}

/// The fd on which the renderer writes its progress, one line per step:
/// "<done> <total> <unit> <phase...>" (unit "-": none).
constexpr int kRendererProgressFd = 3;

/// Shows one progress line of the renderer; ignores what it cannot read.
void show_renderer_progress(const std::string& line, ProgressDisplay& progress,
                            std::string& current_phase) {
  std::istringstream in(line);
  int64_t done = 0, total = 0;
  std::string unit, phase;
  if (!(in >> done >> total >> unit) || !std::getline(in >> std::ws, phase)) return;
  if (phase != current_phase) {
    progress.phase(phase, total, false, unit == "-" ? std::string() : unit);
    current_phase = phase;
  }
  progress.advance(done);
}

/// Runs the report renderer and waits for it, showing the progress it
/// writes on fd kRendererProgressFd; its stderr goes to `stderr_file` (so
/// that it never shares a line with the live one). Returns its exit code,
/// or -1 when it could not be started or did not exit normally.
int run_renderer(const std::vector<std::string>& argv, const fs::path& stderr_file,
                 ProgressDisplay& progress) {
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) return -1;
  ChildOptions options;
  options.search_path = true;
  options.stderr_path = stderr_file;
  options.inherit_fds = {{pipe_fds[1], kRendererProgressFd}};
  // A terminal's Ctrl-C reaches this process only; it stops the renderer
  // (no Python traceback) and exits with 130.
  options.own_process_group = true;
  std::optional<ChildProcess> renderer;
  try {
    renderer.emplace(argv, options);
  } catch (const std::runtime_error&) {
  }
  ::close(pipe_fds[1]);
  if (!renderer) {
    ::close(pipe_fds[0]);
    return -1;
  }
  progress.task("report");
  std::string pending, current_phase;
  char buffer[4096];
  for (;;) {
    // Waits at most 0.2 s at a time, so that a stop signal is seen even
    // while the renderer writes nothing.
    pollfd waiting{pipe_fds[0], POLLIN, 0};
    const int ready = ::poll(&waiting, 1, 200);
    if (interrupt_signal() != 0) {
      ::close(pipe_fds[0]);
      throw_if_interrupted();  // the renderer is stopped as `renderer` goes
    }
    if (ready <= 0) continue;
    const ssize_t got = ::read(pipe_fds[0], buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;
    pending.append(buffer, static_cast<std::size_t>(got));
    for (std::size_t end; (end = pending.find('\n')) != std::string::npos;) {
      show_renderer_progress(pending.substr(0, end), progress, current_phase);
      pending.erase(0, end + 1);
    }
  }
  ::close(pipe_fds[0]);
  progress.finish_task();
  const ProcessEnd end = renderer->wait();
  return end.exited ? end.exit_code : -1;
}

/// Whether `path` is a page `hapticbench report` wrote: the renderer puts
/// kReportGeneratorMeta in every page's head.
bool is_report_page(const fs::path& path) {
  constexpr std::size_t kHeadBytes = 4096;
  std::ifstream in(path, std::ios::binary);
  std::string head(kHeadBytes, '\0');
  in.read(head.data(), static_cast<std::streamsize>(kHeadBytes));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return head.find(kReportGeneratorMeta) != std::string::npos;
}

std::string environment_or(const char* name, const std::string& fallback) {
  const char* value = std::getenv(name);
  return value != nullptr && *value != '\0' ? std::string(value) : fallback;
}

// Where render_report.py and its template are: HAPTICBENCH_REPORTS_DIR (the
// user's explicit choice), else share/hapticbench/reports beside the
// binary's folder (PREFIX/bin and PREFIX/share when installed; the build
// links build/harness/share to the source tree's reports/). That one runs
// only when nobody but this user or root can change it: a copy of the
// binary in a shared folder (/tmp/bin) must not run a stranger's
// /tmp/share/hapticbench/reports. InputError naming the path otherwise.
fs::path reports_dir() {
  const char* chosen = std::getenv("HAPTICBENCH_REPORTS_DIR");
  if (chosen != nullptr && *chosen != '\0') return chosen;
  std::error_code error;
  const fs::path executable = fs::read_symlink("/proc/self/exe", error);
  const fs::path beside =
      executable.parent_path().parent_path() / "share" / "hapticbench" / "reports";
  if (!fs::exists(beside / kRendererScript, error)) return beside;  // said by the caller
  for (const fs::path& part : {beside / kRendererScript, beside / "hapticbench_report"}) {
    const std::string why = writable_by_others(part);
    if (!why.empty())
      throw InputError(beside.string(), "",
                       "the report renderer beside this hapticbench is not run: " + why +
                           ", so another user could change the code it runs; install "
                           "hapticbench (cmake --install) or set HAPTICBENCH_REPORTS_DIR to "
                           "a reports/ folder you trust");
  }
  return beside;
}

}  // namespace

int report_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const auto parsed_options =
      parse_command_line([&] { return parse_report_options(args); }, kReportUsage, exit_code);
  if (!parsed_options) return exit_code;
  const ReportOptions& options = *parsed_options;

  // Never replace what hapticbench did not write (checked before any work).
  require_replaceable_file(options.out, "report", is_report_page);

  // Every run folder once, in the order given, each input's folders sorted;
  // each summary checked for what the renderer relies on. Results of
  // `hapticbench stability` (stability.json) beneath the inputs become the
  // stability-margin table, those of `hapticbench zwidth` (zwidth.json) the
  // Z-width figures; an input may hold only those.
  std::vector<fs::path> run_inputs, stability_files, zwidth_files;
  for (const fs::path& input : options.inputs) {
    const std::vector<fs::path> margins = find_files_named(input, "stability.json");
    const std::vector<fs::path> maps = find_files_named(input, "zwidth.json");
    stability_files.insert(stability_files.end(), margins.begin(), margins.end());
    zwidth_files.insert(zwidth_files.end(), maps.begin(), maps.end());
    if ((margins.empty() && maps.empty()) || !find_files_named(input, "summary.json").empty())
      run_inputs.push_back(input);
  }
  const std::vector<fs::path> folders =
      run_inputs.empty() ? std::vector<fs::path>() : find_run_folders(run_inputs);
  for (const fs::path& folder : folders) read_run_summary(folder / "summary.json");
  if (options.history) {
    const std::vector<HistoryEntry> entries = read_history(*options.history);
    if (entries.empty())
      throw InputError(options.history->string(), "",
                       "no history here: `hapticbench history add` writes one");
  }

  const fs::path script = reports_dir() / kRendererScript;
  if (!fs::is_regular_file(script)) {
    std::cerr << "error: " << script.string()
              << ": the report renderer is not there; set HAPTICBENCH_REPORTS_DIR to the "
                 "project's reports/ folder\n";
    return kExitBadInput;
  }
  const std::string python = environment_or("HAPTICBENCH_PYTHON", kDefaultPython);
  if (run_program({python, "-c", "import matplotlib"}, true) != 0) {
    std::cerr << "error: " << python
              << " cannot import matplotlib: install python3-matplotlib (scripts/setup "
                 "installs it) or set HAPTICBENCH_PYTHON to a Python 3 that has matplotlib\n";
    return kExitBadInput;
  }

  const fs::path out = options.out;
  std::error_code error;
  if (out.has_parent_path()) fs::create_directories(out.parent_path(), error);
  if (error) {
    std::cerr << "error: " << out.string() << ": cannot create the folder: " << error.message()
              << "\n";
    return kExitBadInput;
  }
  // A hidden name beside the page, so the rename cannot cross file systems,
  // created exclusively (never a file or symlink planted there before).
  // Refuses an unwritable destination before rendering, naming the user's
  // path.
  std::optional<TemporarySibling> page;
  try {
    page.emplace(out);
  } catch (const fs::filesystem_error& failure) {
    std::cerr << "error: " << out.string() << ": cannot write the report there ("
              << failure.code().message() << ")\n";
    return kExitBadInput;
  }
  const fs::path temporary = page->path();

  // The metric table the summary table's columns come from (metric_table.h).
  const ScratchFolder scratch("hapticbench-report");
  const fs::path table = scratch.path() / "metric_table.json";
  std::ofstream(table) << metric_table_json().dump() << "\n";

  std::vector<std::string> command = {python,
                                      "-B",
                                      script.string(),
                                      "--out",
                                      temporary.string(),
                                      "--metric-table",
                                      table.string(),
                                      "--progress-fd",
                                      std::to_string(kRendererProgressFd)};
  for (const fs::path& file : stability_files) {
    command.push_back("--stability");
    command.push_back(file.string());
  }
  for (const fs::path& file : zwidth_files) {
    command.push_back("--zwidth");
    command.push_back(file.string());
  }
  if (options.history) {
    command.push_back("--history");
    command.push_back(options.history->string());
  }
  for (const fs::path& folder : folders) command.push_back(folder.string());
  const fs::path renderer_stderr = scratch.path() / "renderer_stderr.txt";
  int status = 0;
  {
    // Drawing the figures takes seconds (tens on large suites).
    ProgressDisplay progress = make_progress_display(options.progress, 1.0);
    status = run_renderer(command, renderer_stderr, progress);
  }
  {
    std::ifstream in(renderer_stderr, std::ios::binary);
    const std::string said((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::cerr << said << std::flush;
  }
  if (status != 0) {
    if (status == kExitBadInput) return kExitBadInput;  // the renderer named the file
    std::cerr << "internal error: " << script.string() << " failed"
              << (status < 0 ? std::string(" to start")
                             : " with exit code " + std::to_string(status))
              << "\n";
    return kExitInternal;
  }
  if (!is_report_page(temporary)) {
    std::cerr << "internal error: " << script.string()
              << " exited 0 but wrote no report page; nothing was written to " << out.string()
              << "\n";
    return kExitInternal;
  }
  try {
    page->commit();
  } catch (const fs::filesystem_error& failure) {
    std::cerr << "error: " << out.string()
              << ": cannot write the report: " << failure.code().message() << "\n";
    return kExitBadInput;
  }
  std::cout << "report: " << out.string() << " (" << folders.size() << " run folder"
            << (folders.size() == 1 ? "" : "s");
  if (!stability_files.empty())
    std::cout << ", " << stability_files.size() << " stability margin"
              << (stability_files.size() == 1 ? "" : "s");
  if (!zwidth_files.empty())
    std::cout << ", " << zwidth_files.size() << " Z-width map"
              << (zwidth_files.size() == 1 ? "" : "s");
  std::cout << ")\n";
  return kExitOk;
}

}  // namespace hb
