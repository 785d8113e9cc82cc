// What `hapticbench ccd` measures on a query file: the kernels' answers
// against the ground truth, and each query's time.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "algorithms/ccd/ccd_primitives.h"
#include "harness/cli/ccd_query_file.h"

namespace hb {

struct CcdFileOutcome {
  std::string file;
  CcdQueryKind kind = CcdQueryKind::kVertexFace;
  int queries = 0;
  int collisions = 0;
  int false_negatives = 0;
  int false_positives = 0;
  int budget_exhausted = 0;
  std::vector<std::int64_t> ns;  // per query
};

/// Runs every query of `file` for its answer, then times each alone (its
/// fastest of 3 runs, caches warm from the first pass).
CcdFileOutcome evaluate_ccd_file(const CcdQueryFile& file, const CcdSettings& settings);

struct CcdTimeSummary {
  double mean = 0;
  std::int64_t median = 0;
  std::int64_t max = 0;
};

/// Mean, lower median and maximum.
CcdTimeSummary summarise_ccd_times(std::vector<std::int64_t> ns);

}  // namespace hb
