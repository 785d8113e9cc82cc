// Runs kept by commit: a folder the user names (HISTORY_DIR) holds
// history.json, listing entries oldest first, and one folder per entry with
// each scenario's summary.json as its run wrote it:
//
//   HISTORY_DIR/history.json   {"schema_version": 1, "entries": [{"commit",
//                               "date", "folder", "scenarios"}, ...]}
//   HISTORY_DIR/0001-3f2a9c1/<scenario>/summary.json
//
// `hapticbench history add` appends to it, `history show` and `report
// --history` read it (docs/reports-compare-sweeps.md).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "harness/compare/comparison.h"

namespace hb {

struct HistoryEntry {
  std::string commit;                  ///< the build's commit, or what --commit named
  std::string date;                    ///< the newest run's date (ISO 8601, UTC)
  std::string folder;                  ///< under HISTORY_DIR
  std::vector<std::string> scenarios;  ///< scenario names, sorted
};

/// history.json's entries, oldest first; empty when the folder does not
/// exist or is empty. Throws InputError naming history.json when it is
/// garbled, or the folder when it holds files but no history.json (a
/// folder that is not a history: nothing is written into it).
std::vector<HistoryEntry> read_history(const std::filesystem::path& history_dir);

/// Stores the summaries of `run_dirs` (run folders or suites of them) as
/// the entry of `commit` (default: the commit the summaries name, which
/// must be one). An entry of the same commit is replaced where it stands;
/// otherwise the entry is appended. The entry's folder is written whole
/// before history.json names it. Throws InputError for unreadable runs,
/// summaries of different commits without `commit`, or a scenario twice.
HistoryEntry add_to_history(const std::filesystem::path& history_dir,
                            const std::vector<std::filesystem::path>& run_dirs,
                            const std::optional<std::string>& commit);

/// A check that moved beyond its tolerance between two consecutive entries:
/// the first entry at which it did, per scenario, label and check.
struct HistoryMove {
  std::size_t entry = 0;  ///< index of the entry where it moved
  CheckRow row;           ///< the check against the entry before it
};

/// For each (scenario, label, check) of compare's checks between
/// consecutive entries (accuracy, stability and instruction counts; no
/// wall-clock times: the store keeps no ticks), the first entry at which it
/// regressed, improved or failed; in entry order.
std::vector<HistoryMove> first_moves(const std::filesystem::path& history_dir,
                                     const std::vector<HistoryEntry>& entries,
                                     const CompareOptions& options);

}  // namespace hb
