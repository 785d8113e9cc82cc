// hapticbench stability SCENARIO.json --label LABEL --param POINTER --range LO HI
// [--tolerance REL] [--epsilon J] [--criterion all|passivity|oscillation]
// [--out DIR]: the largest stable value of one scenario parameter for one
// algorithm, by bracketing and bisection on a log scale. Each probe is a full
// run of the scenario (that algorithm only) with the parameter set; stable
// means the run did not diverge and displayed no non-finite wrench, and, by
// the criterion: its energy stayed above −ε (passivity: the port energy in
// open loop, the energy the hand put into the device in closed loop) and
// nothing kept oscillating (oscillation: the proxy's chatter in open loop,
// the device's limit cycles in closed loop).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
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

struct StabilityArguments {
  StabilitySearchOptions search;
  std::string pointer;
  double low = 0, high = 0;
};

using Table = OptionTable<StabilityArguments>;

const Table& stability_table() {
  constexpr auto search = &StabilityArguments::search;
  static const Table table(
      {"stability",
       {"Finds the largest value of the scenario field at JSON_POINTER (e.g. /coupling/k_t, "
        "/algorithms/2/params/contact_stiffness) in [LO, HI] at which algorithm LABEL is "
        "stable, by bracketing and bisection on a log scale; each probe is a full run."},
       {},
       {}},
      rows_then(stability_target_rows(search),
                rows_then({Table::value("--param", "JSON_POINTER", "the scenario field searched",
                                        [](StabilityArguments& parsed, const std::string& pointer) {
                                          parsed.pointer = json_pointer_option("--param", pointer);
                                        })
                               .required(),
                           Table::values("--range", "LO HI", "the values searched, 0 < LO < HI",
                                         [](StabilityArguments& parsed,
                                            const std::vector<std::string>& values) {
                                           std::tie(parsed.low, parsed.high) =
                                               range_option("--range", values);
                                         })
                               .required()},
                          stability_search_rows(search, "stability.json",
                                                "`out/stability/<scenario>__<label>`"))));
  return table;
}

}  // namespace

int stability_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const auto parsed = parse_command_line([&] { return stability_table().parse(args); },
                                         stability_table().usage(), exit_code);
  if (!parsed) return exit_code;
  ProgressDisplay progress = make_progress_display(parsed->search.progress, 1.0);
  try {
    ScenarioProber prober(parsed->search.scenario, parsed->search.label, parsed->search.criterion,
                          parsed->search.epsilon_j, progress);
    // The parameter must be settable, and the scenario valid with it, before
    // anything runs: loaded at both ends of the range (a bad high end once
    // failed after a 300,000-tick run at the low end).
    prober.check({{parsed->pointer, parsed->low}});
    prober.check({{parsed->pointer, parsed->high}});
    // A plugin's renderer runs in a child this process watches.
    if (should_isolate_plugins({prober.algorithm()})) {
      progress.close();
      return run_plugins_isolated("stability", args);
    }
    const fs::path out = parsed->search.out
                             ? fs::path(*parsed->search.out)
                             : fs::path("out") / "stability" /
                                   (prober.scenario_name() + "__" + parsed->search.label);
    // Refuse an output we may not replace before the first (long) run.
    StagedRunFolder folder(out, OutputFolderKind::kRun);

    // The runs that finished are kept if a stop signal ends the search.
    SearchKeepingRuns searcher(folder, "stability.partial.json",
                               {{"scenario", prober.scenario_name()},
                                {"scenario_file", parsed->search.scenario},
                                {"label", parsed->search.label},
                                {"param", parsed->pointer},
                                {"range", {parsed->low, parsed->high}}},
                               progress);
    const StabilityBracket bracket = searcher.search(
        [&](double value) {
          return prober.probe({{parsed->pointer, value}});
        },
        parsed->low, parsed->high, parsed->search.tolerance);
    const std::optional<double>& largest_stable = bracket.largest_stable;
    const std::optional<double>& smallest_unstable = bracket.smallest_unstable;

    // What the linear loop alone allows (small_signal.h), beside what the
    // runs found: a limit says what sets it.
    const SmallSignalLimit small =
        parsed->pointer == "/coupling/k_t"
            ? prober.small_signal({{parsed->pointer, parsed->low}})
            : SmallSignalLimit{std::nullopt,
                               "the small-signal limit is computed for /coupling/k_t only"};
    Json runs = Json::array();
    for (const StabilityProbe& p : bracket.probes) runs.push_back(probe_json(p));
    const Json result = {
        {"scenario", prober.scenario_name()},
        {"scenario_file", parsed->search.scenario},
        {"label", parsed->search.label},
        {"algorithm", prober.algorithm()},
        {"integrator", prober.integrator().empty() ? Json(nullptr) : Json(prober.integrator())},
        {"param", parsed->pointer},
        {"range", {parsed->low, parsed->high}},
        {"tolerance", parsed->search.tolerance},
        {"criterion", stability_criterion_text(parsed->search.criterion, parsed->search.epsilon_j)},
        {"epsilon_j", parsed->search.epsilon_j},
        {"largest_stable", largest_stable ? Json(*largest_stable) : Json(nullptr)},
        {"smallest_unstable", smallest_unstable ? Json(*smallest_unstable) : Json(nullptr)},
        {"note", bracket_note(bracket, parsed->low, parsed->high)},
        {"small_signal_limit", small.k_t_n_per_m ? Json(*small.k_t_n_per_m) : Json(nullptr)},
        {"small_signal_note", small.note},
        {"runs", runs}};
    folder.write_file("stability.json", result.dump(2) + "\n");
    folder.commit();
    progress.close();

    std::cout << prober.scenario_name() << " / " << parsed->search.label << ", " << parsed->pointer
              << ": largest stable "
              << (largest_stable ? std::to_string(*largest_stable) : std::string("none in range"))
              << ", smallest unstable "
              << (smallest_unstable ? std::to_string(*smallest_unstable)
                                    : std::string("none in range"))
              << " (" << bracket.probes.size() << " runs) -> " << (out / "stability.json").string()
              << "\n";
    const std::string note = bracket_note(bracket, parsed->low, parsed->high);
    if (!note.empty()) std::cout << "  " << note << "\n";
    if (small.k_t_n_per_m)
      std::cout << "  small-signal limit (the linear loop) " << *small.k_t_n_per_m << " N/m\n";
    return kExitOk;
  } catch (const InputError& error) {
    progress.close();
    std::cerr << "error: " << error.what() << "\n";
    return kExitBadInput;
  }
}

const CommandSyntax& stability_syntax() { return stability_table().syntax(); }

}  // namespace hb
