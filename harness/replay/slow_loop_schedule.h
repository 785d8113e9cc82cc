// The schedule of a multi-rate algorithm's slow updates in virtual time:
// when each started and when its result was installed. Recorded by the
// timing pass, replayed by the evaluation pass (so both compute the same),
// written to the run folder as schedule_<label>.csv and replayed by
// `hapticbench run --schedule`.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace hb {

struct SlowLoopUpdate {
  int64_t start_tick = 0;    ///< the update started after this tick's step()
  int64_t install_tick = 0;  ///< its result was installed before this tick's step()
  int64_t update_ns = 0;     ///< wall time it took where it was recorded (ns)
};

struct SlowLoopSchedule {
  std::vector<SlowLoopUpdate> updates;  ///< in order; each starts when the previous is installed
};

/// A replayed schedule that does not fit the run replaying it.
class ScheduleMismatch : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The CSV text: header `start_tick,install_tick,update_ns`, one row per update.
std::string schedule_csv(const SlowLoopSchedule& schedule);

/// Parses schedule_csv's format. Throws InputError(path, "line N", ...) for
/// a malformed row, install_tick <= start_tick, or an update that starts
/// before the previous one is installed.
SlowLoopSchedule parse_schedule_csv(const std::string& text, const std::string& path);

/// Reads and parses a schedule file (InputError naming it when unreadable).
SlowLoopSchedule read_schedule_file(const std::string& path);

}  // namespace hb
