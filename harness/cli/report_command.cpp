// `hapticbench report`: one self-contained HTML page (figures inline, no
// external resources) from run folders. Finds every summary.json beneath the
// folders given, checks that each is a schema 1 summary, and hands the run
// folders to the report renderer (report_renderer.h), which draws the
// figures and writes the page under a temporary name; the page is renamed
// into place only when complete.
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "hapticbench/input_error.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/cli/option_table.h"
#include "harness/cli/report_page.h"
#include "harness/cli/report_renderer.h"
#include "harness/cli/run_folder_search.h"
#include "harness/history/history_store.h"
#include "harness/output/output_ownership.h"
#include "harness/scenario/json_fields.h"

namespace hb {

namespace {

namespace fs = std::filesystem;

struct ReportOptions {
  std::vector<fs::path> inputs;
  fs::path out = "report.html";
  std::optional<fs::path> history;  ///< --history: a history folder
  std::optional<ProgressStyle> progress;
};

using Table = OptionTable<ReportOptions>;

const Table& report_table() {
  static const Table table(
      {"report",
       {},
       {"Environment: HAPTICBENCH_PYTHON (default /usr/bin/python3, needs matplotlib), "
        "HAPTICBENCH_REPORTS_DIR (where render_report.py is; default "
        "../share/hapticbench/reports from the binary's folder)."},
       {}},
      {Table::positional("RUN_DIR",
                         "a run folder (with summary.json) or a folder holding run folders at "
                         "any depth; stability.json files beneath it (hapticbench stability) "
                         "make the margin table, zwidth.json files (hapticbench zwidth) the "
                         "Z-width figures",
                         0, kAnyCount, &ReportOptions::inputs),
       Table::value("--history", "DIR",
                    "runs kept by commit (hapticbench history add): each metric's trend per "
                    "scenario and label, and where it first moved; RUN_DIR may then be left out",
                    &ReportOptions::history),
       Table::value("--out", "FILE", "the HTML page to write", &ReportOptions::out)
           .with_default("report.html in the current folder"),
       Table::progress(&ReportOptions::progress), Table::quiet(&ReportOptions::progress)});
  return table;
}

ReportOptions parse_report_options(const std::vector<std::string>& args) {
  ReportOptions options = report_table().parse(args);
  if (options.inputs.empty() && !options.history) throw UsageError{"missing RUN_DIR"};
  if (options.out.filename().empty()) throw UsageError{"--out: expected a file name"};
  return options;
}

// Every run folder once, in the order given, each input's folders sorted;
// the results of `hapticbench stability` (stability.json) beneath the
// inputs, and of `hapticbench zwidth` (zwidth.json): an input may hold only
// those. Throws InputError for a summary the renderer cannot rely on or an
// empty history.
ReportInputs find_report_inputs(const ReportOptions& options) {
  ReportInputs found;
  found.history = options.history;
  std::vector<fs::path> run_inputs;
  for (const fs::path& input : options.inputs) {
    const std::vector<fs::path> margins = find_files_named(input, "stability.json");
    const std::vector<fs::path> maps = find_files_named(input, "zwidth.json");
    found.stability_files.insert(found.stability_files.end(), margins.begin(), margins.end());
    found.zwidth_files.insert(found.zwidth_files.end(), maps.begin(), maps.end());
    if ((margins.empty() && maps.empty()) || !find_files_named(input, "summary.json").empty())
      run_inputs.push_back(input);
  }
  if (!run_inputs.empty()) found.folders = find_run_folders(run_inputs);
  for (const fs::path& folder : found.folders) read_run_summary(folder / "summary.json");
  if (options.history && read_history(*options.history).empty())
    throw InputError(options.history->string(), "",
                     "no history here: `hapticbench history add` writes one");
  return found;
}

std::string counted(std::size_t count, const std::string& what) {
  return std::to_string(count) + " " + what + (count == 1 ? "" : "s");
}

}  // namespace

int report_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const auto parsed_options = parse_command_line([&] { return parse_report_options(args); },
                                                 report_table().usage(), exit_code);
  if (!parsed_options) return exit_code;
  const ReportOptions& options = *parsed_options;
  const fs::path& out = options.out;

  // Never replace what hapticbench did not write (checked before any work).
  require_replaceable_file(out, "report", is_report_page);
  const ReportInputs inputs = find_report_inputs(options);

  const int written = write_report_page(inputs, out, options.progress);
  if (written != kExitOk) return written;
  std::cout << "report: " << out.string() << " (" << counted(inputs.folders.size(), "run folder");
  if (!inputs.stability_files.empty())
    std::cout << ", " << counted(inputs.stability_files.size(), "stability margin");
  if (!inputs.zwidth_files.empty())
    std::cout << ", " << counted(inputs.zwidth_files.size(), "Z-width map");
  std::cout << ")\n";
  return kExitOk;
}

const CommandSyntax& report_syntax() { return report_table().syntax(); }

}  // namespace hb
