#include "algorithms/voxmap_pointshell/pointshell_contacts.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

namespace hb {

namespace {

constexpr std::size_t kAveragingThreshold = 10;
// A node is skipped only when the scene is this much (m) beyond its
// sphere: room for the rounding of the posed centre.
constexpr double kRoundingMargin = 1e-9;

// Appends the nodes of the subtree over order[begin, end) depth-first.
void build_subtree(const std::vector<Vec3>& points, std::vector<int32_t>& order, int32_t begin,
                   int32_t end, int leaf_points, int32_t parent,
                   std::vector<PointShell::Node>& nodes) {
  Eigen::AlignedBox3d box;
  for (int32_t k = begin; k < end; ++k) box.extend(points[order[k]]);
  const std::size_t index = nodes.size();
  PointShell::Node node;
  node.centre = box.center();
  for (int32_t k = begin; k < end; ++k)
    node.radius = std::max(node.radius, (points[order[k]] - node.centre).norm());
  node.first = begin;
  node.count = end - begin;
  node.parent = parent;
  node.lever = node.centre.norm();
  if (parent >= 0) node.parent_distance = (node.centre - nodes[parent].centre).norm();
  nodes.push_back(node);
  if (end - begin > leaf_points) {
    int axis = 0;
    box.sizes().maxCoeff(&axis);
    const int32_t middle = begin + (end - begin) / 2;
    std::nth_element(order.begin() + begin, order.begin() + middle, order.begin() + end,
                     [&](int32_t a, int32_t b) { return points[a][axis] < points[b][axis]; });
    const auto self = static_cast<int32_t>(index);
    build_subtree(points, order, begin, middle, leaf_points, self, nodes);
    build_subtree(points, order, middle, end, leaf_points, self, nodes);
  }
  nodes[index].skip = static_cast<int32_t>(nodes.size());
}

// What a descent counts.
struct DescentWork {
  int64_t tests = 0;
  int64_t looked_up = 0;
};

// Looks up point i at the pose (x, rotation) and records what it meets.
// Returns the point's slack: for a free point (with_slack), how far (m) it
// may move and stay free (0 when next to a non-free voxel); −1 otherwise.
inline double look_up_point(const PointShell& shell, const VoxelLookup& voxmap,
                            const PointShellGains& gains, const Vec3& x, const Mat3& rotation,
                            int32_t i, PointShellHits& hits, bool with_slack) {
  const Vec3 point = x + rotation * shell.points[i];
  const VoxelLookup::Cell cell = voxmap.cell_at(point);
  const VoxelState voxel_state = voxmap.state(cell);
  if (voxel_state == VoxelState::kFree)
    return with_slack ? std::max(voxmap.clearance(cell, point) - kRoundingMargin, 0.0) : 0.0;
  const bool braking = voxel_state == VoxelState::kProximity;
  if (braking) {
    hits.braking.push_back(i);
    // The signed-distance force acts wherever φ < 0, whatever the voxel's
    // state (from φ at its centre): a point that crossed the surface inside
    // a proximity voxel would otherwise feel nothing until the next voxel,
    // and its force would switch on there at once.
    if (!gains.signed_distance) return -1;
  } else if (!gains.signed_distance && voxel_state == VoxelState::kSurface) {
    const Vec3 normal = rotation * shell.normals[i];
    const Vec3 centre = voxmap.centre_of(voxmap.voxel_of(cell));
    const double depth = normal.dot(centre - point);
    if (depth > 0) hits.contacts.push_back({i, depth, centre, false});
    return -1;
  }
  if (voxmap.has_distances()) {
    FieldSample field;
    field.phi = voxmap.interpolated_distance(point, field.gradient);
    if (field.phi < 0) hits.contacts.push_back({i, -field.phi, field.gradient, true});
    // Kept for report_contacts, which reports an acting braking point with φ.
    if (braking) hits.braking_fields.push_back(field);
  }
  return -1;
}

// The points' slack kept between searches, as a reserve against the
// motion bound accumulated since the front was first searched (so that a
// point the stride leaves out for a while still ages): a point looked up
// free with slack σ when the accumulated bound was S + T |r| is stored as
// σ + S + T |r|, and may be skipped while that exceeds the bound now.
struct PointReserves {
  double* reserve = nullptr;  ///< per point of the shell; −1: look it up
  double shift = 0;           ///< m, Σ |Δx| over the searches
  double turn = 0;            ///< Σ ‖ΔR‖_F over the searches
  double travelled(double lever) const { return shift + turn * lever; }
  void keep(int32_t i, double slack, double lever) {
    reserve[i] = slack > 0 ? slack + travelled(lever) : -1;
  }
  /// Looked up free, with room left (−1 marks a point that was not free:
  /// no bound to work out).
  bool still_free(int32_t i, double lever) const {
    return reserve[i] > 0 && reserve[i] - travelled(lever) > 0;
  }
};

// The first index from `first` on that the stride samples (a multiple of it).
inline int32_t first_sampled(int32_t first, int32_t stride) {
  return stride == 1 ? first : (first + stride - 1) / stride * stride;
}

// Searches nodes [begin, end) (whole subtrees) at the pose (x, rotation):
// a node whose sphere is clear is skipped with its subtree, a leaf that is
// not has its points looked up, those whose index is a multiple of
// `stride`. With `front`, appends where it stopped; with `reserves`, keeps
// each looked-up point's slack there.
void descend(const PointShell& shell, const VoxelLookup& voxmap, const PointShellGains& gains,
             const Vec3& x, const Mat3& rotation, int32_t begin, int32_t end, int32_t stride,
             PointShellHits& hits, DescentWork& work, std::vector<PointShellFront::Entry>* front,
             PointReserves* reserves) {
  for (int32_t k = begin; k < end;) {
    const PointShell::Node& node = shell.nodes[k];
    ++work.tests;
    const double slack =
        voxmap.clearance(x + rotation * node.centre) - node.radius - kRoundingMargin;
    if (slack > 0) {
      if (front) front->push_back({k, slack});
      k = node.skip;
      continue;
    }
    if (node.skip != k + 1) {  // not a leaf: descend
      ++k;
      continue;
    }
    for (int32_t i = first_sampled(node.first, stride); i < node.first + node.count; i += stride) {
      ++work.looked_up;
      const double slack =
          look_up_point(shell, voxmap, gains, x, rotation, i, hits, reserves != nullptr);
      if (reserves) reserves->keep(i, slack, shell.levers[i]);
    }
    if (front) front->push_back({k, -1});
    k = node.skip;
  }
}

// Sums of outer products a bᵀ over points, for a and b stacked from 3-vectors
// (rows/3 × cols/3 blocks of 3×3 sums), added a column at a time so that each
// column is a few packet operations (Eigen's 3×3 column update was a call
// per column). Element (r, c) gets b(c) a(r), as a 3×3 sum of its own would.
template <int Rows, int Cols>
struct OuterSums {
  Eigen::Matrix<double, Rows, Cols> sum = Eigen::Matrix<double, Rows, Cols>::Zero();
  [[gnu::always_inline]] void add(const Eigen::Matrix<double, Rows, 1>& a,
                                  const Eigen::Matrix<double, Cols, 1>& b) {
    for (int c = 0; c < Cols; ++c) sum.col(c) += b[c] * a;
  }
  /// The 3×3 sum of block row i, block column j.
  Mat3 block(int i, int j) const { return sum.template block<3, 3>(3 * i, 3 * j); }
};

// 3-vectors one above the other.
[[gnu::always_inline]] inline Eigen::Matrix<double, 6, 1> stacked(const Vec3& a, const Vec3& b) {
  Eigen::Matrix<double, 6, 1> v;
  v.head<3>() = a;
  v.tail<3>() = b;
  return v;
}
[[gnu::always_inline]] inline Eigen::Matrix<double, 9, 1> stacked(const Vec3& a, const Vec3& b,
                                                                  const Vec3& c) {
  Eigen::Matrix<double, 9, 1> v;
  v.segment<3>(0) = a;
  v.segment<3>(3) = b;
  v.segment<3>(6) = c;
  return v;
}

}  // namespace

double braking_speed(const Vec3& normal, const Vec3& lever, const RigidBodyState& state) {
  return normal.dot(state.v + state.w.cross(lever));
}

PointShell make_pointshell(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                           const Vec3& centre_of_mass, int leaf_points) {
  PointShell shell;
  const auto n = static_cast<int32_t>(points.size());
  std::vector<Vec3> about_centre(points.size());
  for (int32_t i = 0; i < n; ++i) about_centre[i] = points[i] - centre_of_mass;
  std::vector<int32_t> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  if (n > 0) build_subtree(about_centre, order, 0, n, std::max(leaf_points, 1), -1, shell.nodes);
  shell.points.reserve(points.size());
  shell.normals.reserve(points.size());
  shell.moments.reserve(points.size());
  for (const int32_t i : order) {
    shell.points.push_back(about_centre[i]);
    shell.normals.push_back(normals[i]);
    shell.moments.push_back(about_centre[i].cross(normals[i]));
    shell.levers.push_back(about_centre[i].norm());
    shell.radius = std::max(shell.radius, shell.levers.back());
  }
  for (std::size_t k = 0; k < shell.nodes.size(); ++k)
    if (shell.nodes[k].skip == static_cast<int32_t>(k) + 1) ++shell.leaves;
  return shell;
}

Vec3 contact_direction(const PointShell& shell, const PointHit& hit, const Mat3& rotation) {
  return hit.field ? hit.reference : Vec3(rotation * shell.normals[hit.point]);
}

double averaging_divisor(double n) {
  return n >= static_cast<double>(kAveragingThreshold) ? n / kAveragingThreshold : 1.0;
}

int32_t point_budget_stride(int64_t candidates, int64_t budget, int32_t current) {
  if (budget <= 0) return 1;
  const int64_t needed = std::max<int64_t>(1, (candidates + budget - 1) / budget);
  int64_t stride = std::max<int64_t>(current, 1);
  if (needed > stride)
    return static_cast<int32_t>(std::min<int64_t>(needed, std::numeric_limits<int32_t>::max()));
  // Lowered only with a fifth of the lower stride's budget to spare.
  while (stride > 1 && candidates * 5 <= budget * (stride - 1) * 4) --stride;
  return static_cast<int32_t>(stride);
}

double signed_distance_divisor(std::size_t shell_points) {
  return std::max(1.0, static_cast<double>(shell_points) / kSignedDistanceShellShare);
}

void find_pointshell_hits(const PointShell& shell, const VoxelLookup& voxmap,
                          const PointShellGains& gains, const RigidBodyState& state,
                          PointShellHits& hits, WorkCounters& work) {
  hits.clear();
  work.names = &PointShellWork::kNames;
  DescentWork counts;
  descend(shell, voxmap, gains, state.x, state.q.toRotationMatrix(), 0,
          static_cast<int32_t>(shell.nodes.size()), 1, hits, counts, nullptr, nullptr);
  work.add(PointShellWork::kSphereTests, counts.tests);
  work.add(PointShellWork::kPointsLookedUp, counts.looked_up);
  work.add(PointShellWork::kBrakingPoints, static_cast<int64_t>(hits.braking.size()));
}

namespace {

// Appends a node to the new front with its slack (m; −1: looked up), and
// while the scene is beyond the parent's sphere too (the bound drops at most
// by the distance between the centres) coarsens the front to the parent.
// Returns skip_until raised past the subtrees lifted.
[[gnu::always_inline]] inline int32_t push_and_lift(const PointShell& shell,
                                                    std::vector<PointShellFront::Entry>& next,
                                                    int32_t node, double slack,
                                                    int32_t skip_until) {
  next.push_back({node, slack > 0 ? slack : -1});
  if (!(slack > 0)) return skip_until;
  while (next.back().slack > 0) {
    const PointShell::Node& child = shell.nodes[next.back().node];
    if (child.parent < 0) break;
    const PointShell::Node& parent = shell.nodes[child.parent];
    const double parent_slack =
        next.back().slack + child.radius - child.parent_distance - parent.radius;
    if (!(parent_slack > 0)) break;
    while (!next.empty() && next.back().node >= child.parent) next.pop_back();
    next.push_back({child.parent, parent_slack});
    skip_until = std::max(skip_until, parent.skip);
  }
  return skip_until;
}

// Looks up a leaf of the last front again at the pose (x, rotation),
// skipping the points that were free with room to spare while they have it
// (and those the stride leaves out, which keep the leaf in the front).
// Returns whether every point looked up is clear.
[[gnu::always_inline]] inline bool revisit_leaf_points(
    const PointShell& shell, const VoxelLookup& voxmap, const PointShellGains& gains, const Vec3& x,
    const Mat3& rotation, const PointShell::Node& node, int32_t stride, PointShellHits& hits,
    DescentWork& counts, PointReserves& reserves) {
  bool all_clear = stride == 1;
  for (int32_t i = first_sampled(node.first, stride); i < node.first + node.count; i += stride) {
    if (reserves.still_free(i, shell.levers[i])) continue;
    ++counts.looked_up;
    const double slack = look_up_point(shell, voxmap, gains, x, rotation, i, hits, true);
    reserves.keep(i, slack, shell.levers[i]);
    if (!(slack > 0)) all_clear = false;
  }
  return all_clear;
}

// Adds what a search from the front did to the work counters.
void add_front_work(const DescentWork& counts, int32_t stride, int64_t candidates,
                    std::size_t front_entries, std::size_t braking, WorkCounters& work) {
  work.add(PointShellWork::kSphereTests, counts.tests);
  work.add(PointShellWork::kPointsLookedUp, counts.looked_up);
  work.add(PointShellWork::kBudgetSkipped, candidates - counts.looked_up);
  work.add(PointShellWork::kBudgetTicks, stride > 1 ? 1 : 0);
  work.add(PointShellWork::kFrontEntries, static_cast<int64_t>(front_entries));
  work.add(PointShellWork::kBrakingPoints, static_cast<int64_t>(braking));
}

}  // namespace

void find_pointshell_hits_coherent(const PointShell& shell, const VoxelLookup& voxmap,
                                   const PointShellGains& gains, const RigidBodyState& state,
                                   int64_t point_budget, PointShellFront& front,
                                   PointShellHits& hits, WorkCounters& work) {
  hits.clear();
  work.names = &PointShellWork::kNames;
  const int32_t stride = point_budget_stride(front.candidates_, point_budget, front.stride_);
  hits.weight = stride;
  const Mat3 rotation = state.q.toRotationMatrix();
  DescentWork counts;
  std::vector<PointShellFront::Entry>& next = front.next_;
  next.clear();
  front.point_reserve_.resize(shell.points.size(), -1);
  PointReserves reserves{front.point_reserve_.data(), front.travelled_shift_,
                         front.travelled_turn_};
  const bool moved_finite = state.x.allFinite() && rotation.allFinite();
  if (!front.valid_ || !moved_finite) {
    descend(shell, voxmap, gains, state.x, rotation, 0, static_cast<int32_t>(shell.nodes.size()),
            stride, hits, counts, &next, &reserves);
  } else {
    // How far a point r (tool axes) has moved at most: |Δx| + ‖ΔR‖ |r|.
    const double shift = (state.x - front.x_).norm();
    const double turn = (rotation - front.rotation_).norm();
    reserves.shift += shift;
    reserves.turn += turn;
    int32_t skip_until = 0;  // input entries below this node lie in a subtree lifted
    for (const PointShellFront::Entry& entry : front.entries_) {
      if (entry.node < skip_until) continue;
      const PointShell::Node& node = shell.nodes[entry.node];
      if (entry.slack > 0) {
        const double slack = entry.slack - (shift + turn * node.lever);
        if (slack > 0) {
          skip_until = push_and_lift(shell, next, entry.node, slack, skip_until);
        } else {
          // The scene may have come within the sphere: search the subtree again.
          descend(shell, voxmap, gains, state.x, rotation, entry.node, node.skip, stride, hits,
                  counts, &next, &reserves);
        }
        continue;
      }
      // A leaf looked up last time: its points again.
      const bool all_clear = revisit_leaf_points(shell, voxmap, gains, state.x, rotation, node,
                                                 stride, hits, counts, reserves);
      // Every point clear: the leaf's sphere may be too.
      double leaf_slack = -1;
      if (all_clear) {
        ++counts.tests;
        leaf_slack =
            voxmap.clearance(state.x + rotation * node.centre) - node.radius - kRoundingMargin;
      }
      skip_until = push_and_lift(shell, next, entry.node, leaf_slack, skip_until);
    }
  }
  front.entries_.swap(next);
  front.x_ = state.x;
  front.rotation_ = rotation;
  front.travelled_shift_ = reserves.shift;
  front.travelled_turn_ = reserves.turn;
  front.valid_ = moved_finite;
  // Each point looked up stands for `stride` the search would have looked up.
  const int64_t candidates = counts.looked_up * stride;
  front.candidates_ = candidates;
  front.stride_ = stride;
  add_front_work(counts, stride, candidates, front.entries_.size(), hits.braking.size(), work);
}

void find_pointshell_hits_flat(const PointShell& shell, const VoxelLookup& voxmap,
                               const PointShellGains& gains, const RigidBodyState& state,
                               PointShellHits& hits) {
  hits.clear();
  const Mat3 rotation = state.q.toRotationMatrix();
  for (std::size_t i = 0; i < shell.points.size(); ++i)
    look_up_point(shell, voxmap, gains, state.x, rotation, static_cast<int32_t>(i), hits, false);
}

namespace {

// The pose's rotation both ways: every sum of the wrench is taken in tool
// axes (subscript t: R⁻¹ of the world vector) and turned into the world once
// at the end, so a point costs one rotation instead of three.
struct ToolAxes {
  Mat3 rotation;  ///< R, tool to world
  Mat3 to_tool;   ///< Rᵀ, world to tool
  /// A 3×3 sum in tool axes as it reads in the world: X = R X_t Rᵀ.
  Mat3 to_world(const Mat3& tool) const { return rotation * tool * to_tool; }
};

// The contacts' sums over their points, in tool axes; the points' moments
// m_i = r_i × n_i are the shell's own. Per point, with a = ∂d/∂x and
// c = ∂d/∂δθ, m = s × n:
//   ∂F/∂x = K n aᵀ, ∂τ/∂x = K m aᵀ, and
//   tangent plane (n the point's normal, turning with the body): a = −n,
//     c = n × (C − x), ∂F/∂δθ = K n cᵀ − K d [n]×, ∂τ/∂δθ = K m cᵀ − K d [m]×;
//     the d-terms sum to −K [Σ d n]× and −K [Σ d m]×;
//   field (n = ∇φ, fixed in the world; φ's second derivatives left out):
//     a = −∇φ, c = ∇φ × s, ∂F/∂δθ = K n cᵀ, ∂τ/∂δθ = K m cᵀ + K d [n]×[s]×,
//     with [n]×[s]× = s nᵀ − (n·s) I.
struct ContactSums {
  Vec3 force = Vec3::Zero(), torque = Vec3::Zero();              // Σ d n, Σ d m
  Vec3 plane_force = Vec3::Zero(), plane_torque = Vec3::Zero();  // over tangent-plane hits
  // Σ [n; m] [n; c]ᵀ: blocks n nᵀ, n cᵀ (row 0), m nᵀ, m cᵀ (row 1).
  OuterSums<6, 6> outer;
  OuterSums<3, 3> d_s_n;  // Σ d s nᵀ over field hits
  double d_n_s = 0;       // Σ d n·s over field hits
};

// Sums the contacts at the centre of mass x (m, world); the outer products
// only with Jacobians. Out of line, as sum_braking: on its own the loop
// takes fewer instructions a hit than inlined into pointshell_wrench.
[[gnu::noinline]] void sum_contacts(const PointShell& shell, const PointShellHits& hits,
                                    const Vec3& x, const Mat3& to_tool, bool with_jacobians,
                                    ContactSums& sums) {
  for (const PointHit& hit : hits.contacts) {
    // A flat spot of φ (a point deep in a uniform block) adds nothing to any
    // sum below; it still counts for McNeely's averaging.
    if (hit.field && hit.reference.isZero()) continue;
    const Vec3& r = shell.points[hit.point];
    Vec3 n, m;
    if (hit.field) {
      n = to_tool * hit.reference;
      m = r.cross(n);
    } else {
      n = shell.normals[hit.point];
      m = shell.moments[hit.point];
    }
    sums.force += hit.depth * n;
    sums.torque += hit.depth * m;
    if (!with_jacobians) continue;
    Vec3 c;
    if (!hit.field) {
      c = n.cross(to_tool * (hit.reference - x));
      sums.plane_force += hit.depth * n;
      sums.plane_torque += hit.depth * m;
    } else {
      c = -m;  // ∇φ × s
      sums.d_s_n.add(hit.depth * r, n);
      sums.d_n_s += hit.depth * n.dot(r);
    }
    sums.outer.add(stacked(n, m), stacked(n, c));
  }
}

// Sets the contacts' wrench (N, N·m, world) and, with Jacobians and any
// contact, their stiffness blocks.
void set_contact_wrench(const PointShell& shell, const PointShellHits& hits,
                        const PointShellGains& gains, const ToolAxes& axes, const ContactSums& sums,
                        bool with_jacobians, ForceEvaluation& result) {
  const double k = gains.stiffness;
  const double weight = hits.weight;
  const double contact_scale =
      k * weight /
      (gains.signed_distance
           ? signed_distance_divisor(shell.points.size())
           : averaging_divisor(weight * static_cast<double>(hits.contacts.size())));
  result.wrench.force = contact_scale * (axes.rotation * sums.force);
  result.wrench.torque = contact_scale * (axes.rotation * sums.torque);
  if (!with_jacobians || hits.contacts.empty()) return;
  const Mat3 n_n = sums.outer.block(0, 0), n_c = sums.outer.block(0, 1);
  const Mat3 m_n = sums.outer.block(1, 0), m_c = sums.outer.block(1, 1);
  const Mat3 force_turn = -skew(sums.plane_force);
  const Mat3 torque_turn =
      -skew(sums.plane_torque) + sums.d_s_n.sum - sums.d_n_s * Mat3::Identity();
  result.stiffness.block<3, 3>(0, 0) = -contact_scale * axes.to_world(n_n);
  result.stiffness.block<3, 3>(0, 3) = contact_scale * axes.to_world(n_c + force_turn);
  result.stiffness.block<3, 3>(3, 0) = -contact_scale * axes.to_world(m_n);
  result.stiffness.block<3, 3>(3, 3) = contact_scale * axes.to_world(m_c + torque_turn);
}

// The braking points' sums, in tool axes (s = r_i, n = n_i, p = −m_i, and
// v, ω turned once). Braking: F = b c u with c = n·u < 0, u = v + ω × s.
// With A = ∂F/∂u = b (u nᵀ + c I), p = n × s, q = u × n + s × (ω × n), and
// [a]×[b]× = b aᵀ − (a·b) I, every block is a sum of outer products:
//   ∂F/∂v = A                        = b (u nᵀ + c I)
//   ∂F/∂ω = −A [s]×                  = −b (u pᵀ + c [s]×)
//   ∂F/∂δθ = −b u uᵀ[n]× − A[ω]×[s]× = −b (u qᵀ + c s ωᵀ − c (ω·s) I)
//   ∂τ/∂v = [s]× A                   = b ((s × u) nᵀ + c [s]×)
//   ∂τ/∂ω = −[s]× A [s]×             = −b ((s × u) pᵀ + c (s sᵀ − |s|² I))
//   ∂τ/∂δθ = [s]× ∂F/∂δθ + [F]×[s]×  = −b (s × u) qᵀ + b c (ω·s) [s]×
//                                      + b c (s uᵀ − (u·s) I)
struct BrakingSums {
  Vec3 force = Vec3::Zero(), torque = Vec3::Zero();  // Σ c u, Σ c s × u
  // Σ [u; s×u] [n; p; q]ᵀ: blocks u nᵀ, u pᵀ, u qᵀ (row 0), (s×u) nᵀ, … (row 1).
  OuterSums<6, 9> outer;
  OuterSums<3, 6> c_s_outer;  // Σ c s [s; u]ᵀ: blocks c s sᵀ, c s uᵀ
  Vec3 c_s = Vec3::Zero(), c_ws_s = Vec3::Zero();
  double c_sum = 0, c_s2 = 0, c_ws = 0, c_us = 0;
  std::size_t acting = 0;  // braking points moving towards the scene
};

// Sums the braking points that move towards the scene at v (m/s) and ω
// (rad/s), both in tool axes; the Jacobians' terms only with Jacobians.
[[gnu::noinline]] void sum_braking(const PointShell& shell, const PointShellHits& hits,
                                   const Vec3& v, const Vec3& w, bool with_jacobians,
                                   BrakingSums& sums) {
  for (const int32_t i : hits.braking) {
    const Vec3& s = shell.points[i];
    const Vec3& n = shell.normals[i];
    const Vec3 u = v + w.cross(s);
    const double c = n.dot(u);  // braking_speed(n, s, state), u kept for the sums below
    if (!(c < 0)) continue;
    ++sums.acting;
    const Vec3 s_u = s.cross(u);
    sums.force += c * u;
    sums.torque += c * s_u;
    if (!with_jacobians) continue;
    const Vec3 p = -shell.moments[i];
    const Vec3 q = u.cross(n) + s.cross(w.cross(n));
    sums.outer.add(stacked(u, s_u), stacked(n, p, q));
    sums.c_s_outer.add(c * s, stacked(s, u));
    sums.c_s += c * s;
    sums.c_ws_s += (c * w.dot(s)) * s;
    sums.c_sum += c;
    sums.c_s2 += c * s.squaredNorm();
    sums.c_ws += c * w.dot(s);
    sums.c_us += c * u.dot(s);
  }
}

// Adds the braking wrench (viscosity b, N·s²/m²; each hit standing for
// `weight` points) and, with Jacobians and any acting point, its damping and
// stiffness blocks; ω (rad/s) in tool axes.
void add_braking_wrench(double b, double weight, const ToolAxes& axes, const Vec3& w,
                        const BrakingSums& sums, bool with_jacobians, ForceEvaluation& result) {
  const double brake_scale =
      b * weight / averaging_divisor(weight * static_cast<double>(sums.acting));
  result.wrench.force += brake_scale * (axes.rotation * sums.force);
  result.wrench.torque += brake_scale * (axes.rotation * sums.torque);
  if (!with_jacobians || sums.acting == 0) return;
  const Mat3 identity = Mat3::Identity();
  const Mat3 u_n = sums.outer.block(0, 0), u_p = sums.outer.block(0, 1),
             u_q = sums.outer.block(0, 2);
  const Mat3 su_n = sums.outer.block(1, 0), su_p = sums.outer.block(1, 1),
             su_q = sums.outer.block(1, 2);
  const Mat3 c_ss = sums.c_s_outer.block(0, 0), c_su = sums.c_s_outer.block(0, 1);
  result.damping.block<3, 3>(0, 0) += brake_scale * axes.to_world(u_n + sums.c_sum * identity);
  result.damping.block<3, 3>(0, 3) += -brake_scale * axes.to_world(u_p + skew(sums.c_s));
  result.damping.block<3, 3>(3, 0) += brake_scale * axes.to_world(su_n + skew(sums.c_s));
  result.damping.block<3, 3>(3, 3) +=
      -brake_scale * axes.to_world(su_p + c_ss - sums.c_s2 * identity);
  result.stiffness.block<3, 3>(0, 3) +=
      -brake_scale * axes.to_world(u_q + sums.c_s * w.transpose() - sums.c_ws * identity);
  result.stiffness.block<3, 3>(3, 3) +=
      brake_scale * axes.to_world(-su_q + skew(sums.c_ws_s) + c_su - sums.c_us * identity);
}

}  // namespace

ForceEvaluation pointshell_wrench(const PointShell& shell, const PointShellHits& hits,
                                  const PointShellGains& gains, const RigidBodyState& state,
                                  bool with_jacobians) {
  ForceEvaluation result;
  ToolAxes axes;
  axes.rotation = state.q.toRotationMatrix();
  axes.to_tool = axes.rotation.transpose();
  ContactSums contacts;
  sum_contacts(shell, hits, state.x, axes.to_tool, with_jacobians, contacts);
  set_contact_wrench(shell, hits, gains, axes, contacts, with_jacobians, result);
  const double b = gains.braking_viscosity;
  if (!(b > 0) || hits.braking.empty()) return result;
  const Vec3 v = axes.to_tool * state.v;
  const Vec3 w = axes.to_tool * state.w;
  BrakingSums braking;
  sum_braking(shell, hits, v, w, with_jacobians, braking);
  add_braking_wrench(b, hits.weight, axes, w, braking, with_jacobians, result);
  return result;
}

void report_contacts(const PointShell& shell, const PointShellHits& hits, const VoxelLookup& voxmap,
                     const PointShellGains& gains, const RigidBodyState& state,
                     std::vector<Contact>& contacts) {
  const Mat3 rotation = state.q.toRotationMatrix();
  for (const PointHit& hit : hits.contacts) {
    const Vec3 direction = contact_direction(shell, hit, rotation);
    const double length = direction.norm();
    if (!(length > 0)) continue;  // a flat spot of φ: no direction, no force
    contacts.push_back(
        {state.x + rotation * shell.points[hit.point], direction / length, hit.depth});
  }
  if (!(gains.braking_viscosity > 0) || !voxmap.has_distances()) return;
  const bool fields_read = hits.braking_fields.size() == hits.braking.size();
  // n·u in tool axes (v, ω turned once): a braking point acts when negative.
  const Vec3 v = rotation.transpose() * state.v;
  const Vec3 w = rotation.transpose() * state.w;
  for (std::size_t k = 0; k < hits.braking.size(); ++k) {
    const int32_t i = hits.braking[k];
    const Vec3& r = shell.points[i];
    if (!(shell.normals[i].dot(v + w.cross(r)) < 0)) continue;
    const Vec3 point = state.x + rotation * r;
    FieldSample field;
    if (fields_read) {
      field = hits.braking_fields[k];
    } else {
      field.phi = voxmap.interpolated_distance(point, field.gradient);
    }
    const double length = field.gradient.norm();
    if (!(length > 0)) continue;
    contacts.push_back({point, field.gradient / length, -field.phi});
  }
}

}  // namespace hb
