#include "harness/cli/report_page.h"

#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <system_error>

#include "algorithms/core/replacing_file.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/cli/report_renderer.h"
#include "harness/metrics/metric_table.h"
#include "harness/process/scratch_folder.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

std::vector<std::string> renderer_command(const std::string& python, const fs::path& script,
                                          const fs::path& page, const fs::path& metric_table,
                                          const ReportInputs& inputs) {
  std::vector<std::string> command = {python,
                                      "-B",
                                      script.string(),
                                      "--out",
                                      page.string(),
                                      "--metric-table",
                                      metric_table.string(),
                                      "--progress-fd",
                                      std::to_string(kRendererProgressFd)};
  const auto add = [&command](const char* option, const fs::path& path) {
    command.push_back(option);
    command.push_back(path.string());
  };
  for (const fs::path& file : inputs.stability_files) add("--stability", file);
  for (const fs::path& file : inputs.zwidth_files) add("--zwidth", file);
  if (inputs.history) add("--history", *inputs.history);
  for (const fs::path& folder : inputs.folders) command.push_back(folder.string());
  return command;
}

// The renderer's exit code as the command's, said on stderr.
int renderer_failure(int status, const fs::path& script) {
  if (status == kExitBadInput) return kExitBadInput;  // the renderer named the file
  std::cerr << "internal error: " << script.string() << " failed"
            << (status < 0 ? std::string(" to start") : " with exit code " + std::to_string(status))
            << "\n";
  return kExitInternal;
}

}  // namespace

int write_report_page(const ReportInputs& inputs, const fs::path& out,
                      std::optional<ProgressStyle> progress_style) {
  const fs::path script = report_renderer_script();
  if (!fs::is_regular_file(script)) {
    std::cerr << "error: " << script.string()
              << ": the report renderer is not there; set HAPTICBENCH_REPORTS_DIR to the "
                 "project's reports/ folder\n";
    return kExitBadInput;
  }
  const std::string python = report_python();
  if (!has_matplotlib(python)) {
    std::cerr << "error: " << python
              << " cannot import matplotlib: install python3-matplotlib (scripts/setup "
                 "installs it) or set HAPTICBENCH_PYTHON to a Python 3 that has matplotlib\n";
    return kExitBadInput;
  }

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

  // The metric table the summary table's columns come from (metric_table.h).
  const ScratchFolder scratch("hapticbench-report");
  const fs::path table = scratch.path() / "metric_table.json";
  std::ofstream(table) << metric_table_json().dump() << "\n";
  const fs::path renderer_stderr = scratch.path() / "renderer_stderr.txt";
  int status = 0;
  {
    // Drawing the figures takes seconds (tens on large suites).
    ProgressDisplay progress = make_progress_display(progress_style, 1.0);
    status = run_report_renderer(renderer_command(python, script, page->path(), table, inputs),
                                 renderer_stderr, progress);
  }
  {
    std::ifstream in(renderer_stderr, std::ios::binary);
    const std::string said((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::cerr << said << std::flush;
  }
  if (status != 0) return renderer_failure(status, script);
  if (!is_report_page(page->path())) {
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
  return kExitOk;
}

}  // namespace hb
