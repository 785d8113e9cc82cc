// Tunnelling: the proxy passing through a scene object between ticks, the
// failure of discrete contact detection at speed. Both detectors follow the
// proxy's tool origin (its reference point, world frame, m) tick by tick and
// use one definition. Between two consecutive ticks with the origin outside
// the scene, the origin has passed through the scene when the straight path
// between its positions goes deeper than kTunnellingDepthM into the solid
// (a cut across a corner counts: the tick skipped the surface). After ticks
// with the origin inside, it has passed through when it comes out on the
// other side: the side of the surface it is on turned by more than 90° (the
// directions from the nearest surface point to it point away from each
// other) and the straight path between the last position outside and this
// one meets the surface; sinking in and coming back out the way it came is
// penetration, not tunnelling. The run follows more than the origin
// (ToolTunnelling): the tool's extreme vertices along 26 directions too,
// each with its own detector, so a tool whose far end passes through a
// wall while its origin goes round it is counted.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "hapticbench/pose.h"
#include "hapticbench/triangle_mesh.h"
#include "harness/reference/oracle.h"

namespace hb {

/// How deep (m) a straight path between two ticks outside must go into the
/// solid to count as passing through it.
inline constexpr double kTunnellingDepthM = 1e-6;

class TunnellingDetector {
 public:
  virtual ~TunnellingDetector() = default;
  /// Feeds the tool origin's world position at the next tick (m); true when
  /// it has just passed through the scene. Non-finite positions are skipped.
  virtual bool update(const Vec3& origin_world) = 0;
};

/// The tool points tunnelling follows (tool frame, m): the origin and the
/// mesh's extreme vertices along 26 directions (towards the faces, edges
/// and corners of a cube), each once.
std::vector<Vec3> tunnelling_points(const TriangleMesh& tool_mesh);

/// Follows several tool points, each with its own detector (from `make`):
/// a tick counts once however many of them passed through at it.
class ToolTunnelling {
 public:
  ToolTunnelling(std::vector<Vec3> points_tool,
                 const std::function<std::unique_ptr<TunnellingDetector>()>& make);
  /// The tool's pose at the next tick; true when some followed point has
  /// just passed through the scene.
  bool update(const Pose& tool_pose);

 private:
  std::vector<Vec3> points_;  ///< m, tool frame
  std::vector<std::unique_ptr<TunnellingDetector>> detectors_;
};

/// Against an oracle's scene (meshes): the inside test and the nearest
/// surface point come from the oracle. Open (distance_only) objects have no
/// inside: crossing their sheet counts as passing through.
class OracleTunnellingDetector final : public TunnellingDetector {
 public:
  explicit OracleTunnellingDetector(const Oracle& oracle) : oracle_(oracle) {}
  bool update(const Vec3& origin_world) override;

 private:
  const Oracle& oracle_;
  std::optional<Vec3> last_point_;  ///< m, world: the last position outside
  Vec3 last_side_ = Vec3::Zero();   ///< unit, world: its side then
  bool last_tick_outside_ = false;  ///< the previous tick's position was outside
  PointQueryResult query_;          ///< scratch
};

/// Whether the straight path from a to b (m, world) goes deeper than
/// `depth_m` into the oracle's solid: sphere tracing to each point where it
/// meets the surface, then an inside test `depth_m` further along (a path
/// that only grazes the surface does not count). Open (distance_only)
/// objects have no inside: meeting their sheet counts.
bool path_enters_solid(const Oracle& oracle, const Vec3& a, const Vec3& b, double depth_m);

/// Whether the straight path from a to b (m, world) meets the oracle's scene
/// surface: sphere tracing with the oracle's unsigned distance, which never
/// steps over a surface; a path that comes within `touch_m` of it meets it.
bool path_meets_surface(const Oracle& oracle, const Vec3& a, const Vec3& b, double touch_m = 1e-9);

}  // namespace hb
