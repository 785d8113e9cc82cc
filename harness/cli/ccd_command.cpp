// `hapticbench ccd`: runs the primitive continuous collision kernels of the
// god-object on query files with ground truth, counts false negatives (a
// kernel bug: a contact was missed) and false positives (allowed, the
// kernels are conservative), and times every query.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "algorithms/ccd/ccd_primitives.h"
#include "hapticbench/input_error.h"
#include "harness/cli/ccd_evaluation.h"
#include "harness/cli/ccd_query_file.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/cli/option_table.h"

namespace hb {

namespace {

struct CcdOptions {
  std::vector<std::string> files;
  bool json = false;
  CcdSettings settings;
};

using Table = OptionTable<CcdOptions>;

const Table& ccd_table() {
  static const Table table(
      {"ccd",
       {"Query files: 8 rows xnum,xden,ynum,yden,znum,zden,truth per query; the kind comes from "
        "the path (a folder or file name containing vertex-face or edge-edge).",
        "Prints per file: queries, true collisions, false negatives, false positives, and ns per "
        "query (mean, median, max over queries; each query's fastest of 3 timed runs, including "
        "one steady_clock reading pair)."},
       {"Exit 1 when any contact is missed (false negative)."},
       {}},
      {Table::positional("QUERIES.csv", "a query file with ground truth", 1, kAnyCount,
                         &CcdOptions::files),
       Table::flag("--json", "one JSON object per file and line", &CcdOptions::json),
       Table::number("--time-tolerance", "T", "the kernels' time tolerance, in [1e-12, 1]",
                     any_number(), member_of(&CcdOptions::settings, &CcdSettings::time_tolerance))
           .with_default("1e-6"),
       Table::whole("--max-evaluations", "N", "the most sub-intervals one query evaluates",
                    {1, 1'000'000'000, ""},
                    member_of(&CcdOptions::settings, &CcdSettings::max_evaluations))
           .with_default("64")});
  return table;
}

CcdOptions parse_ccd_options(const std::vector<std::string>& args) {
  CcdOptions options = ccd_table().parse(args);
  try {
    validate_ccd_settings(options.settings, "ccd");
  } catch (const InputError& error) {
    throw UsageError{std::string(error.what())};
  }
  return options;
}

void print_json_line(const CcdFileOutcome& o) {
  const CcdTimeSummary t = summarise_ccd_times(o.ns);
  nlohmann::ordered_json line;
  line["file"] = o.file;
  line["kind"] = ccd_query_kind_name(o.kind);
  line["queries"] = o.queries;
  line["collisions"] = o.collisions;
  line["false_negatives"] = o.false_negatives;
  line["false_positives"] = o.false_positives;
  line["ns_mean"] = std::round(t.mean * 10) / 10;
  line["ns_median"] = t.median;
  line["ns_max"] = t.max;
  std::cout << line.dump() << "\n";
}

void print_table_row(const std::string& label, const std::string& kind, int queries, int collisions,
                     int false_negatives, int false_positives, int budget,
                     const CcdTimeSummary& t) {
  std::printf("%7d %10d %9d %9d %10d %9.1f %9lld %9lld  %-11s %s\n", queries, collisions,
              false_negatives, false_positives, budget, t.mean, static_cast<long long>(t.median),
              static_cast<long long>(t.max), kind.c_str(), label.c_str());
}

}  // namespace

int ccd_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const auto parsed_options =
      parse_command_line([&] { return parse_ccd_options(args); }, ccd_table().usage(), exit_code);
  if (!parsed_options) return exit_code;
  const CcdOptions& options = *parsed_options;
  // Every file is read before anything runs: bad input prints nothing else.
  std::vector<CcdQueryFile> files;
  try {
    for (const std::string& path : options.files) files.push_back(read_ccd_query_file(path));
  } catch (const InputError& error) {
    std::cerr << "error: " << error.what() << "\n";
    return kExitBadInput;
  }
  for (const CcdQueryFile& file : files)
    if (file.inexact_coordinates > 0)
      std::cerr << "warning: " << file.path.string() << ": " << file.inexact_coordinates
                << " coordinates are not exactly representable as doubles and were rounded; "
                   "the truth column may not hold for those queries\n";

  std::vector<CcdFileOutcome> outcomes;
  for (const CcdQueryFile& file : files)
    outcomes.push_back(evaluate_ccd_file(file, options.settings));

  int false_negatives = 0;
  if (options.json) {
    for (const CcdFileOutcome& o : outcomes) {
      print_json_line(o);
      false_negatives += o.false_negatives;
    }
  } else {
    std::printf("%7s %10s %9s %9s %10s %9s %9s %9s  %-11s %s\n", "queries", "collisions",
                "false_neg", "false_pos", "budget_out", "ns_mean", "ns_median", "ns_max", "kind",
                "file");
    int queries = 0, collisions = 0, false_positives = 0, budget = 0;
    std::vector<std::int64_t> all_ns;
    for (const CcdFileOutcome& o : outcomes) {
      print_table_row(o.file, ccd_query_kind_name(o.kind), o.queries, o.collisions,
                      o.false_negatives, o.false_positives, o.budget_exhausted,
                      summarise_ccd_times(o.ns));
      queries += o.queries;
      collisions += o.collisions;
      false_negatives += o.false_negatives;
      false_positives += o.false_positives;
      budget += o.budget_exhausted;
      all_ns.insert(all_ns.end(), o.ns.begin(), o.ns.end());
    }
    if (outcomes.size() > 1)
      print_table_row("(all files)", "", queries, collisions, false_negatives, false_positives,
                      budget, summarise_ccd_times(all_ns));
    if (false_negatives > 0)
      std::printf("%d missed contacts (false negatives): the kernels must be conservative\n",
                  false_negatives);
  }
  return false_negatives > 0 ? kExitBudgetFailed : kExitOk;
}

const CommandSyntax& ccd_syntax() { return ccd_table().syntax(); }

}  // namespace hb
