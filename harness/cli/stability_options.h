// The options `hapticbench stability` and `hapticbench zwidth` share, as
// rows of their option tables: the scenario, the algorithm, the search's
// tolerance and criterion, the output folder and the progress display.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "harness/cli/option_table.h"
#include "harness/drivers/stability_search.h"
#include "harness/output/run_folder.h"
#include "harness/progress/progress_display.h"

namespace hb {

struct StabilitySearchOptions {
  std::string scenario;
  std::string label;
  double tolerance = 0.02;
  double epsilon_j = 1e-6;
  StabilityCriterion criterion = StabilityCriterion::kAll;
  std::optional<std::string> out;
  std::optional<ProgressStyle> progress;
};

/// What --criterion's values mean.
extern const char* const kStabilityCriterionHelp;

/// The criterion --criterion names; throws UsageError naming the criteria.
StabilityCriterion stability_criterion_option(const std::string& name);

/// A JSON pointer given to `option`; throws UsageError when it is not one.
const std::string& json_pointer_option(const std::string& option, const std::string& pointer);

/// The two values of `option` LO HI: numbers > 0, LO < HI; throws UsageError otherwise.
std::pair<double, double> range_option(const std::string& option,
                                       const std::vector<std::string>& values);

/// The rows of the scenario and the algorithm, for a command whose
/// arguments hold the shared options in `search`.
template <class Args>
std::vector<typename OptionTable<Args>::Row> stability_target_rows(
    StabilitySearchOptions Args::*search) {
  using Table = OptionTable<Args>;
  using Options = StabilitySearchOptions;
  return {Table::positional("SCENARIO.json", "the scenario whose runs are the probes", 1, 1,
                            member_of(search, &Options::scenario)),
          Table::value("--label", "LABEL", "the algorithm searched: its label in the scenario",
                       member_of(search, &Options::label))
              .required()};
}

/// The rows of the search's options; `result` names the file --out's
/// folder holds ("stability.json"), `default_out` that folder by default.
template <class Args>
std::vector<typename OptionTable<Args>::Row> stability_search_rows(
    StabilitySearchOptions Args::*search, const std::string& result,
    const std::string& default_out) {
  using Table = OptionTable<Args>;
  using Options = StabilitySearchOptions;
  return {
      Table::number("--tolerance", "REL", "stop when smallest_unstable / largest_stable - 1 <= REL",
                    above(0), member_of(search, &Options::tolerance))
          .with_default("0.02"),
      Table::number("--epsilon", "J", "passivity allowance, J", above(0),
                    member_of(search, &Options::epsilon_j))
          .with_default("1e-6"),
      Table::value("--criterion", "all|passivity|oscillation", kStabilityCriterionHelp,
                   [search](Args& args, const std::string& name) {
                     (args.*search).criterion = stability_criterion_option(name);
                   })
          .with_default("all"),
      Table::value("--out", "DIR", "the folder for " + result, member_of(search, &Options::out))
          .with_default(default_out),
      Table::progress(member_of(search, &Options::progress)),
      Table::quiet(member_of(search, &Options::progress))};
}

/// Stability searches whose finished runs outlive a stop signal: when one
/// ends a search, the runs finished so far (across every search made
/// through this object) are written with `description` and "interrupted":
/// true to `partial_name` in `folder` (stability.partial.json,
/// zwidth.partial.json: not the name a report reads), the folder is
/// committed, and Interrupted is thrown on. Nothing is written when no run
/// finished.
class SearchKeepingRuns {
 public:
  SearchKeepingRuns(StagedRunFolder& folder, std::string partial_name,
                    nlohmann::ordered_json description, ProgressDisplay& progress)
      : folder_(folder),
        partial_name_(std::move(partial_name)),
        description_(std::move(description)),
        progress_(progress) {}

  /// search_largest_stable over [low, high], each finished run kept.
  StabilityBracket search(const std::function<StabilityProbe(double)>& probe, double low,
                          double high, double tolerance);

 private:
  StagedRunFolder& folder_;
  std::string partial_name_;
  nlohmann::ordered_json description_;
  ProgressDisplay& progress_;
  std::vector<StabilityProbe> finished_;
};

}  // namespace hb
