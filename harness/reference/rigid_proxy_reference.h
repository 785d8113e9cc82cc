// The ideal rendering of any scene of meshes and primitives: the rigid,
// massless proxy of the coupling's definition, followed tick by tick. At
// each update the proxy moves from where the last one left it toward the
// device along a path that never brings the tool into the scene, to the
// pose where the coupling energy
//   E = ½ k_t |x_h − x_p|² + ½ k_r |θ(q_h q_p⁻¹)|²
// is stationary among the poses it may take (a local minimum reached by
// descent: the proxy stays on its side of a thin wall, as a real one must).
//
// Geometry comes from the Embree oracle (oracle.h), never from the
// algorithms' collision code: the tool's surface samples (the points by
// which the oracles measure penetration) and its sharp edges (in pieces,
// by exact segment–triangle distance) keep a clearance ε from every scene
// triangle, and every scene vertex and point along a scene's sharp edge
// keeps ε from every tool triangle.
// Each iteration solves, exactly (least-distance programming by
// Lawson–Hanson NNLS), the quadratic program of the energy over the
// linearised distances to every triangle within a band; a triangle's
// distance is convex, so its linearisation is a lower bound and a step
// that keeps it ≥ ε keeps the whole straight path ≥ ε. A rotation's
// second-order motion is bounded by limiting it per iteration (½|φ|² r ≤
// ε/2), and points outside the band by conservative advancement. The
// update ends when an iteration moves no point more than a nanometre; the
// KKT residual at the end is the share of the coupling's pull (in the
// energy's metric) that the contact normals cannot balance.
//
// Coulomb friction (μ > 0 on a scene object) is quasi-static and
// path dependent: the proxy's pose, frictional, is carried from update to
// update, and each iteration whose rows carry friction solves the
// incremental problem from where the proxy stands, one Coulomb cone per
// row (Signorini; |f_t| ≤ μ f_n; sliding contacts oppose their slip with
// μ f_n, maximal dissipation), by the constrained-contact solver
// (frictional_contact_solver.h) with the coupling's compliance K⁻¹ as its
// response; its answer is finished by the exact program above (the
// nearest step that keeps every row), so the sweeps' tolerance never lets
// a row be violated. The friction's force and moment both act on the
// proxy: the display carries them through the coupling (a sphere dragged
// on a face turns by r μ F_n / k_r, a box twisted on its face resists with
// the pivot torque of its contact rows).
// Units: m, rad, N, N·m; world frame unless a comment says otherwise.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "algorithms/contact/frictional_contact_solver.h"
#include "hapticbench/pose.h"
#include "hapticbench/scene.h"
#include "harness/reference/analytic_reference.h"
#include "harness/reference/oracle.h"

namespace hb {

struct RigidProxySettings {
  /// Spacing (m) of the tool surface samples that must stay outside; 0 =
  /// a fortieth of the tool's bounding diagonal (the oracles' rule).
  double sample_spacing_m = 0;
  /// ε (m): the clearance every sample and scene vertex keeps. It bounds a
  /// rotation's second-order motion; it shifts the force by k_t·ε.
  double clearance_m = 1e-6;
  /// An update has converged when an iteration moves no point more than this (m).
  double step_tolerance_m = 1e-9;
  /// The widest band (m) of triangles an iteration linearises: a longer
  /// motion takes several iterations.
  double band_max_m = 5e-3;
  /// Iterations an update may take before it reports itself unconverged
  /// (far more than any update needs; only a cycling solve meets it).
  int max_iterations = 20000;
  /// Apply the scene objects' Coulomb friction (the model above); false:
  /// frictionless whatever the scene says.
  bool friction = true;
};

/// What one update did.
struct RigidProxyUpdateStats {
  int iterations = 0;
  bool converged = false;
  /// The pose the device asked for could not be approached (the linearised
  /// constraints had no feasible step): the proxy stayed.
  bool infeasible = false;
  /// |S⁻¹(Aᵀμ + K g)| / |S g| at the end, minimised over μ ≥ 0, with A the
  /// contact rows within 10 ε, K = diag(k_t, k_r) and S = K^½: the share of
  /// the coupling's pull (energy metric) the contacts cannot balance; 0
  /// when nothing pulls.
  double kkt_residual = 0;
  int constraints = 0;  ///< rows of the last iteration's program
  int64_t point_queries = 0;
  /// N: Σ μ_i λ_i over the contact rows of the last iteration, the
  /// tangential force their friction can hold (0 frictionless or out of
  /// contact).
  double friction_limit_n = 0;
  /// No loaded frictional contact's tool point slid along its face over the
  /// update (friction_limit_n > 0; rolling and pivoting about a contact do
  /// not slide).
  bool sticking = false;
};

class RigidProxyReference {
 public:
  /// Builds Embree structures for the scene (world) and the tool (tool
  /// frame). Throws InputError for scene objects the oracles refuse.
  RigidProxyReference(const std::vector<SceneObject>& scene, const TriangleMesh& tool_mesh,
                      const CouplingGains& gains, const RigidProxySettings& settings = {});
  ~RigidProxyReference();
  RigidProxyReference(const RigidProxyReference&) = delete;
  RigidProxyReference& operator=(const RigidProxyReference&) = delete;

  /// The ideal rendering for the next device pose (tool frame). Before the
  /// first device pose whose samples are all outside the scene there is no
  /// proxy to follow: nullopt (started inside).
  std::optional<IdealRendering> update(const Pose& device);

  const RigidProxyUpdateStats& last_stats() const { return stats_; }
  std::size_t sample_count() const { return tool_samples_.size(); }
  double sample_spacing_m() const { return spacing_m_; }
  double clearance_m() const { return settings_.clearance_m; }

 private:
  struct Row;  // one linearised distance
  void add_row(const Vec3& out, const Vec3& point, double distance, double mu);
  double friction_of(int32_t object) const;  ///< μ of a scene object (0 for none)
  /// implied_triangles (see the .cpp) for near_ as found for `query`.
  std::vector<char> implied_near_triangles(const Vec3& query) const;
  void collect_rows(double band);
  void collect_edge_rows(double band);
  bool least_distance_step(std::span<const Row> rows, const Vec6& g, Vec6& step) const;
  bool solve_step(const Vec3& gx, const Vec3& gphi, Vec6& step) const;
  bool stick_step(const Vec6& g, std::span<const std::size_t> locked, Vec6& step);
  /// For the contact rows within 10 ε, the share of the coupling's pull
  /// their normal forces λ ≥ 0 cannot balance: RigidProxyUpdateStats::kkt_residual.
  double frictionless_kkt_residual(const Vec3& gx, const Vec3& gphi) const;
  /// solve_step with one Coulomb cone per row (see above); fills friction_.
  bool solve_frictional_step(const Vec3& gx, const Vec3& gphi, Vec6& step);
  void select_friction_rows(const std::vector<char>& taken);
  const FrictionalContactSolution& sweep_friction(const Vec6& g);
  void record_friction(std::span<const Vec3> forces, const Vec6& answer, const Vec6& g);
  bool start_at(const Pose& device);

  RigidProxySettings settings_;
  CouplingGains gains_;
  std::unique_ptr<Oracle> scene_;   ///< world frame
  std::unique_ptr<Oracle> tool_;    ///< tool frame
  std::vector<Vec3> tool_samples_;  ///< tool frame
  /// The tool's sharp edges in pieces no longer than the sample spacing (tool frame).
  std::vector<std::array<Vec3, 2>> tool_edge_pieces_;
  double spacing_m_ = 0;
  double tool_radius_m_ = 0;  ///< largest |sample| and |vertex| about the tool origin
  std::vector<Vec3> scene_vertices_;
  std::vector<double> scene_vertex_friction_;  ///< μ of each scene vertex's object
  std::vector<double> object_friction_;        ///< μ by scene index
  /// Scene vertices by cubic cell of side cell_m_ (key from the cell's indices).
  std::vector<std::pair<int64_t, int32_t>> vertex_cells_;  ///< (cell key, vertex), sorted
  double cell_m_ = 0;
  // Lower bounds on each point's distance: d at its last query, less the
  // motion bound accumulated since (motion_m_ − motion_at_query).
  std::vector<double> sample_distance_, sample_motion_at_;
  std::vector<double> vertex_distance_, vertex_motion_at_;
  std::vector<double> edge_distance_, edge_motion_at_;  ///< per tool edge piece
  /// Points (by index) in the order their bounds run out: a bound
  /// d − (motion − motion_at) falls below a band once motion + band passes
  /// the key d + motion_at (m), so an iteration takes only those (a tool of
  /// 100,000 samples and edge pieces has a few hundred near the scene).
  class DueQueue {
   public:
    void push(double key, std::size_t index);
    /// Removes every index whose key is below `limit`, into `due`
    /// (cleared first) in ascending order.
    void take(double limit, std::vector<std::size_t>& due);

   private:
    std::vector<std::pair<double, std::size_t>> heap_;  ///< least key first
  };
  DueQueue sample_queue_, edge_queue_;
  std::vector<std::size_t> due_;  ///< scratch: the indices taken
  /// Per tool edge piece: the scene triangles found within `reach` of its
  /// middle when it lay at `ends` (world): they hold every triangle within
  /// the band of it while band + half its length + its ends' motion since
  /// stays within `reach`, so the next iterations measure them alone.
  struct NearbyTriangles {
    std::array<Vec3, 2> ends = {Vec3::Zero(), Vec3::Zero()};  ///< m, world
    double reach = -1;                                        ///< m
    std::vector<NearTriangle> triangles;
  };
  std::vector<NearbyTriangles> edge_nearby_;
  /// How far (m) a point with nothing within the band is measured: two
  /// widest bands (a search that goes farther costs more than the point's
  /// next check once it has moved that far: armadillo_on_bunny's reference
  /// took 1.6, 1.2, 2.6 and 3.8 s at one, two, four and eight).
  double far_bound_m() const { return 2 * settings_.band_max_m; }
  double motion_m_ = 0;         ///< Σ over applied steps of |δx| + |φ| r (m)
  double band_hint_m_ = 1e300;  ///< the next iteration's band before clamping (m)

  std::optional<Pose> proxy_;  ///< the proxy (frictional where the scene has friction)
  /// The tool sample that kept the last start from succeeding: asked first
  /// next time, so that a tool held inside the scene fails at once.
  std::size_t blocking_sample_ = 0;
  /// What the last frictional iteration's contact forces were.
  struct FrictionOutcome {
    bool active = false;  ///< the last iteration solved with friction and something pushed
    double limit_n = 0;   ///< Σ μ_k f_n,k (N)
    /// The loaded frictional contacts: point (m, world, scene side) and normal.
    std::vector<std::pair<Vec3, Vec3>> loaded;
    Vec3 normal = Vec3::Zero();  ///< direction of Σ f_n,k n_k (unit, or 0)
    double residual = 0;         ///< as RigidProxyUpdateStats::kkt_residual
  };
  FrictionOutcome friction_;
  /// Its tolerance well under the update's 1 nm step tolerance, so that
  /// the sweeps' error cannot keep an update creeping; it stops at a clear
  /// stick at 0.1 µm of slip, the threshold at which the update holds every
  /// loaded contact with the exact stick step (kStickSlipM in the .cpp).
  FrictionalContactSolver friction_solver_{FrictionalContactSettings{200, 1e-12, 1e-7}};
  std::vector<FrictionalContactRow> friction_rows_;  ///< scratch
  std::vector<Row> stick_rows_;                      ///< scratch: the stick step's rows
  /// The last frictional solve's rows (point, m, world; unit normal) and
  /// forces (N, in the solver's tangent basis), to warm the next.
  std::vector<std::pair<Vec3, Vec3>> warm_rows_;
  std::vector<Vec3> warm_forces_;
  std::vector<Row> rows_;
  std::vector<NearTriangle> near_;  ///< scratch
  RigidProxyUpdateStats stats_;
  /// The last converged update's device pose and rendering, answered again
  /// while the device holds still.
  struct Held {
    Pose device;
    IdealRendering rendering;
  };
  std::optional<Held> last_;
};

}  // namespace hb
