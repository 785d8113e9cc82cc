// The short table `hapticbench run` prints per scenario.
#pragma once

#include <ostream>

#include "harness/output/run_report.h"

namespace hb {

/// One row per algorithm: timing, accuracy, stability and budget verdicts;
/// "-" where a metric does not apply.
void print_run_table(std::ostream& out, const ScenarioRun& run);

/// What each column of print_run_table means, with its unit and the
/// summary.json field it shows, as a Markdown table (`run --explain`;
/// docs/metrics.md holds it).
void print_run_table_legend(std::ostream& out);

}  // namespace hb
