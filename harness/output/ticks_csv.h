// ticks_<label>.csv: one row per tick (DESIGN.md column contract, then
// extra columns), and a hash of everything in it except wall-clock timings,
// which is the run's determinism fingerprint.
#pragma once

#include <string>
#include <vector>

#include "algorithms/core/content_hash.h"
#include "harness/metrics/run_metrics.h"
#include "harness/replay/replay.h"

namespace hb {

/// The header row, without newline.
const std::string& ticks_csv_header();

/// The wall-clock columns (step_ns, slow_update_ns, oracle_ns): the only
/// ones that differ between two runs of one scenario on one build.
const std::vector<std::string>& ticks_csv_timing_columns();

class TicksCsvWriter {
 public:
  TicksCsvWriter();
  void add(const TickRecord& record, const TickEvaluation& evaluation);
  /// The whole file, header included.
  const std::string& text() const { return text_; }
  /// Hex hash of every column but step_ns and slow_update_ns: equal for two
  /// runs exactly when they computed the same numbers.
  std::string deterministic_hash() const { return hash_.hex(); }

 private:
  std::string text_;
  ContentHash hash_;
};

}  // namespace hb
