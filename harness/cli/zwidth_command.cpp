// hapticbench zwidth SCENARIO.json --label LABEL --x POINTER --x-values V,V,...
// --y POINTER --y-range LO HI [--tolerance REL] [--criterion C] [--epsilon J]
// [--out DIR]: the stable region of one algorithm over two scenario
// parameters (Colgate & Brown 1994's Z-width, e.g. coupling damping against
// coupling stiffness): for each value of the first, the largest stable value
// of the second, found as `hapticbench stability` finds it.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "hapticbench/input_error.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/cli/option_table.h"
#include "harness/cli/plugin_isolation.h"
#include "harness/cli/stability_options.h"
#include "harness/drivers/stability_search.h"
#include "harness/output/run_folder.h"
#include "harness/sweep/sweep_spec.h"

namespace hb {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

struct ZwidthArguments {
  StabilitySearchOptions search;
  std::string x_pointer, y_pointer;
  std::vector<double> x_values;
  double y_low = 0, y_high = 0;
};

constexpr std::size_t kMaxXValues = 256;

using Table = OptionTable<ZwidthArguments>;

void add_x_values(ZwidthArguments& parsed, const std::string& list) {
  for (std::size_t start = 0; start <= list.size();) {
    const std::size_t comma = std::min(list.find(',', start), list.size());
    parsed.x_values.push_back(
        number_in("--x-values", list.substr(start, comma - start), at_least(0)));
    start = comma + 1;
  }
  // Each x value is a whole search of runs: a list of thousands is a typo.
  if (parsed.x_values.size() > kMaxXValues)
    throw UsageError{"--x-values: " + std::to_string(parsed.x_values.size()) + " values; at most " +
                     std::to_string(kMaxXValues) + " (each is a search of several full runs)"};
}

const Table& zwidth_table() {
  constexpr auto search = &ZwidthArguments::search;
  static const Table table(
      {"zwidth",
       {"Maps the stable region of algorithm LABEL over two scenario fields (a Z-width, Colgate & "
        "Brown 1994): for each value of the field at --x, the largest stable value of the field "
        "at --y in [LO, HI], searched as `hapticbench stability` does (the same criterion and "
        "options); each probe is a full run.",
        "e.g. `--x /coupling/b_t --x-values 0,2,5,10 --y /coupling/k_t --y-range 1000 100000`"},
       {},
       {}},
      rows_then(
          stability_target_rows(search),
          rows_then(
              {Table::value("--x", "JSON_POINTER", "the scenario field set to each x value",
                            [](ZwidthArguments& parsed, const std::string& pointer) {
                              parsed.x_pointer = json_pointer_option("--x", pointer);
                            })
                   .required(),
               Table::value("--x-values", "V,V,...", "the x values, each >= 0", add_x_values)
                   .required(),
               Table::value("--y", "JSON_POINTER", "the scenario field searched at each x",
                            [](ZwidthArguments& parsed, const std::string& pointer) {
                              parsed.y_pointer = json_pointer_option("--y", pointer);
                            })
                   .required(),
               Table::values("--y-range", "LO HI", "the y values searched, 0 < LO < HI",
                             [](ZwidthArguments& parsed, const std::vector<std::string>& values) {
                               std::tie(parsed.y_low, parsed.y_high) =
                                   range_option("--y-range", values);
                             })
                   .required()},
              stability_search_rows(search, "zwidth.json", "`out/zwidth/<scenario>__<label>`"))));
  return table;
}

// Throws UsageError or HelpRequested.
ZwidthArguments parse_zwidth_arguments(const std::vector<std::string>& args) {
  ZwidthArguments parsed = zwidth_table().parse(args);
  if (parsed.x_pointer == parsed.y_pointer) throw UsageError{"--x and --y name the same field"};
  return parsed;
}

Json or_null(const std::optional<double>& value) { return value ? Json(*value) : Json(); }

}  // namespace

int zwidth_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const auto parsed = parse_command_line([&] { return parse_zwidth_arguments(args); },
                                         zwidth_table().usage(), exit_code);
  if (!parsed) return exit_code;
  ProgressDisplay progress = make_progress_display(parsed->search.progress, 1.0);
  try {
    ScenarioProber prober(parsed->search.scenario, parsed->search.label, parsed->search.criterion,
                          parsed->search.epsilon_j, progress);
    // Every x value must be settable, and the scenario valid with it, before
    // anything runs.
    for (double x : parsed->x_values)
      for (double y : {parsed->y_low, parsed->y_high})
        prober.check({{parsed->x_pointer, x}, {parsed->y_pointer, y}});
    // A plugin's renderer runs in a child this process watches.
    if (should_isolate_plugins({prober.algorithm()})) {
      progress.close();
      return run_plugins_isolated("zwidth", args);
    }
    const fs::path out =
        parsed->search.out
            ? fs::path(*parsed->search.out)
            : fs::path("out") / "zwidth" / (prober.scenario_name() + "__" + parsed->search.label);
    StagedRunFolder folder(out, OutputFolderKind::kRun);

    Json points = Json::array(), runs = Json::array();
    // The runs that finished are kept if a stop signal ends the search.
    SearchKeepingRuns searcher(folder, "zwidth.partial.json",
                               {{"scenario", prober.scenario_name()},
                                {"scenario_file", parsed->search.scenario},
                                {"label", parsed->search.label},
                                {"x_param", parsed->x_pointer},
                                {"y_param", parsed->y_pointer},
                                {"x_values", parsed->x_values},
                                {"y_range", {parsed->y_low, parsed->y_high}}},
                               progress);
    for (double x : parsed->x_values) {
      const StabilityBracket bracket = searcher.search(
          [&](double y) {
            return prober.probe({{parsed->x_pointer, x}, {parsed->y_pointer, y}});
          },
          parsed->y_low, parsed->y_high, parsed->search.tolerance);
      // What the linear loop alone allows at this x (small_signal.h).
      const SmallSignalLimit small =
          parsed->y_pointer == "/coupling/k_t"
              ? prober.small_signal({{parsed->x_pointer, x}, {parsed->y_pointer, parsed->y_low}})
              : SmallSignalLimit{std::nullopt,
                                 "the small-signal limit is computed for y = /coupling/k_t only"};
      points.push_back({{"x", x},
                        {"largest_stable", or_null(bracket.largest_stable)},
                        {"smallest_unstable", or_null(bracket.smallest_unstable)},
                        {"runs", bracket.probes.size()},
                        {"note", bracket_note(bracket, parsed->y_low, parsed->y_high)},
                        {"small_signal_limit", or_null(small.k_t_n_per_m)},
                        {"small_signal_note", small.note}});
      for (const StabilityProbe& p : bracket.probes) runs.push_back(probe_json(p));
      std::cout << prober.scenario_name() << " / " << parsed->search.label << ", "
                << parsed->x_pointer << " = " << x << ": largest stable " << parsed->y_pointer
                << " "
                << (bracket.largest_stable ? std::to_string(*bracket.largest_stable)
                                           : std::string("none in range"))
                << "\n";
    }
    const Json result = {
        {"scenario", prober.scenario_name()},
        {"scenario_file", parsed->search.scenario},
        {"label", parsed->search.label},
        {"algorithm", prober.algorithm()},
        {"x_param", parsed->x_pointer},
        {"y_param", parsed->y_pointer},
        {"x_values", parsed->x_values},
        {"y_range", {parsed->y_low, parsed->y_high}},
        {"tolerance", parsed->search.tolerance},
        {"criterion", stability_criterion_text(parsed->search.criterion, parsed->search.epsilon_j)},
        {"epsilon_j", parsed->search.epsilon_j},
        {"points", points},
        {"runs", runs}};
    folder.write_file("zwidth.json", result.dump(2) + "\n");
    folder.commit();
    progress.close();
    std::cout << "-> " << (out / "zwidth.json").string() << "\n";
    return kExitOk;
  } catch (const InputError& error) {
    progress.close();
    std::cerr << "error: " << error.what() << "\n";
    return kExitBadInput;
  }
}

const CommandSyntax& zwidth_syntax() { return zwidth_table().syntax(); }

}  // namespace hb
