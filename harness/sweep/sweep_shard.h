// One slice of a sweep's jobs, so that N independent tasks (a Slurm job
// array, N machines) run a sweep between them: task I runs the jobs whose
// index % N == I.
#pragma once

#include <cstddef>
#include <string>

namespace hb {

struct SweepShard {
  std::size_t index = 0;  ///< I, in [0, count)
  std::size_t count = 1;  ///< N >= 1
};

/// Parses "I/N" (whole numbers, 0 <= I < N). Throws InputError with
/// location "--shard" and the expected form otherwise.
SweepShard parse_sweep_shard(const std::string& text);

/// True when the job with this index belongs to the shard.
bool in_shard(std::size_t job_index, const SweepShard& shard);

/// "I/N".
std::string shard_text(const SweepShard& shard);

}  // namespace hb
