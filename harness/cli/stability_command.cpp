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
#include <vector>

#include "algorithms/core/input_error.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/output/run_folder.h"
#include "harness/stability/stability_search.h"
#include "harness/sweep/sweep_spec.h"

namespace hb {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

const std::string kStabilityUsage =
    "usage: hapticbench stability SCENARIO.json --label LABEL --param JSON_POINTER --range LO HI\n"
    "                             [--tolerance REL] [--epsilon J] [--out DIR]\n"
    "                             [--criterion all|passivity|oscillation]\n"
    "                             [--progress STYLE] [--quiet]\n"
    "  finds the largest value of the scenario field at JSON_POINTER (e.g. /coupling/k_t,\n"
    "  /algorithms/2/params/contact_stiffness) in [LO, HI] at which algorithm LABEL is\n"
    "  stable, by bracketing and bisection on a log scale; each probe is a full run.\n"
    "  stable: not diverged, no non-finite wrench, and by --criterion (default all):\n"
    "    passivity    the port energy minimum >= -EPSILON; in closed loop (docs/closed-loop.md)\n"
    "                 the energy the hand put into the device, display_energy_min_j\n"
    "    oscillation  no chatter at the end of the run (proxy_chatter_m, docs/metrics.md);\n"
    "                 in closed loop no limit cycle of the device either\n"
    "    all          both\n"
    "  --tolerance REL  stop when smallest_unstable / largest_stable - 1 <= REL (default 0.02)\n"
    "  --epsilon J      passivity allowance, J (default 1e-6)\n"
    "  --out DIR        folder for stability.json (default out/stability/<scenario>__<label>)\n" +
    std::string(kProgressUsage);

struct StabilityArguments {
  std::string scenario;
  std::string label;
  std::string pointer;
  double low = 0, high = 0;
  double tolerance = 0.02;
  double epsilon_j = 1e-6;
  StabilityCriterion criterion = StabilityCriterion::kAll;
  std::optional<std::string> out;
  std::optional<ProgressStyle> progress;
};

double positive_number(const std::string& option, const std::string& text) {
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(value) || !(value > 0))
    throw UsageError{option + ": expected a finite number > 0, got \"" + text + "\""};
  return value;
}

// Throws UsageError or HelpRequested.
StabilityArguments parse_stability_arguments(const std::vector<std::string>& args) {
  StabilityArguments parsed;
  bool have_range = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    check_help(a);
    if (a == "--label") {
      parsed.label = option_value(args, i);
    } else if (a == "--param") {
      parsed.pointer = option_value(args, i);
    } else if (a == "--range") {
      parsed.low = positive_number("--range LO", option_value(args, i));
      parsed.high = positive_number("--range HI", option_value(args, i));
      have_range = true;
    } else if (a == "--tolerance") {
      parsed.tolerance = positive_number(a, option_value(args, i));
    } else if (a == "--epsilon") {
      parsed.epsilon_j = positive_number(a, option_value(args, i));
    } else if (a == "--criterion") {
      const std::string name = option_value(args, i);
      const std::optional<StabilityCriterion> criterion = stability_criterion_named(name);
      if (!criterion)
        throw UsageError{"--criterion: expected all, passivity or oscillation, got \"" + name +
                         "\""};
      parsed.criterion = *criterion;
    } else if (a == "--out") {
      parsed.out = option_value(args, i);
    } else if (parse_progress_option(args, i, parsed.progress)) {
    } else if (a.rfind("--", 0) == 0) {
      throw UsageError{"unknown option " + a};
    } else if (!parsed.scenario.empty()) {
      throw UsageError{"one scenario at a time (got " + parsed.scenario + " and " + a + ")"};
    } else {
      parsed.scenario = a;
    }
  }
  if (parsed.scenario.empty()) throw UsageError{"no scenario given"};
  if (parsed.label.empty()) throw UsageError{"--label LABEL is required"};
  if (parsed.pointer.empty()) throw UsageError{"--param JSON_POINTER is required"};
  if (!json_pointer_tokens(parsed.pointer))
    throw UsageError{"--param: expected a JSON pointer such as /coupling/k_t, got \"" +
                     parsed.pointer + "\""};
  if (!have_range) throw UsageError{"--range LO HI is required"};
  if (!(parsed.low < parsed.high)) throw UsageError{"--range: expected LO < HI"};
  return parsed;
}

}  // namespace

int stability_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const auto parsed = parse_command_line([&] { return parse_stability_arguments(args); },
                                         kStabilityUsage, exit_code);
  if (!parsed) return exit_code;
  ProgressDisplay progress = make_progress_display(parsed->progress, 1.0);
  try {
    ScenarioProber prober(parsed->scenario, parsed->label, parsed->criterion, parsed->epsilon_j,
                          progress);
    // The parameter must be settable, and the scenario valid with it, before
    // anything runs: loaded at the low end only.
    prober.check({{parsed->pointer, parsed->low}});
    const fs::path out = parsed->out ? fs::path(*parsed->out)
                                     : fs::path("out") / "stability" /
                                           (prober.scenario_name() + "__" + parsed->label);
    // Refuse an output we may not replace before the first (long) run.
    StagedRunFolder folder(out, OutputFolderKind::kRun);

    const StabilityBracket bracket = search_largest_stable(
        [&](double value) {
          return prober.probe({{parsed->pointer, value}});
        },
        parsed->low, parsed->high, parsed->tolerance);
    const std::optional<double>& largest_stable = bracket.largest_stable;
    const std::optional<double>& smallest_unstable = bracket.smallest_unstable;

    Json runs = Json::array();
    for (const StabilityProbe& p : bracket.probes) runs.push_back(probe_json(p));
    const Json result = {
        {"scenario", prober.scenario_name()},
        {"scenario_file", parsed->scenario},
        {"label", parsed->label},
        {"algorithm", prober.algorithm()},
        {"integrator", prober.integrator().empty() ? Json(nullptr) : Json(prober.integrator())},
        {"param", parsed->pointer},
        {"range", {parsed->low, parsed->high}},
        {"tolerance", parsed->tolerance},
        {"criterion", stability_criterion_text(parsed->criterion, parsed->epsilon_j)},
        {"epsilon_j", parsed->epsilon_j},
        {"largest_stable", largest_stable ? Json(*largest_stable) : Json(nullptr)},
        {"smallest_unstable", smallest_unstable ? Json(*smallest_unstable) : Json(nullptr)},
        {"runs", runs}};
    folder.write_file("stability.json", result.dump(2) + "\n");
    folder.commit();
    progress.close();

    std::cout << prober.scenario_name() << " / " << parsed->label << ", " << parsed->pointer
              << ": largest stable "
              << (largest_stable ? std::to_string(*largest_stable) : std::string("none in range"))
              << ", smallest unstable "
              << (smallest_unstable ? std::to_string(*smallest_unstable)
                                    : std::string("none in range"))
              << " (" << bracket.probes.size() << " runs) -> " << (out / "stability.json").string()
              << "\n";
    return kExitOk;
  } catch (const InputError& error) {
    progress.close();
    std::cerr << "error: " << error.what() << "\n";
    return kExitBadInput;
  }
}

}  // namespace hb
