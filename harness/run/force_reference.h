// The mesh force reference along a scenario's trajectory: computed once per
// scenario (it does not depend on the algorithm), on every force_every-th
// tick, before the algorithms' evaluation passes read it; cached on disk by
// content (scene, tool, trajectory, coupling, settings), so that a rerun
// costs nothing.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "hapticbench/pose.h"
#include "harness/output/run_report.h"
#include "harness/progress/progress_display.h"
#include "harness/scenario/scenario.h"

namespace hb {

/// The reference at one tick it was evaluated on.
struct ForceReferenceTick {
  bool evaluated = false;  ///< a sampled tick with a proxy to follow
  bool in_contact = false;
  Wrench display;  ///< what the ideal proxy displays (N, N·m about the tool origin)
};

struct ForceReferenceTrack {
  std::vector<ForceReferenceTick> ticks;  ///< one per tick of the trajectory
  ForceReferenceDescription description;
};

/// Whether the scenario gets the mesh force reference: reference.force is
/// "auto", the closed forms do not cover it, and the scene is not empty.
bool wants_mesh_force_reference(const Scenario& scenario, bool analytic_covered);

/// Follows the trajectory (with progress, phase "force reference").
/// Throws InputError for scene objects the oracles refuse.
ForceReferenceTrack compute_force_reference(const Scenario& scenario, ProgressDisplay* progress);

}  // namespace hb
