// Continuous collision detection of a rigidly moving tool mesh against the
// static meshes of the scene (lecture notes, "Bounding Volumes" and "CCD
// Summary"). The tool follows a ScrewMotion over the step; both sides carry
// a bounding-sphere tree, and a pair of nodes is opened only when the
// conservative interval test ‖c_tool(t) − c_scene‖² ≤ (r_tool + r_scene)²
// (and two tests of each node's sphere or slab against the other's slab)
// cannot be excluded over the sub-interval of t still in question. Leaf
// pairs of triangles run the screw-motion primitive kernels (tool vertex vs
// scene face, scene vertex vs tool face, edge vs edge), earliest first, each
// searching only times before the best contact found so far (plus the
// contact window). The search is described in mesh_ccd_search.cpp.
//
// Conservative like the kernels: no contact during [0, 1] is missed; the
// reported time of contact is a lower bound (every earlier time is proven
// contact-free). Meshes need not be closed; normals follow the triangles'
// orientation (counter-clockwise seen from outside).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "algorithms/ccd/ccd_settings.h"
#include "algorithms/ccd/screw_motion.h"
#include "hapticbench/pose.h"
#include "hapticbench/scene.h"
#include "hapticbench/triangle_mesh.h"

namespace hb {

/// Which two features of the tool and of one scene object meet.
enum class ContactFeatureKind : uint8_t {
  kToolVertexSceneFace,  ///< tool vertex index, scene triangle index
  kSceneVertexToolFace,  ///< tool triangle index, scene vertex index
  kEdgeEdge,             ///< tool edge index, scene edge index (MeshCcd::tool_edges/scene_edges)
};

/// A pair of features, stable across steps (indices into the meshes given
/// to MeshCcd), so a caller can keep a contact and re-evaluate it later.
struct ContactFeatures {
  ContactFeatureKind kind = ContactFeatureKind::kToolVertexSceneFace;
  int scene_object = 0;   ///< index into the scene given to MeshCcd
  int tool_feature = 0;   ///< tool vertex, triangle or edge index
  int scene_feature = 0;  ///< scene triangle, vertex or edge index
  bool operator==(const ContactFeatures&) const = default;
  /// By kind, object, tool feature, scene feature: the order that breaks
  /// ties between pairs at one distance (ProximityPair).
  auto operator<=>(const ContactFeatures&) const = default;
};

/// A feature pair's geometry at one tool pose.
struct FeatureGeometry {
  /// World, m: the point of the scene feature closest to the tool feature
  /// (for scene vertex vs tool face: the scene vertex).
  Vec3 point = Vec3::Zero();
  /// World, unit, pushes the tool out of the scene: the scene face's normal
  /// (tool vertex vs scene face), minus the tool face's normal (scene vertex
  /// vs tool face), or the edges' common normal e_tool × e_scene oriented
  /// along the sum of the scene edge's adjacent face normals (edge–edge;
  /// along minus the tool edge's sum when the scene's is about zero).
  Vec3 normal = Vec3::Zero();
  /// Signed separation (m) along `normal`: (tool feature point − scene
  /// feature point) · normal, using the closest points of the two features'
  /// planes/lines: the vertex's distance from the face's plane, or the
  /// distance between the edges' lines. ≥ 0 while the tool is outside.
  double gap = 0;
  /// Unsigned distance (m) between the two closed features themselves
  /// (point–triangle or segment–segment); ≥ |gap|.
  double distance = 0;
};

/// One contact at the first time of contact.
struct MeshCcdContact {
  ContactFeatures features;
  double toi = 1;            ///< this pair's time-of-contact lower bound, [0, 1]
  FeatureGeometry geometry;  ///< evaluated at the tool pose at the result's toi
};

struct MeshCcdSettings {
  CcdSettings primitive;  ///< the kernels' tolerance and budget, per primitive pair
  /// Pairs whose time of contact lies within this much (unitless, fraction
  /// of the step) after the first one are reported among the contacts, so a
  /// face landing flat yields all its touching features. In [0, 1].
  double contact_window = 1e-3;
};

/// Throws InputError naming `field_prefix` + ".…" when a setting is out of range.
void validate_mesh_ccd_settings(const MeshCcdSettings& settings, const std::string& field_prefix);

struct MeshCcdResult {
  bool contact = false;  ///< some pair may touch at some t in [0, 1]
  double toi = 1;        ///< lower bound of the first time of contact; 1 when none
  /// Every pair whose own toi is within settings.contact_window of `toi`,
  /// earliest first, geometry at the tool pose at `toi`.
  std::vector<MeshCcdContact> contacts;
  int64_t bv_tests = 0;           ///< interval node-pair tests (sphere, then slabs)
  int64_t primitive_queries = 0;  ///< kernel calls
  /// Sub-interval evaluations of the primitive tests: the kernels' and the
  /// one-interval tests that rule out primitive pairs before any kernel.
  int64_t primitive_evaluations = 0;
  bool budget_exhausted = false;  ///< some kernel answered by its budget fallback
};

/// Closest points of a feature pair at one tool pose.
struct PairClosestPoints {
  Vec3 tool_point = Vec3::Zero();   ///< on the tool feature, world, m
  Vec3 scene_point = Vec3::Zero();  ///< on the scene feature, world, m
  double distance = 0;              ///< between the two closed features, m
};

/// A feature pair and its distance at the pose asked about.
struct ProximityPair {
  ContactFeatures features;
  double distance = 0;  ///< m
};

/// The order proximity lists pairs in: by distance, pairs at one distance
/// by their features (the greater first), so that a list depends on the
/// pose alone, not on which search found the pairs or in what order. The
/// contact solvers' paths depend on the order of pairs at one distance
/// (docs/performance.md): this one keeps the suites' results within the
/// gate's tolerances of the order the searches met them in.
inline bool nearer(const ProximityPair& a, const ProximityPair& b) {
  return a.distance < b.distance || (a.distance == b.distance && b.features < a.features);
}

/// What lies near the tool at one pose (MeshCcd::proximity).
struct ProximityResult {
  /// Feature pairs closer than clearance_m (or at it), nearest first
  /// (nearer()).
  std::vector<ProximityPair> pairs;
  /// Every feature pair not listed is at least this far apart (m).
  double clearance_m = 0;
  int64_t bv_tests = 0;    ///< node pairs tested
  int64_t pair_tests = 0;  ///< feature pairs whose distance was computed
};

namespace ccd_detail {
class ProximitySearch;
}

/// A proximity query worked in slices (MeshCcd::start_proximity), so that
/// a caller can spread one search over several calls: each advance opens a
/// bounded number of node pairs of the trees, nearest first. Once complete,
/// finish() gives what MeshCcd::proximity gives at the same pose, bit for
/// bit. It reads the MeshCcd's trees, which must outlive it.
class ProximityInSlices {
 public:
  /// Deletes the search (mesh_proximity.cpp, where it is defined).
  struct Deleter {
    void operator()(ccd_detail::ProximitySearch* search) const;
  };
  using Search = std::unique_ptr<ccd_detail::ProximitySearch, Deleter>;

  ProximityInSlices() = default;
  explicit ProximityInSlices(Search search) : search_(std::move(search)) {}

  /// Opens at most `node_pairs` (> 0) more node pairs; true once the search
  /// is complete (also for a default-constructed one).
  bool advance(int64_t node_pairs);
  /// Node pairs opened so far.
  int64_t opened() const;
  /// No feature pair is nearer than this (m), from the node pairs opened so
  /// far (the nearest pair found, the least bound of those still open, the
  /// distance asked for): a lower bound of the tool's distance to the scene
  /// that tightens as the search goes on (0 for a default-constructed one).
  double nearest_bound() const;
  /// Completes the search and gives its answer (an empty one, clearance 0,
  /// for a default-constructed one); the search is spent afterwards.
  ProximityResult finish();

 private:
  Search search_;
};

/// Bounding-sphere trees of one tool and a static scene, built once.
class MeshCcd {
 public:
  /// tool_mesh: in the coordinates of the frame whose poses the ScrewMotion
  /// interpolates (for the god-object: a frame at the tool's centre of mass
  /// with the tool frame's axes), m. scene: static objects, each mesh in its
  /// object frame placed by its pose. Throws InputError for an empty tool
  /// or a non-finite coordinate.
  MeshCcd(const TriangleMesh& tool_mesh, std::span<const SceneObject> scene);
  ~MeshCcd();
  MeshCcd(MeshCcd&&) noexcept;
  MeshCcd& operator=(MeshCcd&&) noexcept;

  /// Whether every mesh's trees came from the disk cache (cached_mesh_features).
  bool cache_hit() const;

  /// The first contact of the tool moving along `motion` (its frame's pose
  /// at t = 0 to t = 1) with any scene object. Only times up to
  /// settings.primitive.time_limit are searched. A motion with a number
  /// that is not finite or beyond kMaxCcdCoordinate is answered, like the
  /// kernels answer it, as contact at t = 0 (with no contacts listed).
  MeshCcdResult first_contact(const ScrewMotion& motion, const MeshCcdSettings& settings) const;

  /// The first contact along `motion` among the listed feature pairs only,
  /// each by its primitive kernel (no tree is traversed): the caller knows
  /// that no other pair can meet during the motion, e.g. from a proximity
  /// query whose clearance the motion's point_reach stays below. Contacts,
  /// counters and the time limit as for first_contact; bv_tests is 0.
  /// Indices are checked as by evaluate().
  MeshCcdResult first_contact_among(const ScrewMotion& motion,
                                    std::span<const ContactFeatures> pairs,
                                    const MeshCcdSettings& settings) const;

  /// The pair's geometry with the tool's frame at `tool_pose` (world).
  FeatureGeometry evaluate(const ContactFeatures& features, const Pose& tool_pose) const;
  /// evaluate(pairs[i], tool_pose) for every i, in `geometry` (resized to
  /// the pairs): the same values, the tool's rotation and each vertex's
  /// place worked out once.
  void evaluate(std::span<const ContactFeatures> pairs, const Pose& tool_pose,
                std::vector<FeatureGeometry>& geometry) const;

  /// The feature pairs (tool vertex–scene face, scene vertex–tool face, edge–
  /// edge) at most max_distance apart with the tool's frame at `tool_pose`:
  /// the max_pairs nearest when there are more. clearance_m is max_distance,
  /// or, when pairs were left out, the distance of the nearest one left out;
  /// either way no pair outside the list is closer.
  ProximityResult proximity(const Pose& tool_pose, double max_distance,
                            std::size_t max_pairs) const;
  /// proximity(tool_pose, max_distance, max_pairs), to be worked in slices.
  ProximityInSlices start_proximity(const Pose& tool_pose, double max_distance,
                                    std::size_t max_pairs) const;

  /// Closest points of the pair's two closed features, the tool's frame at
  /// `tool_pose`. Indices are checked as by evaluate().
  PairClosestPoints closest_points(const ContactFeatures& features, const Pose& tool_pose) const;
  /// closest_points(pairs[i], tool_pose) for every i, in `points` (resized
  /// to the pairs): the same values, the tool's rotation worked out once.
  void closest_points(std::span<const ContactFeatures> pairs, const Pose& tool_pose,
                      std::vector<PairClosestPoints>& points) const;

  /// Whether two scene features of one kind lie at one place (separate
  /// objects that touch: feature_places.h).
  bool scene_features_share_places() const;
  /// The place of each pair's scene feature (a triangle, vertex or edge by
  /// its kind; indices checked as by evaluate()), in `places` (resized): −1
  /// for a feature alone at its place. Pairs of one kind and one tool
  /// feature whose scene features share a place have the same closest
  /// points at every tool pose.
  void scene_feature_places(std::span<const ContactFeatures> pairs, std::vector<int>& places) const;

  /// Unique undirected edges (vertex index pairs, smaller first) of the tool
  /// and of scene object `object`, as indexed by ContactFeatures.
  std::span<const std::array<int, 2>> tool_edges() const;
  std::span<const std::array<int, 2>> scene_edges(int object) const;

  /// Radius (m) of the tool about its frame's origin; bytes held by the trees.
  double tool_radius() const;
  /// A sphere (world, m) holding every scene triangle: centre and radius
  /// (radius −1 for a scene without triangles).
  std::pair<Vec3, double> scene_bounding_sphere() const;
  std::size_t memory_bytes() const;

 private:
  struct Data;
  std::unique_ptr<Data> data_;
};

}  // namespace hb
