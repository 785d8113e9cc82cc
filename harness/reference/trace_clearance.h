// How far the tool is from the scene along a device trajectory, at the
// device's pose: what `validate` prints so that a scenario's author sees
// whether the trace reaches the scene, and where, before running it.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "hapticbench/pose.h"
#include "hapticbench/scene.h"
#include "hapticbench/triangle_mesh.h"

namespace hb {

/// The tool's clearance at one pose: the least distance (m) from a tool
/// vertex outside the scene to the scene's surface, or minus the depth of
/// the deepest vertex inside a closed scene object (so < 0: it penetrates).
struct ClearanceSample {
  std::size_t pose_index = 0;
  double gap_m = 0;
};

struct TraceClearance {
  ClearanceSample first, closest, last;  ///< closest: the least gap of all poses
  std::size_t poses = 0;                 ///< poses measured
  std::size_t vertices = 0;              ///< tool vertices measured at each pose
};

/// The clearance of `tool` (tool frame, m) placed at each of `poses` (tool
/// frame in the world) from `scene`, by up to `max_vertices` of the tool's
/// vertices (evenly spread over its vertex list) with the Embree oracle.
/// A measure of vertices, not of triangles: a tool face may come closer
/// than its corners. Throws InputError as make_embree_oracle does.
TraceClearance trace_clearance(const std::vector<SceneObject>& scene, const TriangleMesh& tool,
                               std::span<const Pose> poses, std::size_t max_vertices = 2000);

}  // namespace hb
