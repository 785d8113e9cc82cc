// hapticbench compare BASELINE CANDIDATE [--gate] [--out DIR] [--no-timing]
//                     [--rel-tol X] [--timing-ratio X] [--alpha X]
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>

#include "hapticbench/input_error.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/compare/comparison.h"
#include "harness/compare/comparison_report.h"
#include "harness/compare/summary_set.h"
#include "harness/output/run_folder.h"

namespace hb {

namespace {
const std::string kCompareUsage =
    "usage: hapticbench compare BASELINE CANDIDATE [--gate] [--out DIR] [--no-timing]\n"
    "                           [--rel-tol X] [--timing-ratio X] [--alpha X]\n"
    "                           [--timing-same-cpu] [--strict-timing] [--instructions-tol X]\n"
    "                           [--tolerances FILE]\n"
    "                           [--progress STYLE] [--quiet]\n"
    "  BASELINE, CANDIDATE  a run folder, a summary.json, or a folder of run folders\n"
    "                       (a suite; scenarios matched by name, runs by label)\n"
    "  --gate            exit 1 when a check regressed or failed (default: report, exit 0)\n"
    "  --out DIR         write DIR/compare.json, DIR/compare.md and DIR/junit.xml\n"
    "  --no-timing       skip the wall-clock timing checks (instruction counts stay)\n"
    "  --timing-same-cpu wall-clock timing only gates when both runs name the same CPU\n"
    "  --strict-timing   wall-clock timing gates even when a run's noise floor says its\n"
    "                    machine was busy (default: it gates only when both runs measured\n"
    "                    a quiet machine and their calibration workloads agree within\n"
    "                    10 %, and otherwise informs; --timing-quiet-only names the default)\n"
    "  --instructions-tol X  instruction counts (run --instructions) regress beyond this\n"
    "                    share (default 0.02)\n"
    "  --rel-tol X       accuracy/stability tolerance relative to the baseline (default 0.05)\n"
    "  --tolerances FILE per-metric tolerances in place of the defaults: a JSON object\n"
    "                    {metric: {\"rel_tol\": x, \"abs_tol\": y}} (docs/ci-gating.md)\n"
    "  --timing-ratio X  step time p50 or p99 ratio above which a significant slowdown\n"
    "                    is a regression (default 1.25)\n"
    "  --alpha X         significance level of the one-sided Mann-Whitney test (default 0.01)\n" +
    std::string(kProgressUsage);

struct CompareArguments {
  std::string baseline;
  std::string candidate;
  bool gate = false;
  std::optional<std::string> out;
  CompareOptions options;
  std::optional<ProgressStyle> progress;
  std::optional<std::string> tolerances_file;
};

// Throws UsageError or HelpRequested.
CompareArguments parse_compare_arguments(const std::vector<std::string>& args) {
  CompareArguments parsed;
  std::vector<std::string> paths;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    check_help(a);
    if (a == "--gate") {
      parsed.gate = true;
    } else if (a == "--no-timing") {
      parsed.options.timing = false;
    } else if (a == "--timing-same-cpu") {
      parsed.options.timing_same_cpu_only = true;
    } else if (a == "--timing-quiet-only") {
      parsed.options.strict_timing = false;
    } else if (a == "--strict-timing") {
      parsed.options.strict_timing = true;
    } else if (a == "--tolerances") {
      parsed.tolerances_file = option_value(args, i);
    } else if (a == "--out" || a == "--rel-tol" || a == "--timing-ratio" || a == "--alpha" ||
               a == "--instructions-tol") {
      const std::string& value = option_value(args, i);
      if (a == "--out") {
        parsed.out = value;
        continue;
      }
      // rel-tol >= 0; a ratio below 1 would call a faster candidate a
      // regression; alpha is a probability.
      const double min = a == "--timing-ratio" ? 1 : 0;
      const double max = a == "--alpha" ? 1 : HUGE_VAL;
      std::optional<double> number = parse_number(value);
      if (number && !(*number >= min && *number <= max)) number.reset();
      if (!number || (a == "--alpha" && *number == 0))
        throw UsageError{a + " expects " +
                         (a == "--rel-tol" || a == "--instructions-tol" ? "a number >= 0"
                          : a == "--timing-ratio"                       ? "a number >= 1"
                                                  : "a probability in (0, 1]") +
                         ", got \"" + value + "\""};
      (a == "--rel-tol"            ? parsed.options.rel_tol
       : a == "--instructions-tol" ? parsed.options.instructions_rel_tol
       : a == "--timing-ratio"     ? parsed.options.timing_ratio
                                   : parsed.options.alpha) = *number;
    } else if (parse_progress_option(args, i, parsed.progress)) {
    } else if (a.rfind("--", 0) == 0) {
      throw UsageError{"unknown option " + a};
    } else {
      paths.push_back(a);
    }
  }
  if (paths.size() != 2)
    throw UsageError{"expected BASELINE and CANDIDATE, got " + std::to_string(paths.size()) +
                     " path" + (paths.size() == 1 ? "" : "s")};
  parsed.baseline = paths[0];
  parsed.candidate = paths[1];
  return parsed;
}
}  // namespace

int compare_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const auto parsed_arguments =
      parse_command_line([&] { return parse_compare_arguments(args); }, kCompareUsage, exit_code);
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

}  // namespace hb
