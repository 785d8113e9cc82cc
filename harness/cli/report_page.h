// The page `hapticbench report` writes: the report renderer
// (report_renderer.h) draws it under a temporary name beside the
// destination, and it is renamed into place only when complete, so the
// destination holds the old page or the whole new one.
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

#include "harness/progress/progress_display.h"

namespace hb {

/// What the page shows.
struct ReportInputs {
  std::vector<std::filesystem::path> folders;          ///< run folders, checked
  std::vector<std::filesystem::path> stability_files;  ///< stability.json: the margin table
  std::vector<std::filesystem::path> zwidth_files;     ///< zwidth.json: the Z-width figures
  std::optional<std::filesystem::path> history;        ///< a history folder: the trends
};

/// Renders `inputs` into the page `out` (its folder created), with the
/// renderer's progress in `progress` style, and replaces `out` with it
/// once the renderer has written a whole page. Says on stderr what went
/// wrong and returns the exit code: 0, 2 (bad input: no renderer or
/// matplotlib, an unwritable destination, or what the renderer said), 3
/// (the renderer failed). Throws Interrupted when a stop signal came.
int write_report_page(const ReportInputs& inputs, const std::filesystem::path& out,
                      std::optional<ProgressStyle> progress);

}  // namespace hb
