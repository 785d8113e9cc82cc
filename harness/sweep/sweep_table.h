// A sweep read as a sweep: one row per job and label, the grid values
// first, in numeric order within each scenario, then the run's headline
// figures read back from the job's summary.json. Printed after a sweep and
// written beside sweep.json as sweep.md.
#pragma once

#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "harness/sweep/sweep_index.h"
#include "harness/sweep/sweep_jobs.h"
#include "harness/sweep/sweep_spec.h"

namespace hb {

struct SweepTableRow {
  std::size_t job_index = 0;
  std::vector<std::string> grid_cells;  ///< each grid key's value, as the sweep file gives it
  std::string scenario;                 ///< the sweep's entry for the job's scenario
  std::string label;                    ///< "" when the job has no summary
  std::string status;                   ///< the job's sweep_job_status_name
  std::optional<double> force_err_rms_n, penetration_max_mm, step_p50_us, step_p99_us;
  std::string stability;  ///< "stable", the failed check, "(expected)" marked; "" without a run
  std::string budgets;    ///< "2/2 pass", "1/2 FAIL", "none"
};

/// The rows of every job (one per label when its summary.json is readable,
/// one saying the job's status otherwise), ordered by scenario and then by
/// the grid values: numbers by value, other values by their text.
std::vector<SweepTableRow> sweep_table_rows(const SweepSpec& spec,
                                            const std::vector<SweepJob>& jobs,
                                            const std::vector<SweepJobState>& states,
                                            const std::filesystem::path& out_dir);

/// The console's cross-job table.
void print_sweep_table(std::ostream& out, const SweepSpec& spec,
                       const std::vector<SweepTableRow>& rows);

/// sweep.md: the sweep's name, file and grid, and the cross-job table in
/// Markdown. Its first line marks it as hapticbench's (is_sweep_table_file).
std::string sweep_table_markdown(const SweepSpec& spec, const std::vector<SweepTableRow>& rows);

/// Whether `path` is a sweep.md that sweep_table_markdown wrote, so that a
/// later sweep may replace it.
bool is_sweep_table_file(const std::filesystem::path& path);

}  // namespace hb
