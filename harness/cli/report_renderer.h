// The report renderer of `hapticbench report`: reports/render_report.py,
// found in HAPTICBENCH_REPORTS_DIR or beside the binary, run by a Python 3
// with matplotlib; it draws the figures and writes the page, and tells its
// progress one line per step.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "harness/progress/progress_display.h"

namespace hb {

/// The fd on which the renderer writes its progress, one line per step:
/// "<done> <total> <unit> <phase...>" (unit "-": none).
inline constexpr int kRendererProgressFd = 3;

/// Whether `path` is a page `hapticbench report` wrote: the renderer puts
/// a generator meta tag naming it in every page's head.
bool is_report_page(const std::filesystem::path& path);

/// render_report.py: in HAPTICBENCH_REPORTS_DIR (the user's explicit
/// choice), else in share/hapticbench/reports beside the binary's folder
/// (PREFIX/bin and PREFIX/share when installed; the build links
/// build/harness/share to the source tree's reports/). That one runs only
/// when nobody but this user or root can change it: a copy of the binary in
/// a shared folder (/tmp/bin) must not run a stranger's
/// /tmp/share/hapticbench/reports. Throws InputError naming the path
/// otherwise. The script may not exist: the caller says so.
std::filesystem::path report_renderer_script();

/// The Python that runs the renderer: HAPTICBENCH_PYTHON, else /usr/bin/python3.
std::string report_python();

/// Whether `python` starts and imports matplotlib.
bool has_matplotlib(const std::string& python);

/// Runs the renderer (`argv`) and waits for it, showing the progress it
/// writes on fd kRendererProgressFd; its stderr goes to `stderr_file` (so
/// that it never shares a line with the live one). A stop signal stops it
/// and is thrown on as Interrupted. Returns its exit code, or -1 when it
/// could not be started or did not exit normally.
int run_report_renderer(const std::vector<std::string>& argv,
                        const std::filesystem::path& stderr_file, ProgressDisplay& progress);

}  // namespace hb
