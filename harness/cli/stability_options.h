// The options `hapticbench stability` and `hapticbench zwidth` share: the
// scenario, the algorithm, the search's tolerance and criterion, the output
// folder and the progress display.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "harness/output/run_folder.h"
#include "harness/progress/progress_display.h"
#include "harness/stability/stability_search.h"

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

/// After a stop signal ended a search: writes `document` (what was being
/// searched) with "interrupted": true and the runs that finished to
/// `name` in `folder` (stability.partial.json, zwidth.partial.json: not
/// the name a report reads), and commits the folder. Nothing when no run
/// finished.
void keep_interrupted_search(StagedRunFolder& folder, const std::string& name,
                             nlohmann::ordered_json document,
                             const std::vector<StabilityProbe>& finished);

}  // namespace hb
