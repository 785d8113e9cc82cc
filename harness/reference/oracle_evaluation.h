// Per-tick ground truth on real meshes: penetration of the posed tool's
// surface samples by Embree (every tick) and CGAL (every exact_every-th
// tick, with the exact intersection volume when the tool touches the
// scene), their disagreements, on scenes without inside/outside the tool's
// distance to the scene and whether it crosses it, and a check of the
// contacts an algorithm reports. Runs outside the timed window; skipped entirely while the tool's
// bounds are clear of the scene's (broad phase).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hapticbench/renderer.h"
#include "hapticbench/scene.h"
#include "harness/reference/oracle.h"
#include "harness/reference/tool_scene_distance.h"

namespace hb {

struct OracleEvaluationSettings {
  /// Backends to build, by name (oracle_backends()); evaluated in that
  /// list's order whatever order they are given in.
  std::vector<std::string> backends;
  int64_t exact_every = 10;     ///< exact backends on ticks k with k % exact_every == 0
  double sample_spacing_m = 0;  ///< tool surface sample spacing; 0 = automatic
};

/// A reported contact against the oracle at the same pose.
struct ContactCheck {
  double normal_error_deg = 0;  ///< angle between reported and oracle surface normal
  double depth_error_m = 0;     ///< reported depth - oracle depth (signed distance inside)
};

/// One backend's penetration of the tool samples at one tick.
struct BackendPenetration {
  PenetrationResult result;
  int64_t ns = 0;  ///< wall time of the evaluation
};

struct OracleTickEvaluation {
  bool broad_phase_skipped = false;  ///< tool bounds clear of the scene: nothing evaluated
  /// Indexed like oracle_backends(); empty where the backend was not asked
  /// for or not evaluated at this tick.
  std::vector<std::optional<BackendPenetration>> backends;
  std::optional<double> intersection_volume_m3;  ///< when the tool touches the scene
  int64_t volume_ns = 0;
  /// Scenes whose objects are all distance_only (no inside, so no
  /// penetration), while the tool's bounds are within one tool diagonal of
  /// the scene's; null otherwise. The least distance (m) between the posed
  /// tool's triangles and the scene's (tool_scene_distance.h; 0 when they
  /// cross), with the primary backend's triangles.
  std::optional<double> min_distance_m;
  /// When min_distance_m is given: whether a tool triangle and a scene
  /// triangle share a point (exact predicates), i.e. the tool crosses or
  /// exactly touches the scene's surface. Counted like penetration.
  std::optional<bool> crossing;
  int64_t distance_ns = 0;
  int64_t inside_disagreements = 0;  ///< samples a backend classifies unlike the primary
  std::vector<ContactCheck> contact_checks;

  /// The penetration of the first backend evaluated at this tick (the
  /// primary when it was), or null.
  const PenetrationResult* first_penetration() const;
  /// Wall time of all evaluations at this tick.
  int64_t total_ns() const;
};

class OracleEvaluator {
 public:
  /// Builds the requested oracles and samples the tool surface. Throws
  /// InputError for a scene the oracles refuse (open or self-intersecting
  /// mesh not marked distance_only).
  OracleEvaluator(const RenderContext& context, const OracleEvaluationSettings& settings);
  ~OracleEvaluator();

  OracleTickEvaluation evaluate(int64_t tick, const Pose& tool_pose,
                                std::span<const Contact> contacts);

  /// The deepest tool sample at `tool_pose` by the primary backend (m; 0
  /// with the tool's bounds clear of the scene or no sample inside), for a
  /// pose other than the proxy's (closed loop: the device's own). Null when
  /// the oracle does not measure penetration.
  std::optional<double> primary_penetration(const Pose& tool_pose);

  std::size_t sample_count() const { return tool_samples_.size(); }
  double sample_spacing_m() const { return spacing_m_; }
  const std::vector<std::string>& distance_only_objects() const;
  /// Name of the primary backend (the first built).
  std::string_view primary_name() const;
  /// The primary backend itself, for queries of the harness's own (e.g.
  /// tunnelling); null without a backend.
  const Oracle* primary_oracle() const {
    return backends_.empty() ? nullptr : backends_.front().oracle.get();
  }
  /// False when every scene object is distance_only: no inside/outside, so
  /// no penetration; the distance to the scene and whether the tool crosses
  /// it are reported instead (OracleTickEvaluation::min_distance_m,
  /// crossing) and contacts are checked by distance.
  bool measures_penetration() const { return measures_penetration_; }

 private:
  OracleEvaluationSettings settings_;
  const TriangleMesh& tool_mesh_;
  Eigen::AlignedBox3d tool_bounds_;  ///< tool frame
  double spacing_m_ = 0;
  std::vector<Vec3> tool_samples_;   ///< tool frame
  std::vector<Vec3> world_samples_;  ///< scratch, world frame
  struct Backend {
    std::size_t index;  ///< in oracle_backends()
    const OracleBackendEntry* entry;
    std::unique_ptr<Oracle> oracle;
  };
  std::vector<Backend> backends_;    ///< in oracle_backends() order; [0] is the primary
  PointQueryResult primary_inside_;  ///< scratch
  PointQueryResult inside_;          ///< scratch
  Eigen::AlignedBox3d scene_bounds_;
  bool measures_penetration_ = true;
  std::optional<ToolSceneDistanceSearch> distance_search_;  ///< distance-only scenes
};

}  // namespace hb
