// The mesh force reference along a scenario's trajectory: computed once per
// scenario (it does not depend on the algorithm), on every force_every-th
// tick, before the algorithms' evaluation passes read it in order; cached on
// disk by content (scene, tool, trajectory, coupling, settings), so that a
// rerun costs nothing. Its ticks are kept in a SpillBuffer and read and
// written in parts: memory does not grow with the run's length.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "hapticbench/pose.h"
#include "harness/metrics/spill_buffer.h"
#include "harness/output/run_report.h"
#include "harness/progress/progress_display.h"
#include "harness/reference/coupling_damper.h"
#include "harness/reference/rigid_proxy_reference.h"
#include "harness/scenario/scenario.h"

namespace hb {

/// The reference at one tick it was evaluated on.
struct ForceReferenceTick {
  bool evaluated = false;  ///< a sampled tick with a proxy to follow
  bool in_contact = false;
  Wrench display;  ///< what the ideal proxy displays (N, N·m about the tool origin)
};

/// One tick as stored (trivially copyable, the cache file's record).
struct ForceReferenceRecord {
  uint8_t evaluated = 0, in_contact = 0;
  double display[6] = {};  ///< force (N) then torque (N·m), world frame
};

struct ForceReferenceTrack {
  SpillBuffer<ForceReferenceRecord> ticks;  ///< one per tick of the trajectory
  ForceReferenceDescription description;

  /// Reads the ticks in increasing order (each evaluation pass has one).
  class Reader {
   public:
    explicit Reader(const ForceReferenceTrack& track) : records_(track.ticks) {}
    /// The reference at `tick`, which is not before the last one asked
    /// for. std::logic_error otherwise, or past the end.
    const ForceReferenceTick& at(int64_t tick);

   private:
    SpillBuffer<ForceReferenceRecord>::Reader records_;
    int64_t next_ = 0;  ///< the tick the next record read is
    ForceReferenceTick current_;
  };
};

/// Whether the scenario gets the mesh force reference: reference.force is
/// "auto", the closed forms do not cover it, and the scene is not empty.
bool wants_mesh_force_reference(const Scenario& scenario, bool analytic_covered);

/// Follows the trajectory (with progress, phase "force reference").
/// Throws InputError for scene objects the oracles refuse.
ForceReferenceTrack compute_force_reference(const Scenario& scenario, ProgressDisplay* progress);

/// The rigid-proxy reference following device samples tick by tick, in
/// order: the ideal rendering (its coupling damper included) on the ticks
/// it evaluates, and the description's counts and time. compute_force_
/// reference follows the trace with it; in closed loop each run's
/// evaluation pass follows that run's own device with one (the device stops
/// short of the intent, by the hand's spring: a reference along the intent
/// charged 18 N RMS of the hand to the algorithm).
class ForceReferenceFollower {
 public:
  /// `path`: what it follows, for the description ("the trace", "this
  /// run's device path (closed loop)"). Throws InputError for scene objects
  /// the oracles refuse.
  ForceReferenceFollower(const Scenario& scenario, std::string path);
  /// The reference at the sample's tick, or nullopt on a tick it does not
  /// evaluate (off the force_every grid, a non-finite pose, before it could
  /// start outside the scene).
  std::optional<IdealRendering> follow(const DeviceSample& sample);
  const ForceReferenceDescription& description() const { return description_; }

 private:
  RigidProxyReference reference_;
  IdealCouplingDamper damper_;
  ForceReferenceDescription description_;
};

}  // namespace hb
