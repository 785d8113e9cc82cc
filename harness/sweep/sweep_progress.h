// Progress of a sweep on stderr. On a terminal: one line redrawn in place,
// "[k/n] job-name ... ETA mm:ss". Otherwise (a log file, a batch system):
// one line per finished job, nothing redrawn.
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <ostream>
#include <string>

#include "harness/progress/progress_display.h"

namespace hb {

/// Seconds left if the rest goes as fast as the finished part did:
/// remaining jobs × elapsed / finished jobs (parallel workers included in
/// the rate); negative when nothing has finished yet.
double estimate_remaining_seconds(double elapsed_s, std::size_t finished, std::size_t total);

class SweepProgress {
 public:
  /// Seconds since an arbitrary origin; a steady clock unless a test gives one.
  using Clock = std::function<double()>;

  /// total: the jobs this invocation runs. terminal: redraw one line, kept
  /// within line_width characters (a wrapped line could not be redrawn).
  SweepProgress(std::ostream& out, std::size_t total, bool terminal, std::size_t line_width = 100,
                Clock clock = {});

  /// A job started.
  void started(const std::string& job);
  /// A job finished; verdict e.g. "ok", "budgets failed", "crashed (exit code 3)".
  /// ok: an expected outcome; anything else also gets a line of its own on a terminal.
  void finished(const std::string& job, const std::string& verdict, double job_seconds, bool ok);
  /// Redraws the terminal line (ETA ticking), at most once a second.
  void refresh();
  /// Ends the terminal line.
  void close();

 private:
  void draw();

  std::ostream& out_;
  std::size_t total_;
  bool terminal_;
  std::size_t line_width_;
  Clock clock_;
  double start_s_ = 0;
  double last_draw_s_ = -1;
  std::size_t finished_ = 0;
  std::string current_job_;
};

}  // namespace hb
