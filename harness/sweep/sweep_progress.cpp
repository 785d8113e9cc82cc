#include "harness/sweep/sweep_progress.h"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace hb {

namespace {
constexpr double kRedrawPeriodS = 1.0;
}  // namespace

double estimate_remaining_seconds(double elapsed_s, std::size_t finished, std::size_t total) {
  if (finished == 0) return -1;
  const std::size_t remaining = total > finished ? total - finished : 0;
  return elapsed_s * static_cast<double>(remaining) / static_cast<double>(finished);
}

SweepProgress::SweepProgress(std::ostream& out, std::size_t total, bool terminal,
                             std::size_t line_width, Clock clock)
    : out_(out),
      total_(total),
      terminal_(terminal),
      line_width_(line_width),
      clock_(std::move(clock)) {
  if (!clock_) {
    clock_ = [] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
          .count();
    };
  }
  start_s_ = clock_();
}

void SweepProgress::started(const std::string& job) {
  current_job_ = job;
  if (terminal_) draw();
}

void SweepProgress::finished(const std::string& job, const std::string& verdict, double job_seconds,
                             bool ok) {
  ++finished_;
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%.1f s", job_seconds);
  std::ostringstream text;
  text << "[" << finished_ << "/" << total_ << "] " << job << ": " << verdict << " (" << seconds
       << ")";
  const std::string line = text.str();
  if (!terminal_) {
    out_ << line << "\n" << std::flush;
    return;
  }
  if (!ok) out_ << "\r\033[K" << line << "\n";
  draw();
}

void SweepProgress::refresh() {
  if (terminal_ && clock_() - last_draw_s_ >= kRedrawPeriodS) draw();
}

void SweepProgress::close() {
  if (!terminal_) return;
  out_ << "\r\033[K[" << finished_ << "/" << total_ << "] done in "
       << format_eta(clock_() - start_s_) << "\n"
       << std::flush;
}

void SweepProgress::draw() {
  const double now = clock_();
  last_draw_s_ = now;
  const double remaining = estimate_remaining_seconds(now - start_s_, finished_, total_);
  std::ostringstream head_text;
  head_text << "[" << finished_ << "/" << total_ << "] ";
  const std::string head = head_text.str();
  const std::string tail =
      " ... ETA " + (remaining < 0 ? std::string("--:--") : format_eta(remaining));
  // The end of a job name (its grid values) tells jobs apart; keep that.
  std::string job = current_job_;
  const std::size_t room =
      line_width_ > head.size() + tail.size() + 3 ? line_width_ - head.size() - tail.size() - 1 : 3;
  if (job.size() > room) {
    std::string shortened = "...";
    shortened += job.substr(job.size() - (room - 3));
    job = std::move(shortened);
  }
  out_ << "\r\033[K" << head << job << tail << std::flush;
}

}  // namespace hb
