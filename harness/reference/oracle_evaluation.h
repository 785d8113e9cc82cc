// Per-tick ground truth on real meshes: penetration of the posed tool's
// surface samples by Embree (every tick) and CGAL (every exact_every-th
// tick, with the exact intersection volume when the tool touches the
// scene), their disagreements, and a check of the contacts an algorithm
// reports. Runs outside the timed window; skipped entirely while the tool's
// bounds are clear of the scene's (broad phase).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "algorithms/core/scene.h"
#include "algorithms/proxy/renderer.h"
#include "harness/reference/oracle.h"

namespace hb {

struct OracleEvaluationSettings {
  bool use_embree = false;
  bool use_cgal = false;
  int64_t exact_every = 10;     ///< CGAL on ticks k with k % exact_every == 0
  double sample_spacing_m = 0;  ///< tool surface sample spacing; 0 = automatic
};

/// A reported contact against the oracle at the same pose.
struct ContactCheck {
  double normal_error_deg = 0;  ///< angle between reported and oracle surface normal
  double depth_error_m = 0;     ///< reported depth - oracle depth (signed distance inside)
};

struct OracleTickEvaluation {
  bool broad_phase_skipped = false;  ///< tool bounds clear of the scene: nothing evaluated
  std::optional<PenetrationResult> embree;
  int64_t embree_ns = 0;  ///< wall time of the Embree evaluation
  std::optional<PenetrationResult> cgal;
  int64_t cgal_ns = 0;                           ///< wall time of the CGAL penetration evaluation
  std::optional<double> intersection_volume_m3;  ///< CGAL, when the tool touches the scene
  int64_t volume_ns = 0;
  int64_t inside_disagreements = 0;  ///< samples Embree and CGAL classify differently
  std::vector<ContactCheck> contact_checks;
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

  std::size_t sample_count() const { return tool_samples_.size(); }
  double sample_spacing_m() const { return spacing_m_; }
  const std::vector<std::string>& distance_only_objects() const;
  bool has_embree() const { return embree_ != nullptr; }
  bool has_cgal() const { return cgal_ != nullptr; }
  /// False when every scene object is distance_only: no inside/outside, so
  /// no penetration (contacts are still checked by distance).
  bool measures_penetration() const { return measures_penetration_; }

 private:
  OracleEvaluationSettings settings_;
  const TriangleMesh& tool_mesh_;
  Eigen::AlignedBox3d tool_bounds_;  ///< tool frame
  double spacing_m_ = 0;
  std::vector<Vec3> tool_samples_;   ///< tool frame
  std::vector<Vec3> world_samples_;  ///< scratch, world frame
  std::unique_ptr<Oracle> embree_;
  std::unique_ptr<Oracle> cgal_;
  Eigen::AlignedBox3d scene_bounds_;
  bool measures_penetration_ = true;
};

}  // namespace hb
