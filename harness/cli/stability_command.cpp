// hapticbench stability SCENARIO.json --label LABEL --param POINTER --range LO HI
// [--tolerance REL] [--epsilon J] [--out DIR]: the largest stable value of one
// scenario parameter for one algorithm, by bracketing and bisection on a log
// scale. Each probe is a full run of the scenario (that algorithm only) with
// the parameter set; stable means the run did not diverge, displayed no
// non-finite wrench, its passivity energy stayed above −ε and the proxy was
// not still oscillating from tick to tick at the end (stability.chatters).
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
#include "harness/run/scenario_runner.h"
#include "harness/scenario/scenario.h"
#include "harness/sweep/sweep_jobs.h"
#include "harness/sweep/sweep_spec.h"

namespace hb {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

const std::string kStabilityUsage =
    "usage: hapticbench stability SCENARIO.json --label LABEL --param JSON_POINTER --range LO HI\n"
    "                             [--tolerance REL] [--epsilon J] [--out DIR]\n"
    "                             [--progress STYLE] [--quiet]\n"
    "  finds the largest value of the scenario field at JSON_POINTER (e.g. /coupling/k_t,\n"
    "  /algorithms/2/params/contact_stiffness) in [LO, HI] at which algorithm LABEL is\n"
    "  stable, by bracketing and bisection on a log scale; each probe is a full run.\n"
    "  stable: not diverged, no non-finite wrench, passivity energy minimum >= -EPSILON,\n"
    "          no chatter at the end of the run (proxy_chatter_m, docs/metrics.md)\n"
    "  --tolerance REL  stop when smallest_unstable / largest_stable - 1 <= REL (default 0.02)\n"
    "  --epsilon J      passivity allowance, J (default 1e-6)\n"
    "  --out DIR        folder for stability.json (default out/stability/<scenario>__<label>)\n" +
    std::string(kProgressUsage);

constexpr int kMaxProbes = 64;

struct StabilityArguments {
  std::string scenario;
  std::string label;
  std::string pointer;
  double low = 0, high = 0;
  double tolerance = 0.02;
  double epsilon_j = 1e-6;
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

// One run of the scenario at one value of the parameter.
struct Probe {
  double value = 0;
  bool stable = false;
  bool diverged = false;
  int64_t nonfinite = 0;
  double passivity_min_j = 0;
  double max_separation_m = 0;
  bool chatters = false;
  double proxy_chatter_m = 0;
};

class StabilitySearch {
 public:
  StabilitySearch(const StabilityArguments& args, ProgressDisplay& progress)
      : args_(args), progress_(progress) {
    std::ifstream in(args.scenario, std::ios::binary);
    if (!in) throw InputError(args.scenario, "", "cannot open scenario file");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    try {
      document_ = Json::parse(text);
    } catch (const Json::exception& e) {
      throw InputError(args.scenario, "", std::string("not valid JSON: ") + e.what());
    }
    base_dir_ = fs::absolute(args.scenario).parent_path();
    // The parameter must be settable, and the scenario valid with it, before
    // anything runs: one probe at the low end, loaded only.
    load_at(args.low);
  }

  Probe probe(double value) {
    const Scenario scenario = load_at(value);
    std::ostringstream prefix;
    prefix << "run " << probes_.size() + 1 << ", " << args_.pointer << " = " << value << ": ";
    progress_.set_prefix(prefix.str());
    PreparedScenario prepared = prepare_scenario(scenario, args_.label, &progress_);
    RunOptions options;
    options.progress = &progress_;
    const ScenarioOutcome outcome = run_prepared(prepared, options);
    const RunMetrics& m = outcome.report.runs.front().metrics;
    Probe p;
    p.value = value;
    p.diverged = m.stability.diverged;
    p.nonfinite = m.stability.nonfinite;
    p.passivity_min_j = m.stability.passivity_energy_min_j;
    p.max_separation_m = m.stability.max_proxy_separation_m;
    p.chatters = m.stability.chatters;
    p.proxy_chatter_m = m.stability.proxy_chatter_m;
    p.stable =
        !p.diverged && p.nonfinite == 0 && p.passivity_min_j >= -args_.epsilon_j && !p.chatters;
    probes_.push_back(p);
    std::ostringstream line;
    line << "stability: " << args_.pointer << " = " << value << ": "
         << (p.stable ? "stable" : "unstable") << "\n";
    progress_.print_above(std::cerr, line.str());
    return p;
  }

  const std::vector<Probe>& probes() const { return probes_; }
  const std::string& scenario_name() const { return name_; }
  const std::string& algorithm() const { return algorithm_; }
  /// The labelled algorithm's "integrator" parameter; empty when not given.
  const std::string& integrator() const { return integrator_; }

 private:
  Scenario load_at(double value) {
    Json document = document_;
    const std::optional<std::string> failure =
        set_at_pointer(document, *json_pointer_tokens(args_.pointer), Json(value));
    if (failure) throw InputError(args_.scenario, args_.pointer, "cannot set it: " + *failure);
    // Only the algorithm asked for: the label must name one.
    const Json& algorithms = document["algorithms"];
    bool found = false;
    if (algorithms.is_array())
      for (const Json& a : algorithms)
        if (a.is_object() &&
            (a.value("label", "") == args_.label || a.value("name", "") == args_.label)) {
          found = true;
          algorithm_ = a.value("name", "");
          const Json params = a.value("params", Json::object());
          integrator_ = params.is_object() && params.contains("integrator") &&
                                params["integrator"].is_string()
                            ? params["integrator"].get<std::string>()
                            : "";
        }
    if (!found)
      throw InputError(args_.scenario, "/algorithms",
                       "no algorithm labelled or named \"" + args_.label + "\"");
    Scenario scenario = load_scenario_json(document.dump(), args_.scenario, base_dir_);
    name_ = scenario.name;
    return scenario;
  }

  const StabilityArguments& args_;
  ProgressDisplay& progress_;
  Json document_;
  fs::path base_dir_;
  std::string name_;
  std::string algorithm_, integrator_;
  std::vector<Probe> probes_;
};

Json probe_json(const Probe& p) {
  return {{"value", p.value},
          {"stable", p.stable},
          {"diverged", p.diverged},
          {"nonfinite", p.nonfinite},
          {"passivity_energy_min_j", p.passivity_min_j},
          {"max_proxy_separation_m", p.max_separation_m},
          {"chatters", p.chatters},
          {"proxy_chatter_m", p.proxy_chatter_m}};
}

}  // namespace

int stability_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const auto parsed = parse_command_line([&] { return parse_stability_arguments(args); },
                                         kStabilityUsage, exit_code);
  if (!parsed) return exit_code;
  ProgressDisplay progress = make_progress_display(parsed->progress, 1.0);
  try {
    StabilitySearch search(*parsed, progress);
    const fs::path out = parsed->out ? fs::path(*parsed->out)
                                     : fs::path("out") / "stability" /
                                           (search.scenario_name() + "__" + parsed->label);
    // Refuse an output we may not replace before the first (long) run.
    StagedRunFolder folder(out, OutputFolderKind::kRun);

    // Bracket: the low end must be stable and the high end not; then
    // bisect the log of the interval until it is within the tolerance.
    std::optional<double> largest_stable, smallest_unstable;
    const Probe low = search.probe(parsed->low);
    if (!low.stable) {
      smallest_unstable = parsed->low;
    } else {
      largest_stable = parsed->low;
      const Probe high = search.probe(parsed->high);
      if (high.stable) {
        largest_stable = parsed->high;
      } else {
        smallest_unstable = parsed->high;
        for (int k = 0; k<kMaxProbes&& * smallest_unstable / *largest_stable - 1> parsed->tolerance;
             ++k) {
          const double middle = std::sqrt(*largest_stable * *smallest_unstable);
          (search.probe(middle).stable ? largest_stable : smallest_unstable) = middle;
        }
      }
    }

    Json runs = Json::array();
    for (const Probe& p : search.probes()) runs.push_back(probe_json(p));
    const Json result = {
        {"scenario", search.scenario_name()},
        {"scenario_file", parsed->scenario},
        {"label", parsed->label},
        {"algorithm", search.algorithm()},
        {"integrator", search.integrator().empty() ? Json(nullptr) : Json(search.integrator())},
        {"param", parsed->pointer},
        {"range", {parsed->low, parsed->high}},
        {"tolerance", parsed->tolerance},
        {"criterion",
         "stable: the run did not diverge (proxy farther than max(0.1 m, 5 tool radii) from the "
         "device, or reset), displayed no non-finite wrench, its passivity energy minimum "
         "was >= -" +
             std::to_string(parsed->epsilon_j) +
             " J, and the proxy did not chatter (its position's tick-to-tick second difference, "
             "RMS over the last quarter of the run, below max(1 um, 10 times the device's))"},
        {"epsilon_j", parsed->epsilon_j},
        {"largest_stable", largest_stable ? Json(*largest_stable) : Json(nullptr)},
        {"smallest_unstable", smallest_unstable ? Json(*smallest_unstable) : Json(nullptr)},
        {"runs", runs}};
    folder.write_file("stability.json", result.dump(2) + "\n");
    folder.commit();
    progress.close();

    std::cout << search.scenario_name() << " / " << parsed->label << ", " << parsed->pointer
              << ": largest stable "
              << (largest_stable ? std::to_string(*largest_stable) : std::string("none in range"))
              << ", smallest unstable "
              << (smallest_unstable ? std::to_string(*smallest_unstable)
                                    : std::string("none in range"))
              << " (" << search.probes().size() << " runs) -> " << (out / "stability.json").string()
              << "\n";
    return kExitOk;
  } catch (const InputError& error) {
    progress.close();
    std::cerr << "error: " << error.what() << "\n";
    return kExitBadInput;
  }
}

}  // namespace hb
