// The per-tick part of Voxmap PointShell (McNeely, Puterbaugh & Troy 1999):
// the tool's points, posed by the proxy, looked up in the scene voxmap, and
// the wrench they produce.
//
// With R the proxy's rotation, x its centre of mass, a point r_i (tool axes,
// about the centre of mass) with inward unit normal n_i sits at P = x + R r_i
// with normal n = R n_i, lever s = R r_i.
//   Tangent-plane force (voxmap variant): a point in a surface voxel of
//   centre C has depth d = n·(C − P) below the plane through C
//   perpendicular to n; when d > 0 it gets F = K_ff d n (Hooke's law). A
//   point past the surface layer, in an interior voxel (where McNeely's
//   voxmap exerts nothing, so a proxy pushed through the layer stayed
//   trapped), acts as in the signed-distance variant below.
//   Signed-distance variant: d = −φ(P), φ interpolated trilinearly from the
//   voxel-centre signed distances, for points in surface, interior or
//   proximity voxels (wherever φ can be negative); F = (K_ff / D) d ∇φ when
//   d > 0 with D = max(1, shell points / 200) one constant per tool: minus
//   the gradient of the potential (K_ff / 2D) Σ min(φ(P_i), 0)², which is
//   continuous in the pose, so the contact force is conservative (the
//   point's own normal as direction is not: it gave energy away; neither
//   is a state read at the voxel's centre, nor McNeely's averaging, whose
//   divisor jumps as points cross the surface).
//   Torque about the centre of mass: s × F.
//   Averaging (voxmap variant): with N points in contact, the net wrench
//   is the sum when N < 10 and the sum / (N/10) when N ≥ 10.
//   Braking viscosity: a point in a proximity voxel moving with u = v + ω × s
//   gets F = −b u (−n·u) when n·u < 0 (moving towards the scene) and nothing
//   otherwise. The averaging rule applies to the M braking points apart from
//   the N contacts, so neither sum grows with the number of points.
// The Jacobians (force_model.h coordinates) treat C, N and M as fixed, n and
// s as turning with the body.
#pragma once

#include <cstdint>
#include <vector>

#include "algorithms/voxmap_pointshell/voxel_lookup.h"
#include "hapticbench/pose.h"
#include "hapticbench/proxy/force_model.h"
#include "hapticbench/proxy/rigid_body.h"
#include "hapticbench/renderer.h"

namespace hb {

/// The tool's pointshell for the haptic loop, with a bounding-sphere tree
/// over its points (after Barbič & James's nested pointshells): a subtree
/// is skipped when the scene is farther from its sphere's centre than the
/// radius, so the search descends only where the scene is near.
struct PointShell {
  /// A node of the tree. Nodes are stored depth-first: a node's children
  /// follow it, and `skip` is the first node after its subtree; a leaf is a
  /// node whose `skip` is the next node.
  struct Node {
    Vec3 centre = Vec3::Zero();  ///< m, tool axes, about the centre of mass
    double radius = 0;           ///< m, every point of the subtree is within it
    int32_t first = 0;           ///< index of the subtree's first point
    int32_t count = 0;           ///< points of the subtree, consecutive
    int32_t skip = 0;            ///< index of the node after the subtree
    int32_t parent = -1;         ///< index of the parent node, −1 at the root
    double parent_distance = 0;  ///< m, from the centre to the parent's centre
    double lever = 0;            ///< m, |centre|
  };
  std::vector<Vec3> points;    ///< r_i: m, tool axes, about the centre of mass
  std::vector<Vec3> normals;   ///< n_i: unit, tool axes, pointing into the tool
  std::vector<Vec3> moments;   ///< m_i = r_i × n_i: m, tool axes
  std::vector<double> levers;  ///< |r_i|, m
  std::vector<Node> nodes;     ///< depth-first; nodes[0] is the root (when any point)
  double radius = 0;           ///< m, max |r_i|
  int32_t leaves = 0;
};

/// Points per leaf of the tree at most.
inline constexpr int kPointShellLeafPoints = 8;

/// Builds the tree over tool-frame points (m) and inward normals, splitting
/// at the median along the longest side of each node's box down to leaves of
/// at most leaf_points points, and expresses them about centre_of_mass (m,
/// tool frame). The points are reordered so that every subtree's are consecutive.
PointShell make_pointshell(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                           const Vec3& centre_of_mass, int leaf_points = kPointShellLeafPoints);

/// A point of the shell that acts at a pose.
struct PointHit {
  int32_t point = 0;  ///< index into PointShell::points
  double depth = 0;   ///< d (m), > 0
  /// Tangent-plane hit: the surface voxel's centre C (m, world).
  /// Field hit: ∇φ at the point (world, dimensionless).
  Vec3 reference = Vec3::Zero();
  bool field = false;  ///< d = −φ(P) and F = K d ∇φ (else the tangent plane)
};

/// φ and its gradient at a point, as VoxelLookup::interpolated_distance reads them.
struct FieldSample {
  double phi = 0;                ///< m, negative inside the scene
  Vec3 gradient = Vec3::Zero();  ///< ∇φ, world, dimensionless
};

/// What the points meet at one pose.
struct PointShellHits {
  std::vector<PointHit> contacts;  ///< points in contact (d > 0)
  std::vector<int32_t> braking;    ///< points in proximity voxels
  /// φ at each braking point, in the same order, when the search read it
  /// (the signed-distance variant reads φ wherever it may be negative);
  /// empty when it did not (report_contacts then reads it itself).
  std::vector<FieldSample> braking_fields;
  /// How many shell points each hit stands for: the point budget's stride
  /// (every stride-th point looked up), 1 when every point was.
  double weight = 1;
  void clear() {
    contacts.clear();
    braking.clear();
    braking_fields.clear();
    weight = 1;
  }
};

/// The force law's constants.
struct PointShellGains {
  double stiffness = 10000;      ///< K_ff, N/m per point
  double braking_viscosity = 5;  ///< b, N·s²/m²
  bool signed_distance = false;  ///< depth from φ instead of the tangent plane
};

/// What one search leaves for the next at a nearby pose (temporal
/// coherence): the front of the tree where it stopped, depth-first,
/// covering every point once: skipped nodes with their slack (m, how far
/// the scene is beyond the sphere) and the leaves looked up; and the pose.
class PointShellFront {
 public:
  /// A node of the front.
  struct Entry {
    int32_t node = 0;
    double slack = -1;  ///< m, > 0 for a skipped node, < 0 for a leaf looked up
  };

  /// Forgets the front: the next search descends from the root, every
  /// point looked up.
  void clear() {
    valid_ = false;
    candidates_ = 0;
    stride_ = 1;
  }
  /// Nodes in the front (0 when cleared or never searched).
  std::size_t size() const { return valid_ ? entries_.size() : 0; }
  /// The point budget's stride at the last search (1: every point looked up).
  int32_t stride() const { return stride_; }

 private:
  friend void find_pointshell_hits_coherent(const PointShell& shell, const VoxelLookup& voxmap,
                                            const PointShellGains& gains,
                                            const RigidBodyState& state, int64_t point_budget,
                                            PointShellFront& front, PointShellHits& hits,
                                            WorkCounters& work);
  std::vector<Entry> entries_, next_;
  /// Per point of a leaf looked up: how far (m) it may move and stay free
  /// when looked up, plus the motion bound travelled until then (m); −1
  /// when it must be looked up again (pointshell_contacts.cpp).
  std::vector<double> point_reserve_;
  double travelled_shift_ = 0;  ///< m, Σ |Δx| over the searches since the first
  double travelled_turn_ = 0;   ///< Σ ‖ΔR‖_F over the searches since the first
  Vec3 x_ = Vec3::Zero();       ///< m, world: the centre of mass at the last search
  Mat3 rotation_ = Mat3::Identity();
  bool valid_ = false;
  /// Points the last search had to look up, budget aside: those it looked
  /// up times its stride (each stands for that many).
  int64_t candidates_ = 0;
  int32_t stride_ = 1;  ///< the last search's stride
};

/// The point budget's stride for a search after one that had `candidates`
/// points to look up, at `current` stride: the least k ≥ 1 with
/// candidates ≤ k · budget, except that the stride is lowered only once
/// candidates ≤ 0.8 (k − 1) budget, so that a count hovering at a boundary
/// does not switch the sample back and forth. 1 when budget ≤ 0 (none).
int32_t point_budget_stride(int64_t candidates, int64_t budget, int32_t current);

/// n·u for a point with normal n (world, pointing into the tool) and lever
/// s (m, world, from the centre of mass) at `state`, u = v + ω × s (m/s): a
/// braking point acts when it is negative (moving towards the scene).
double braking_speed(const Vec3& normal, const Vec3& lever, const RigidBodyState& state);

/// The averaging rule's divisor for n acting points: 1 when n < 10, else
/// n / 10 (n counts the points the hits stand for: hits × weight).
double averaging_divisor(double n);

/// Shell points per unit of the signed-distance variant's divisor: a 2 cm
/// sphere at 2 mm (about 1,250 points) gets 6.3 where a 2.5 mm press
/// touches about 40 points (McNeely's rule: 4); a 4 cm cube's face flat in
/// contact is about three times as stiff as under McNeely's rule.
inline constexpr double kSignedDistanceShellShare = 200;

/// The signed-distance variant's divisor, one constant per tool:
/// max(1, shell points / 200). A divisor that followed the number of points
/// in contact (McNeely's rule) would make the potential jump whenever a
/// point crosses the surface.
double signed_distance_divisor(std::size_t shell_points);

/// The Voxmap PointShell's work counters (WorkCounters slots and names).
struct PointShellWork {
  enum Slot : std::size_t {
    kSphereTests,     ///< bounding spheres of tree nodes
    kPointsLookedUp,  ///< points whose voxel was read
    kFrontEntries,    ///< front entries carried between searches
    kBrakingPoints,   ///< points found in proximity voxels
    kBudgetSkipped,   ///< points to look up that the stride left out (looked up × (stride − 1))
    kBudgetTicks,     ///< searches with a stride above 1
  };
  // Each slot beside its name, so that the two cannot drift apart.
  static constexpr WorkCounters::Names kNames = [] {
    WorkCounters::Names names{};
    names[kSphereTests] = "sphere_tests";
    names[kPointsLookedUp] = "points_looked_up";
    names[kFrontEntries] = "front_entries";
    names[kBrakingPoints] = "braking_points";
    names[kBudgetSkipped] = "points_over_budget";
    names[kBudgetTicks] = "searches_over_budget";
    return names;
  }();
};

/// Finds the points of the shell that act at the proxy pose (x, q of
/// `state`) by descending the tree: a node whose sphere is clear of every
/// non-free voxel (VoxelLookup::clearance at its centre) is skipped with its
/// subtree, a leaf that is not has its points looked up. Hits come in point
/// order. Counts points looked up in work (PointShellWork::kPointsLookedUp)
/// and node spheres tested (kSphereTests).
void find_pointshell_hits(const PointShell& shell, const VoxelLookup& voxmap,
                          const PointShellGains& gains, const RigidBodyState& state,
                          PointShellHits& hits, WorkCounters& work);

/// The same hits as find_pointshell_hits, starting from the front the last
/// search at another pose left (then updated for the next), within a point
/// budget (the time-critical traversal of Barbič & James's pointshells,
/// by stride): when the last search had more points to look up than
/// `point_budget` (> 0), only every k-th point of the shell is looked up
/// (k = point_budget_stride, the same points while k holds, so the
/// sampled force stays a function of the pose) and each hit stands for k
/// points (hits.weight = k: the sums are scaled by k, the averaging rule
/// counts k per hit); the points left out are counted in work
/// (kBudgetSkipped, kBudgetTicks). The stride follows the last search's
/// count, so the first search of a sudden crowd looks up every point.
/// With point_budget ≤ 0 every point is looked up. A skipped
/// node stays skipped while its slack exceeds how far its sphere's centre
/// has moved since it was tested (|Δx| + ‖ΔR‖_F |centre|: a lower bound on
/// the distance to the scene drops at most that much), and is tested again
/// (and its subtree searched) once it does not. A leaf looked up stays in
/// the front: its points are looked up again, but a point that was free
/// with room to spare (its own slack, from the clearance) is skipped while
/// it has moved less; once all its points are clear its sphere is tested
/// again. A skipped node whose slack, less the offset to its parent's
/// centre, exceeds the parent's radius is replaced with the parent's
/// subtree, so the front coarsens again as the tool leaves. Counts front
/// entries visited in work (PointShellWork::kFrontEntries) besides the
/// spheres tested and points looked up.
void find_pointshell_hits_coherent(const PointShell& shell, const VoxelLookup& voxmap,
                                   const PointShellGains& gains, const RigidBodyState& state,
                                   int64_t point_budget, PointShellFront& front,
                                   PointShellHits& hits, WorkCounters& work);

/// The same hits by looking up every point, without the tree (the reference
/// the tree's culling is checked against).
void find_pointshell_hits_flat(const PointShell& shell, const VoxelLookup& voxmap,
                               const PointShellGains& gains, const RigidBodyState& state,
                               PointShellHits& hits);

/// The net wrench of the hits at `state` about the centre of mass (world),
/// with Jacobians when asked; each hit counts hits.weight times.
ForceEvaluation pointshell_wrench(const PointShell& shell, const PointShellHits& hits,
                                  const PointShellGains& gains, const RigidBodyState& state,
                                  bool with_jacobians);

/// The direction (world) of a contact's force: the point's normal n = R n_i
/// (tangent-plane hit, unit) or ∇φ at the point (field hit, about unit).
Vec3 contact_direction(const PointShell& shell, const PointHit& hit, const Mat3& rotation);

/// The hits found at `state` as Contacts, appended to `contacts`: each point in
/// contact at P (world) with the unit direction of its force (pushes the
/// tool out of the scene) and its depth d; and each braking point that acts
/// (b > 0, moving towards the scene) at P with the scene's outward normal
/// ∇φ/|∇φ| and depth −φ(P) < 0 (its distance to the scene, m), so that a
/// tick whose force is braking alone still reports what pushes. Without φ
/// in the voxmap braking points are not reported. φ is the search's
/// (hits.braking_fields) when it read it.
void report_contacts(const PointShell& shell, const PointShellHits& hits, const VoxelLookup& voxmap,
                     const PointShellGains& gains, const RigidBodyState& state,
                     std::vector<Contact>& contacts);

}  // namespace hb
