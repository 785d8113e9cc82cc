#include "harness/cli/report_renderer.h"

#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "algorithms/core/file_trust.h"
#include "hapticbench/input_error.h"
#include "harness/cli/child_line_pipe.h"
#include "harness/process/child_process.h"
#include "harness/process/interrupt.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

constexpr const char* kDefaultPython = "/usr/bin/python3";
constexpr const char* kRendererScript = "render_report.py";

// In the head of every page (reports/report_template.html): how a later
// report recognises a page it may replace.
constexpr const char* kReportGeneratorMeta =
    "<meta name=\"generator\" content=\"hapticbench report\">";

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

}  // namespace

bool is_report_page(const fs::path& path) {
  constexpr std::size_t kHeadBytes = 4096;
  std::ifstream in(path, std::ios::binary);
  std::string head(kHeadBytes, '\0');
  in.read(head.data(), static_cast<std::streamsize>(kHeadBytes));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return head.find(kReportGeneratorMeta) != std::string::npos;
}

fs::path report_renderer_script() {
  const char* chosen = std::getenv("HAPTICBENCH_REPORTS_DIR");
  if (chosen != nullptr && *chosen != '\0') return fs::path(chosen) / kRendererScript;
  std::error_code error;
  const fs::path executable = fs::read_symlink("/proc/self/exe", error);
  const fs::path beside =
      executable.parent_path().parent_path() / "share" / "hapticbench" / "reports";
  if (!fs::exists(beside / kRendererScript, error)) return beside / kRendererScript;
  for (const fs::path& part : {beside / kRendererScript, beside / "hapticbench_report"}) {
    const std::string why = writable_by_others(part);
    if (!why.empty())
      throw InputError(beside.string(), "",
                       "the report renderer beside this hapticbench is not run: " + why +
                           ", so another user could change the code it runs; install "
                           "hapticbench (cmake --install) or set HAPTICBENCH_REPORTS_DIR to "
                           "a reports/ folder you trust");
  }
  return beside / kRendererScript;
}

std::string report_python() {
  const char* chosen = std::getenv("HAPTICBENCH_PYTHON");
  return chosen != nullptr && *chosen != '\0' ? std::string(chosen) : kDefaultPython;
}

bool has_matplotlib(const std::string& python) {
  ChildOptions options;
  options.search_path = true;
  options.stdout_path = options.stderr_path = "/dev/null";
  try {
    const ProcessEnd end = ChildProcess({python, "-c", "import matplotlib"}, options).wait();
    return end.exited && end.exit_code == 0;
  } catch (const std::runtime_error&) {
    return false;
  }
}

int run_report_renderer(const std::vector<std::string>& argv, const fs::path& stderr_file,
                        ProgressDisplay& progress) {
  std::optional<ChildLinePipe> pipe;
  std::optional<ChildProcess> renderer;
  try {
    pipe.emplace();
    ChildOptions options;
    options.search_path = true;
    options.stderr_path = stderr_file;
    options.inherit_fds = {pipe->child_end(kRendererProgressFd)};
    // A terminal's Ctrl-C reaches this process only; it stops the renderer
    // (no Python traceback) and exits with 130.
    options.own_process_group = true;
    renderer.emplace(argv, options);
  } catch (const std::runtime_error&) {
    return -1;
  }
  pipe->close_write_end();
  progress.task("report");
  std::string current_phase;
  const auto show = [&](const std::string& line) {
    show_renderer_progress(line, progress, current_phase);
  };
  // At most 0.2 s between looks at the stop signals, even while the
  // renderer writes nothing; the renderer is stopped as `renderer` goes.
  while (pipe->read_lines(200, show)) throw_if_interrupted();
  progress.finish_task();
  const ProcessEnd end = renderer->wait();
  return end.exited ? end.exit_code : -1;
}

}  // namespace hb
