#include "harness/cli/stability_options.h"

#include "harness/cli/command_line.h"
#include "harness/process/interrupt.h"
#include "harness/scenario/json_pointer.h"

namespace hb {

const char* const kStabilityCriterionHelp =
    "stable means not diverged, no non-finite wrench, and by the criterion: passivity, the port "
    "energy minimum >= -J (--epsilon; in closed loop, docs/closed-loop.md, the energy the hand "
    "put into the device, display_energy_min_j); oscillation, no chatter at the end of the run "
    "(proxy_chatter_m, docs/metrics.md; in closed loop no limit cycle of the device either); "
    "all, both";

StabilityCriterion stability_criterion_option(const std::string& name) {
  const std::optional<StabilityCriterion> criterion = stability_criterion_named(name);
  if (!criterion)
    throw UsageError{"--criterion: expected all, passivity or oscillation, got \"" + name + "\""};
  return *criterion;
}

const std::string& json_pointer_option(const std::string& option, const std::string& pointer) {
  if (!json_pointer_tokens(pointer))
    throw UsageError{option + ": expected a JSON pointer such as /coupling/k_t, got \"" + pointer +
                     "\""};
  return pointer;
}

std::pair<double, double> range_option(const std::string& option,
                                       const std::vector<std::string>& values) {
  const double low = number_in(option + " LO", values.at(0), above(0));
  const double high = number_in(option + " HI", values.at(1), above(0));
  if (!(low < high)) throw UsageError{option + ": expected LO < HI"};
  return {low, high};
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
