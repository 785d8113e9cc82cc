// SIGINT and SIGTERM as a request to stop cleanly: the handler only records
// the signal; long loops (the replay, the sweep's worker pool) check it and
// throw Interrupted, so that destructors remove staging folders and child
// processes before main() reports the interruption and exits with 128 +
// the signal number. A second signal while stopping ends the process at
// once (a stale staging folder is then removed by the next run).
#pragma once

#include <stdexcept>

namespace hb {

struct Interrupted : std::runtime_error {
  explicit Interrupted(int signal_number);
  int signal;
};

/// Installs the handlers for SIGINT and SIGTERM (idempotent).
void install_interrupt_handlers();

/// The signal received since the handlers were installed, or 0.
int interrupt_signal();

/// Throws Interrupted when a signal was received.
inline void throw_if_interrupted() {
  if (const int signal = interrupt_signal()) throw Interrupted(signal);
}

}  // namespace hb
