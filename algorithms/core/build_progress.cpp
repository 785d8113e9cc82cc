#include "algorithms/core/build_progress.h"

#include <atomic>
#include <string>

namespace hb {

namespace {
thread_local BuildProgressListener* current_listener = nullptr;
std::atomic<void (*)()> stop_check{nullptr};
}  // namespace

void check_build_stop() {
  if (void (*check)() = stop_check.load(std::memory_order_relaxed)) check();
}

bool build_stop_requested() {
  try {
    check_build_stop();
    return false;
  } catch (...) {
    return true;
  }
}

void set_build_stop_check(void (*check)()) { stop_check.store(check); }

void announce_build_stage(std::string_view stage) {
  if (current_listener != nullptr) current_listener->build_stage(stage);
}

void announce_build_progress(std::size_t done, std::size_t total) {
  if (current_listener != nullptr) current_listener->build_progress(done, total);
}

void announce_cached_build(std::string_view what, bool cache_hit) {
  if (current_listener == nullptr) return;
  std::string stage(what);
  stage += cache_hit ? ": cache hit" : ": building";
  current_listener->build_stage(stage);
}

ScopedBuildProgressListener::ScopedBuildProgressListener(BuildProgressListener* listener)
    : previous_(current_listener) {
  current_listener = listener;
}

ScopedBuildProgressListener::~ScopedBuildProgressListener() { current_listener = previous_; }

}  // namespace hb
