// Progress of long work on stderr, in one of three styles:
//  - bar: one live line per task (e.g. "[2/5] armadillo_on_bunny / god_object:
//    timing pass 31,000/60,000 ticks 52%, 0:02, ETA 0:02"), redrawn in
//    place at most 10 times a second and erased when the task is done;
//  - plain: one line for each phase or preprocessing stage still running
//    after a second, nothing redrawn (logs, pipes);
//  - none: nothing.
// A background thread redraws while untimed work runs (preprocessing, the
// evaluation pass, the oracle), so that the elapsed time moves even inside
// one long call. During a timed phase (a timing pass) that thread sleeps
// and never wakes; the replay loop's observer redraws between ticks, from
// the tick counter only, never inside step().
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <thread>

#include "algorithms/core/build_progress.h"

namespace hb {

enum class ProgressStyle { kBar, kPlain, kNone };

/// "bar", "plain", "none"; nullopt for anything else.
std::optional<ProgressStyle> progress_style_named(std::string_view name);
/// Without a choice: a bar when stderr is a terminal, else plain lines.
ProgressStyle default_progress_style();
/// Columns of the terminal on stderr; 100 when it is not one or does not say.
std::size_t terminal_width();
/// "mm:ss", or "h:mm:ss" from one hour on; seconds rounded up.
std::string format_eta(double seconds);
/// The same with seconds rounded down (time spent so far).
std::string format_elapsed(double seconds);
/// 60000 -> "60,000".
std::string with_thousands(int64_t value);

/// How a display behaves beyond its style.
struct ProgressSettings {
  ProgressStyle style = ProgressStyle::kNone;
  /// Nothing is shown before the command has run this long, s: commands
  /// that are usually quick (report, compare, validate) stay silent when they are.
  double quiet_for_s = 0;
  /// The bar is kept within this many columns (a wrapped line cannot be
  /// redrawn); 0: the terminal's width.
  std::size_t line_width = 0;
  /// Seconds since an arbitrary origin; a steady clock unless a test gives one.
  std::function<double()> clock;
};

class ProgressDisplay : public BuildProgressListener {
 public:
  ProgressDisplay(std::ostream& out, ProgressSettings settings);
  /// Erases the live line.
  ~ProgressDisplay() override;
  ProgressDisplay(const ProgressDisplay&) = delete;
  ProgressDisplay& operator=(const ProgressDisplay&) = delete;

  ProgressStyle style() const { return settings_.style; }

  /// Put before every task name, e.g. "[2/5] ".
  void set_prefix(std::string prefix);
  /// The task the next phases belong to, e.g. "armadillo_on_bunny / god_object".
  void task(std::string name);
  /// A phase of the task: "preprocessing", "timing pass", "evaluation pass",
  /// "oracle", ...; total: units it counts (ticks; 0: it counts none);
  /// unit: their name. timed: the phase is being measured (see above).
  void phase(std::string name, int64_t total = 0, bool timed = false, std::string unit = "ticks");
  /// What the phase is doing now, e.g. "convex hierarchy of bunny: building".
  void stage(std::string detail);
  /// Units done in the phase. Cheap: one relaxed store, and in a timed
  /// phase a clock read every 64 calls and a redraw at most 10 times a second.
  void advance(int64_t done);
  /// Writes `text` (whole lines) to `stream` above the live line, e.g. a
  /// result table on stdout, so that the two never share a line.
  void print_above(std::ostream& stream, const std::string& text);
  /// The task is done: its live line is erased.
  void finish_task();
  /// Stops the display and erases the live line (the destructor does this);
  /// nothing is drawn after it.
  void close();

  // BuildProgressListener: preprocessing stages become the phase's stage.
  void build_stage(std::string_view stage) override;
  void build_progress(std::size_t done, std::size_t total) override;

 private:
  void run_ticker();
  bool showing_allowed(double now) const;
  void redraw_locked(double now);
  void erase_locked();
  void print_plain_locked(double now);
  std::string bar_text(double now) const;

  std::ostream& out_;
  ProgressSettings settings_;
  double start_s_ = 0;

  std::mutex mutex_;
  std::condition_variable wake_;
  std::thread ticker_;
  bool stopping_ = false;
  bool closed_ = false;

  // The state shown; written by the working thread under mutex_ (done_ is
  // atomic so that advance() takes no lock).
  std::string prefix_, task_, phase_, stage_, unit_;
  int64_t total_ = 0;
  std::atomic<int64_t> done_{0};
  bool timed_ = false;
  double phase_start_s_ = 0;
  /// Since when the phase's (or stage's) plain line is due; -1: printed or none due.
  double plain_pending_since_s_ = -1;
  bool drawn_ = false;  ///< a bar line is on the terminal
  double last_draw_s_ = -1;
};

/// Units per second so far, and the seconds left at that rate; negative
/// when nothing is done yet.
double remaining_seconds(double elapsed_s, int64_t done, int64_t total);

}  // namespace hb
