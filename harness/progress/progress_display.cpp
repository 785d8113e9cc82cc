#include "harness/progress/progress_display.h"

#include <sys/ioctl.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <sstream>

namespace hb {

namespace {
constexpr double kRedrawPeriodS = 0.1;  // at most 10 redraws a second
constexpr int64_t kTicksBetweenClockReads = 64;
// A plain line is written for a phase or stage still running after this
// long, s: a quick one leaves no line in a log, a slow or stuck one does.
constexpr double kPlainAfterS = 1.0;

double steady_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Keeps `text` within `width` columns (counting bytes; the names shown are
// ASCII) by cutting its middle, marked "...": both ends (a scenario's
// start, an algorithm's label) stay readable.
std::string fit(const std::string& text, std::size_t width) {
  if (text.size() <= width || width < 8) return text;
  const std::size_t keep = width - 3, front = keep / 3;
  return text.substr(0, front) + "..." + text.substr(text.size() - (keep - front));
}
}  // namespace

std::optional<ProgressStyle> progress_style_named(std::string_view name) {
  if (name == "bar") return ProgressStyle::kBar;
  if (name == "plain") return ProgressStyle::kPlain;
  if (name == "none") return ProgressStyle::kNone;
  return std::nullopt;
}

ProgressStyle default_progress_style() {
  return ::isatty(STDERR_FILENO) == 1 ? ProgressStyle::kBar : ProgressStyle::kPlain;
}

std::size_t terminal_width() {
  winsize size{};
  if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col >= 20) return size.ws_col;
  return 100;
}

namespace {
std::string minutes_and_seconds(long long total) {
  char text[32];
  if (total >= 3600)
    std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", total / 3600, total / 60 % 60,
                  total % 60);
  else
    std::snprintf(text, sizeof text, "%02lld:%02lld", total / 60, total % 60);
  return text;
}
}  // namespace

std::string format_eta(double seconds) {
  return minutes_and_seconds(seconds > 0 ? static_cast<long long>(std::ceil(seconds)) : 0);
}

std::string format_elapsed(double seconds) {
  return minutes_and_seconds(seconds > 0 ? static_cast<long long>(std::floor(seconds)) : 0);
}

std::string with_thousands(int64_t value) {
  const std::string digits = std::to_string(value < 0 ? -value : value);
  std::string text = value < 0 ? "-" : "";
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) text.push_back(',');
    text.push_back(digits[i]);
  }
  return text;
}

double remaining_seconds(double elapsed_s, int64_t done, int64_t total) {
  if (done <= 0) return -1;
  const int64_t left = total > done ? total - done : 0;
  return elapsed_s * static_cast<double>(left) / static_cast<double>(done);
}

ProgressDisplay::ProgressDisplay(std::ostream& out, ProgressSettings settings)
    : out_(out), settings_(std::move(settings)) {
  if (!settings_.clock) settings_.clock = steady_seconds;
  if (settings_.line_width == 0) settings_.line_width = terminal_width();
  start_s_ = settings_.clock();
  phase_start_s_ = start_s_;
  if (settings_.style != ProgressStyle::kNone) ticker_ = std::thread([this] { run_ticker(); });
}

ProgressDisplay::~ProgressDisplay() { close(); }

void ProgressDisplay::close() {
  {
    std::lock_guard lock(mutex_);
    if (closed_) return;
    closed_ = true;
    stopping_ = true;
  }
  wake_.notify_all();
  if (ticker_.joinable()) ticker_.join();
  std::lock_guard lock(mutex_);
  erase_locked();
}

void ProgressDisplay::set_prefix(std::string prefix) {
  std::lock_guard lock(mutex_);
  prefix_ = std::move(prefix);
}

void ProgressDisplay::task(std::string name) {
  std::lock_guard lock(mutex_);
  task_ = std::move(name);
  phase_.clear();
  stage_.clear();
}

void ProgressDisplay::phase(std::string name, int64_t total, bool timed, std::string unit) {
  if (settings_.style == ProgressStyle::kNone) return;
  {
    std::lock_guard lock(mutex_);
    phase_ = std::move(name);
    stage_.clear();
    unit_ = std::move(unit);
    total_ = total;
    done_.store(0, std::memory_order_relaxed);
    timed_ = timed;
    const double now = settings_.clock();
    phase_start_s_ = now;
    plain_pending_since_s_ = now;
    if (settings_.style == ProgressStyle::kBar && now - last_draw_s_ >= kRedrawPeriodS)
      redraw_locked(now);
  }
  wake_.notify_all();  // the ticker sleeps through timed phases and wakes after them
}

void ProgressDisplay::stage(std::string detail) {
  if (settings_.style == ProgressStyle::kNone) return;
  std::lock_guard lock(mutex_);
  stage_ = std::move(detail);
  // A stage restarts the count: the build announces its own.
  total_ = 0;
  done_.store(0, std::memory_order_relaxed);
  const double now = settings_.clock();
  plain_pending_since_s_ = now;
  if (settings_.style == ProgressStyle::kBar && now - last_draw_s_ >= kRedrawPeriodS)
    redraw_locked(now);
}

void ProgressDisplay::advance(int64_t done) {
  done_.store(done, std::memory_order_relaxed);
  // Only the working thread sets timed_, and it is the caller here.
  if (!timed_ || settings_.style == ProgressStyle::kNone || done % kTicksBetweenClockReads != 0)
    return;
  const double now = settings_.clock();
  std::lock_guard lock(mutex_);
  if (settings_.style == ProgressStyle::kPlain)
    print_plain_locked(now);
  else if (now - last_draw_s_ >= kRedrawPeriodS)
    redraw_locked(now);
}

void ProgressDisplay::build_stage(std::string_view stage_text) { stage(std::string(stage_text)); }

void ProgressDisplay::build_progress(std::size_t done, std::size_t total) {
  if (settings_.style == ProgressStyle::kNone) return;
  std::lock_guard lock(mutex_);
  total_ = static_cast<int64_t>(total);
  unit_.clear();  // a fraction of a build: shown as a percentage
  done_.store(static_cast<int64_t>(done), std::memory_order_relaxed);
}

void ProgressDisplay::print_above(std::ostream& stream, const std::string& text) {
  std::lock_guard lock(mutex_);
  const bool was_drawn = drawn_;
  erase_locked();
  stream << text << std::flush;
  if (was_drawn) redraw_locked(settings_.clock());
}

void ProgressDisplay::finish_task() {
  std::lock_guard lock(mutex_);
  erase_locked();
  task_.clear();
  phase_.clear();
  stage_.clear();
  total_ = 0;
  timed_ = false;
  plain_pending_since_s_ = -1;
}

void ProgressDisplay::run_ticker() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    if (timed_) {
      // Asleep for the whole timed phase: no wake-up can land in a step().
      wake_.wait(lock, [this] { return stopping_ || !timed_; });
      continue;
    }
    wake_.wait_for(lock, std::chrono::duration<double>(kRedrawPeriodS));
    if (stopping_ || timed_) continue;
    const double now = settings_.clock();
    if (settings_.style == ProgressStyle::kPlain)
      print_plain_locked(now);
    else if (!phase_.empty())
      redraw_locked(now);
  }
}

bool ProgressDisplay::showing_allowed(double now) const {
  return now - start_s_ >= settings_.quiet_for_s;
}

void ProgressDisplay::redraw_locked(double now) {
  if (settings_.style != ProgressStyle::kBar || closed_ || phase_.empty() || !showing_allowed(now))
    return;
  last_draw_s_ = now;
  out_ << "\r\033[K" << bar_text(now) << std::flush;
  drawn_ = true;
}

void ProgressDisplay::erase_locked() {
  if (!drawn_) return;
  out_ << "\r\033[K" << std::flush;
  drawn_ = false;
}

void ProgressDisplay::print_plain_locked(double now) {
  if (closed_ || plain_pending_since_s_ < 0 || now - plain_pending_since_s_ < kPlainAfterS ||
      phase_.empty() || !showing_allowed(now))
    return;
  plain_pending_since_s_ = -1;
  out_ << "[" << format_elapsed(now - start_s_) << "] " << prefix_ << task_ << ": " << phase_;
  if (!stage_.empty()) out_ << ", " << stage_;
  if (total_ > 0 && !unit_.empty()) out_ << " (" << with_thousands(total_) << " " << unit_ << ")";
  out_ << "\n" << std::flush;
}

std::string ProgressDisplay::bar_text(double now) const {
  // What runs (task, then phase and stage) and how far it is; a narrow
  // terminal shortens the task first, then the phase, never the numbers.
  std::string task = prefix_ + task_;
  std::string what = ": " + phase_;
  if (!stage_.empty()) what += ", " + stage_;
  const int64_t done = done_.load(std::memory_order_relaxed);
  const double elapsed = now - phase_start_s_;
  std::ostringstream tail;
  if (total_ > 0) {
    const double fraction = std::min(1.0, static_cast<double>(done) / static_cast<double>(total_));
    tail << " ";
    if (!unit_.empty())
      tail << with_thousands(done) << "/" << with_thousands(total_) << " " << unit_ << " ";
    tail << static_cast<int>(std::floor(100 * fraction)) << "%";
  }
  const std::string elapsed_text = " elapsed " + format_elapsed(elapsed);
  if (total_ > 0) {
    const double left = remaining_seconds(elapsed, done, total_);
    tail << elapsed_text << ", ETA " << (left < 0 ? std::string("--:--") : format_eta(left));
  } else {
    tail << elapsed_text;
  }
  std::string numbers = tail.str();
  const std::size_t width = settings_.line_width > 1 ? settings_.line_width - 1 : 0;
  constexpr std::size_t kShortestTask = 16;
  // Very narrow: the time spent goes before the ETA does.
  if (total_ > 0 && task.size() + what.size() + numbers.size() > width &&
      kShortestTask + 8 + numbers.size() > width)
    numbers.erase(numbers.find(elapsed_text), elapsed_text.size() + 1);
  if (task.size() + what.size() + numbers.size() > width) {
    const std::size_t fixed = what.size() + numbers.size();
    task = fit(task, width > fixed + kShortestTask ? width - fixed : kShortestTask);
  }
  if (task.size() + what.size() + numbers.size() > width) {
    const std::size_t fixed = task.size() + numbers.size();
    what = fit(what, width > fixed + 8 ? width - fixed : 8);
  }
  return task + what + numbers;
}

}  // namespace hb
