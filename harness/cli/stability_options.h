// The options `hapticbench stability` and `hapticbench zwidth` share: the
// scenario, the algorithm, the search's tolerance and criterion, the output
// folder and the progress display.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

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

/// Usage lines of the shared options.
extern const char* const kStabilitySearchUsage;

/// Takes args[i] (and its value) when it is a shared option or the
/// scenario; false for anything else. Throws UsageError for a bad value, an
/// unknown option or a second scenario.
bool parse_stability_search_option(const std::vector<std::string>& args, std::size_t& i,
                                   StabilitySearchOptions& options);

/// Throws UsageError when the scenario or the label is missing.
void require_stability_search_options(const StabilitySearchOptions& options);

/// `text` as a finite number, > 0 (positive) or >= 0; throws UsageError
/// naming `option` otherwise.
double finite_number_option(const std::string& option, const std::string& text, bool positive);

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
