// ticks_<label>.csv: one row per tick (DESIGN.md column contract, then
// extra columns), and a hash of everything in it except wall-clock timings,
// which is the run's determinism fingerprint.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "hapticbench/content_hash.h"
#include "harness/metrics/run_metrics.h"
#include "harness/replay/replay.h"

namespace hb {

/// The header row, without newline.
const std::string& ticks_csv_header();

/// The wall-clock columns (step_ns, slow_update_ns, oracle_ns): the only
/// ones that differ between two runs of one scenario on one build.
const std::vector<std::string>& ticks_csv_timing_columns();

/// Writes the rows to a stream as the ticks arrive (in blocks of about
/// 256 KB), so a run's length costs no memory.
class TicksCsvWriter {
 public:
  /// Writes the header to `out`, which must outlive the writer.
  explicit TicksCsvWriter(std::ostream& out);
  void add(const TickRecord& record, const TickEvaluation& evaluation);
  /// Writes the rows still buffered and flushes the stream; false when the
  /// stream failed at any point.
  bool finish();
  /// Hex hash of every column but step_ns and slow_update_ns: equal for two
  /// runs exactly when they computed the same numbers.
  std::string deterministic_hash() const { return hash_.hex(); }

 private:
  std::ostream& out_;
  std::string buffer_;
  ContentHash hash_;
};

}  // namespace hb
