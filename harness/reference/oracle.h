// Ground-truth oracles on real meshes: what a query wants is stated in a
// Request, what it gets back in a Result (only what was asked is computed).
// Two backends share this interface: Embree (fast, float BVH with distances
// recomputed in double) and CGAL (exact predicates, AABB-tree distances,
// exact intersection volume). Their heavy headers stay in oracle_embree.cpp
// and oracle_cgal.cpp. All coordinates are metres, world frame.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hapticbench/pose.h"
#include "hapticbench/scene.h"
#include "hapticbench/triangle_mesh.h"

namespace hb {

/// Per-point queries against the whole scene (union of its objects).
struct PointQueryRequest {
  std::span<const Vec3> points;  ///< m, world frame
  bool want_inside = true;       ///< inside any closed scene object?
  bool want_closest = false;     ///< closest point on the scene surface, distance, normal
  /// m: a point with no scene triangle within this distance is answered
  /// with this distance (a lower bound; closest NaN, normal 0, object −1)
  /// instead of being searched farther. A backend may answer it exactly.
  double max_distance = std::numeric_limits<double>::infinity();
};

struct PointQueryResult {
  std::vector<uint8_t> inside;   ///< 1 inside a closed scene object (want_inside)
  std::vector<double> distance;  ///< m, unsigned distance to the nearest scene triangle
  std::vector<Vec3> closest;     ///< m, the nearest point on the scene surface
  std::vector<Vec3> normal;      ///< unit outward normal of the nearest triangle
  std::vector<int32_t> object;   ///< index of the scene object the nearest triangle is in

  /// Sizes the closest-point vectors for n points (each backend's first step).
  void resize_closest(std::size_t n) {
    distance.resize(n);
    closest.resize(n);
    normal.resize(n);
    object.resize(n);
  }
};

/// Penetration of a set of points (e.g. tool surface samples at a pose).
struct PenetrationResult {
  int64_t points = 0;      ///< points tested
  int64_t inside = 0;      ///< points inside the scene
  double max_depth_m = 0;  ///< largest distance to the surface of an inside point
  double rms_depth_m = 0;  ///< RMS over inside points (0 when none)
};

/// A scene triangle near a point: its closest point and the distance.
struct NearTriangle {
  Vec3 closest = Vec3::Zero();  ///< m, world frame: the triangle's point nearest the query
  double distance = 0;          ///< m, from the query point to `closest`
  int32_t object = -1;          ///< index of the triangle's object in the oracle's scene
  std::array<Vec3, 3> corners = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};  ///< m, world frame
};

class Oracle {
 public:
  virtual ~Oracle() = default;
  /// "embree" or "cgal".
  virtual std::string_view name() const = 0;
  /// Answers what the request asks, resizing only the wanted result vectors.
  virtual void query_points(const PointQueryRequest& request, PointQueryResult& result) const = 0;
  /// Exact volume (m³) of the intersection of a closed tool mesh, given in
  /// world coordinates, with the scene; nullopt when the backend cannot
  /// compute it (Embree) or the scene has distance-only objects.
  virtual std::optional<double> intersection_volume(const TriangleMesh& tool_in_world) const = 0;
  /// Names of scene objects used for distances only (marked distance_only).
  virtual const std::vector<std::string>& distance_only_objects() const = 0;
  /// World-frame bounds of the scene.
  virtual Eigen::AlignedBox3d bounds() const = 0;

  /// Every scene triangle within `radius_m` of `point` (each once, in no
  /// particular order), appended to `out` after clearing it; the distances
  /// are computed in double. False when the backend does not answer this
  /// query.
  virtual bool triangles_within(const Vec3& point, double radius_m,
                                std::vector<NearTriangle>& out) const {
    (void)point, (void)radius_m;
    out.clear();
    return false;
  }

  /// Penetration of the points: inside test for every point, then the
  /// distance to the surface of each point found inside.
  PenetrationResult penetration(std::span<const Vec3> points) const;
};

/// Penetration of `points` given which of them are inside (from an earlier
/// inside query): the distance to the surface of each inside point.
PenetrationResult penetration_of_inside_points(const Oracle& oracle, std::span<const Vec3> points,
                                               const std::vector<uint8_t>& inside);

/// Builds the Embree oracle for the scene (each object's mesh placed by its
/// pose). An object whose mesh is open or self-intersecting is refused with
/// InputError(object name, "/scene/<i>", why) unless the object is marked
/// distance_only, in which case it serves distances only and is listed by
/// distance_only_objects().
std::unique_ptr<Oracle> make_embree_oracle(const std::vector<SceneObject>& scene);

/// Builds the CGAL oracle; same rules.
std::unique_ptr<Oracle> make_cgal_oracle(const std::vector<SceneObject>& scene);

/// Why a scene object cannot be used for inside/outside, or nullopt: open
/// boundary, non-manifold, or self-intersecting (CGAL's exact test). Shared
/// by both backends so they refuse the same objects.
std::optional<std::string> inside_outside_defect(const TriangleMesh& mesh);

/// Whether the closed triangles a and b (m, one frame) share a point, decided
/// with exact predicates on the given doubles (CGAL): crossing, touching at
/// a vertex or an edge, or overlapping in one plane all count.
bool triangles_intersect(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b);

/// One oracle backend the harness can evaluate. A new backend is one row in
/// oracle_backends() plus its make function; the ticks CSV, summary.json,
/// the metrics and the scenario's `reference.oracle` choices follow the list.
struct OracleBackendEntry {
  std::string_view name;  ///< as a scenario names it and as summary.json keys it
  std::unique_ptr<Oracle> (*make)(const std::vector<SceneObject>& scene);
  /// Evaluated only on ticks k with k % exact_every == 0 (an expensive,
  /// exact backend) rather than on every tick.
  bool exact_ticks_only;
  /// Computes the exact tool–scene intersection volume on its ticks.
  bool intersection_volume;
};

/// The backends in evaluation order, every-tick ones first. Of those a
/// scenario asks for, the first is the primary: it gives the penetration
/// on ticks it evaluates and checks the reported contacts; the others are
/// cross-checked against it sample by sample.
std::span<const OracleBackendEntry> oracle_backends();

/// Index of the backend named `name` in oracle_backends(), or nullopt.
std::optional<std::size_t> oracle_backend_index(std::string_view name);

}  // namespace hb
