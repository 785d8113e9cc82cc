#include "harness/cli/stability_options.h"

#include <cmath>

#include "harness/cli/command_line.h"
#include "harness/process/interrupt.h"

namespace hb {

const char* const kStabilitySearchUsage =
    "  stable: not diverged, no non-finite wrench, and by --criterion (default all):\n"
    "    passivity    the port energy minimum >= -EPSILON; in closed loop (docs/closed-loop.md)\n"
    "                 the energy the hand put into the device, display_energy_min_j\n"
    "    oscillation  no chatter at the end of the run (proxy_chatter_m, docs/metrics.md);\n"
    "                 in closed loop no limit cycle of the device either\n"
    "    all          both\n"
    "  --tolerance REL  stop when smallest_unstable / largest_stable - 1 <= REL (default 0.02)\n"
    "  --epsilon J      passivity allowance, J (default 1e-6)\n";

double finite_number_option(const std::string& option, const std::string& text, bool positive) {
  const double value = parse_number(text).value_or(-1);
  if (!(positive ? value > 0 : value >= 0))
    throw UsageError{option + ": expected a finite number " + (positive ? "> 0" : ">= 0") +
                     ", got \"" + text + "\""};
  return value;
}

bool parse_stability_search_option(const std::vector<std::string>& args, std::size_t& i,
                                   StabilitySearchOptions& options) {
  const std::string& a = args[i];
  if (a == "--label") {
    options.label = option_value(args, i);
  } else if (a == "--tolerance") {
    options.tolerance = finite_number_option(a, option_value(args, i), true);
  } else if (a == "--epsilon") {
    options.epsilon_j = finite_number_option(a, option_value(args, i), true);
  } else if (a == "--criterion") {
    const std::string name = option_value(args, i);
    const std::optional<StabilityCriterion> criterion = stability_criterion_named(name);
    if (!criterion)
      throw UsageError{"--criterion: expected all, passivity or oscillation, got \"" + name + "\""};
    options.criterion = *criterion;
  } else if (a == "--out") {
    options.out = option_value(args, i);
  } else if (parse_progress_option(args, i, options.progress)) {
  } else if (a.rfind("--", 0) == 0) {
    return false;
  } else if (!options.scenario.empty()) {
    throw UsageError{"one scenario at a time (got " + options.scenario + " and " + a + ")"};
  } else {
    options.scenario = a;
  }
  return true;
}

void require_stability_search_options(const StabilitySearchOptions& options) {
  if (options.scenario.empty()) throw UsageError{"no scenario given"};
  if (options.label.empty()) throw UsageError{"--label LABEL is required"};
}

StabilityBracket SearchKeepingRuns::search(const std::function<StabilityProbe(double)>& probe,
                                           double low, double high, double tolerance) {
  try {
    return search_largest_stable(
        [&](double value) {
          finished_.push_back(probe(value));
          return finished_.back();
        },
        low, high, tolerance);
  } catch (const Interrupted&) {
    progress_.close();
    if (!finished_.empty()) {
      nlohmann::ordered_json document = description_;
      document["interrupted"] = true;
      nlohmann::ordered_json runs = nlohmann::ordered_json::array();
      for (const StabilityProbe& finished : finished_) runs.push_back(probe_json(finished));
      document["runs"] = runs;
      folder_.write_file(partial_name_, document.dump(2) + "\n");
      folder_.commit();
    }
    throw;
  }
}

}  // namespace hb
