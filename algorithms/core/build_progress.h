// Where a long preprocessing step is, for whoever displays progress.
// Builders (voxmaps, pointshells, convex hierarchies, feature trees,
// oracles) announce each stage and, inside long loops, how far they are;
// a display installs a listener for the calling thread. Without a listener
// an announcement is a thread-local load and a branch.
#pragma once

#include <cstddef>
#include <string_view>

namespace hb {

class BuildProgressListener {
 public:
  virtual ~BuildProgressListener() = default;
  /// A stage began, e.g. "convex hierarchy of bunny: building" or
  /// "voxmap: cache hit".
  virtual void build_stage(std::string_view stage) = 0;
  /// `done` of `total` units of the current stage are done.
  virtual void build_progress(std::size_t done, std::size_t total) = 0;
};

/// Tells this thread's listener (if any) that a stage began.
void announce_build_stage(std::string_view stage);
/// Tells this thread's listener (if any) how far the current stage is.
void announce_build_progress(std::size_t done, std::size_t total);

/// "<what>: cache hit" or "<what>: building".
void announce_cached_build(std::string_view what, bool cache_hit);

/// Calls the process's stop check, which throws when the user asked to
/// stop (the command line tool's throws Interrupted after SIGINT or
/// SIGTERM), so that a build of minutes ends within moments of the signal
/// and leaves nothing behind. Builders call it inside their long loops;
/// without a check installed it is a load and a branch.
void check_build_stop();
/// Whether the stop check would throw now: for loops that must not throw,
/// such as a library's worker threads (OpenVDB's interrupter). The caller
/// ends its work and calls check_build_stop() on its own thread.
bool build_stop_requested();
/// Installs the process-wide stop check (null: none).
void set_build_stop_check(void (*check)());

/// Makes `listener` receive this thread's announcements while it lives
/// (null: none); the previous listener is restored on destruction.
class ScopedBuildProgressListener {
 public:
  explicit ScopedBuildProgressListener(BuildProgressListener* listener);
  ~ScopedBuildProgressListener();
  ScopedBuildProgressListener(const ScopedBuildProgressListener&) = delete;
  ScopedBuildProgressListener& operator=(const ScopedBuildProgressListener&) = delete;

 private:
  BuildProgressListener* previous_;
};

}  // namespace hb
