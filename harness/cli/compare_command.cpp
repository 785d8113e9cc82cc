// hapticbench compare BASELINE CANDIDATE [--gate] [--out DIR] ...: the
// regression gate of harness/compare/ on the command line.
#include <filesystem>
#include <iostream>
#include <optional>

#include "hapticbench/input_error.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/cli/option_table.h"
#include "harness/compare/comparison.h"
#include "harness/compare/comparison_report.h"
#include "harness/compare/summary_set.h"
#include "harness/output/run_folder.h"

namespace hb {

namespace {

struct CompareArguments {
  std::string baseline;
  std::string candidate;
  bool gate = false;
  std::optional<std::string> out;
  CompareOptions options;
  std::optional<ProgressStyle> progress;
  std::optional<std::string> tolerances_file;
};

using Table = OptionTable<CompareArguments>;

const Table& compare_table() {
  const auto in_options = [](auto field) { return member_of(&CompareArguments::options, field); };
  static const Table table(
      {"compare", {}, {}, {}},
      {Table::positional("BASELINE",
                         "a run folder, a summary.json, or a folder of run folders (a suite; "
                         "scenarios matched by name, runs by label)",
                         1, 1, &CompareArguments::baseline),
       Table::positional("CANDIDATE", "the same, compared with BASELINE", 1, 1,
                         &CompareArguments::candidate),
       Table::flag("--gate", "exit 1 when a check regressed or failed (default: report, exit 0)",
                   &CompareArguments::gate),
       Table::value("--out", "DIR", "write DIR/compare.json, DIR/compare.md and DIR/junit.xml",
                    &CompareArguments::out),
       Table::flag("--no-timing", "skip the wall-clock timing checks (instruction counts stay)",
                   [](CompareArguments& parsed) { parsed.options.timing = false; }),
       Table::flag("--timing-same-cpu",
                   "wall-clock timing only gates when both runs name the same CPU",
                   in_options(&CompareOptions::timing_same_cpu_only)),
       Table::flag("--strict-timing",
                   "wall-clock timing gates even when a run's noise floor says its machine was "
                   "busy (default: it gates only when both runs measured a quiet machine and "
                   "their calibration workloads agree within 10 %, and otherwise informs)",
                   in_options(&CompareOptions::strict_timing)),
       Table::flag("--timing-quiet-only",
                   "the default that --strict-timing changes: wall-clock timing gates only on "
                   "quiet machines",
                   [](CompareArguments& parsed) { parsed.options.strict_timing = false; }),
       Table::number("--instructions-tol", "X",
                     "instruction counts (run --instructions) regress beyond this share",
                     at_least(0), in_options(&CompareOptions::instructions_rel_tol))
           .with_default("0.02"),
       Table::number("--rel-tol", "X", "accuracy/stability tolerance relative to the baseline",
                     at_least(0), in_options(&CompareOptions::rel_tol))
           .with_default("0.05"),
       Table::value("--tolerances", "FILE",
                    "per-metric tolerances in place of the defaults: a JSON object "
                    "`{metric: {\"rel_tol\": x, \"abs_tol\": y}}` (docs/ci-gating.md)",
                    &CompareArguments::tolerances_file),
       // A ratio below 1 would call a faster candidate a regression.
       Table::number("--timing-ratio", "X",
                     "step time p50 or p99 ratio above which a significant slowdown is a "
                     "regression",
                     at_least(1), in_options(&CompareOptions::timing_ratio))
           .with_default("1.25"),
       Table::number("--alpha", "X", "significance level of the one-sided Mann-Whitney test",
                     probability(), in_options(&CompareOptions::alpha))
           .with_default("0.01"),
       Table::progress(&CompareArguments::progress), Table::quiet(&CompareArguments::progress)});
  return table;
}

}  // namespace

int compare_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const auto parsed_arguments = parse_command_line([&] { return compare_table().parse(args); },
                                                   compare_table().usage(), exit_code);
  if (!parsed_arguments) return exit_code;
  const CompareArguments& arguments = *parsed_arguments;

  // Everything that can reject the input happens before anything is written.
  Comparison comparison;
  {
    // Reading the ticks logs of large suites for step times takes a while.
    ProgressDisplay progress = make_progress_display(arguments.progress, 1.0);
    try {
      if (arguments.out) require_replaceable_folder(*arguments.out, OutputFolderKind::kComparison);
      CompareOptions options = arguments.options;
      if (arguments.tolerances_file)
        options.tolerances = read_tolerances_file(*arguments.tolerances_file);
      const SummarySet baseline = load_summary_set(arguments.baseline);
      const SummarySet candidate = load_summary_set(arguments.candidate);
      comparison = compare_summary_sets(baseline, candidate, options, &progress);
    } catch (const InputError& error) {
      progress.close();
      std::cerr << "error: " << error.what() << "\n";
      return kExitBadInput;
    }
  }

  print_comparison_table(std::cout, comparison);
  if (arguments.out) {
    StagedRunFolder staged{std::filesystem::path(*arguments.out), OutputFolderKind::kComparison};
    staged.write_file("compare.json", comparison_json(comparison).dump(2) + "\n");
    staged.write_file("compare.md", comparison_markdown(comparison));
    staged.write_file("junit.xml", comparison_junit_xml(comparison));
    const bool replaced = staged.commit();
    std::cout << "wrote " << *arguments.out << "/{compare.json,compare.md,junit.xml}"
              << (replaced ? " (replaced the earlier comparison)" : "") << "\n";
  }
  if (comparison.passed()) return kExitOk;
  if (!arguments.gate) {
    std::cout << "(report only: with --gate, regressions exit 1)\n";
    return kExitOk;
  }
  return kExitBudgetFailed;
}

const CommandSyntax& compare_syntax() { return compare_table().syntax(); }

}  // namespace hb
