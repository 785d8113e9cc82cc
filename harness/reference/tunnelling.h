// Tunnelling: the proxy passing through a scene object between ticks, the
// failure of discrete contact detection at speed. Both detectors follow the
// proxy's tool origin (its reference point, world frame, m) tick by tick and
// use one definition: the origin has passed through the scene when, between
// two ticks on which it is outside the scene, the side of the surface it is
// on turns by more than 90° (the directions from the nearest surface point
// to it point away from each other) and the straight path between the two
// positions meets the surface. Going round an edge or a corner turns the
// side a little each tick and is not counted; leaving by the face it
// entered is not counted. Ticks with the origin inside are skipped: the
// proxy sinking in and coming back out the way it came is penetration, not
// tunnelling.
#pragma once

#include <optional>

#include "algorithms/core/pose.h"
#include "harness/reference/oracle.h"

namespace hb {

class TunnellingDetector {
 public:
  virtual ~TunnellingDetector() = default;
  /// Feeds the tool origin's world position at the next tick (m); true when
  /// it has just passed through the scene. Non-finite positions are skipped.
  virtual bool update(const Vec3& origin_world) = 0;
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
  PointQueryResult query_;          ///< scratch
};

/// Whether the straight path from a to b (m, world) meets the oracle's scene
/// surface: sphere tracing with the oracle's unsigned distance, which never
/// steps over a surface; a path that comes within `touch_m` of it meets it.
bool path_meets_surface(const Oracle& oracle, const Vec3& a, const Vec3& b, double touch_m = 1e-9);

}  // namespace hb
