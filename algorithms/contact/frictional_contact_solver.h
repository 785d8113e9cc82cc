// Hard contacts with Coulomb friction on a rigid proxy, solved at velocity
// level (Duriez, Dubois, Kheddar & Andriot 2006; the lecture notes'
// "Constrained Dynamics" cell of the proxy taxonomy). With u = (v, ω) the
// generalised velocity after the step, u_free the velocity without contact
// forces and R the response (the inverse of the step's effective mass, so
// that u = u_free + R Σ J_kᵀ λ_k), each contact k with normal n_k, lever
// r_k (contact point − centre of mass) and tangents t1_k, t2_k has
//   J_k = [ (n, r × n); (t1, r × t1); (t2, r × t2) ]   (3 × 6)
// and impulses λ_k = (λ_n, λ_t1, λ_t2) that satisfy
//   Signorini:  λ_n ≥ 0,  n·u_k − b_k ≥ 0,  λ_n (n·u_k − b_k) = 0
//   Coulomb:    |λ_t| ≤ μ_k λ_n; |λ_t| < μ_k λ_n ⇒ u_t = 0 (stick);
//               sliding ⇒ λ_t = −μ_k λ_n u_t / |u_t| (maximal dissipation)
// where u_k = J_k u and b_k is the bound on the normal velocity (−gap/Δt for
// a speculative contact, > 0 to push a penetration out).
//
// Solved by projected Gauss–Seidel over the contacts with the exact
// circular cone, polished by a semismooth Newton method where the sweeps
// converge slowly (docs/algorithms/constrained-step.md).
//
// With R = K⁻¹ (the coupling's stiffness) and u_free the unconstrained
// displacement, the same problem is the massless god-object's quasi-static
// step with friction: λ are then forces (N) and u a displacement (m, rad).
#pragma once

#include <span>
#include <vector>

#include "hapticbench/pose.h"

namespace hb {

/// One contact of the velocity-level problem.
struct FrictionalContactRow {
  Vec3 normal = Vec3::UnitZ();  ///< world frame, unit length, pushes the tool out of the scene
  Vec3 lever = Vec3::Zero();    ///< contact point minus the centre of mass, world frame (m)
  /// Lower bound b on the normal velocity of the contact point n·(v + ω × r)
  /// (m/s; for a displacement problem, m).
  double bound = 0;
  double friction = 0;  ///< Coulomb μ ≥ 0 (0: frictionless)
};

struct FrictionalContactSettings {
  int max_sweeps = 200;  ///< upper bound on Gauss–Seidel sweeps
  /// Converged when a sweep changed no contact point's velocity by more
  /// than this (m/s, or m for a displacement problem); 0 runs every sweep.
  double tolerance = 1e-9;
  /// Where > 0, the sweeps stop early once every contact carrying load
  /// with friction sticks clearly — its point slides less than this (m/s,
  /// or m) and less than at the sweep before, its tangential impulse
  /// inside kClearStickShare of its disk — and no contact is below its
  /// bound by more than this (the solution is then `stuck`): a caller that
  /// solves the sticking problem exactly (a linear one) need not wait for
  /// the sweeps, which converge slowly where loaded contacts are nearly
  /// dependent.
  double stick_slip = 0;
};

struct FrictionalContactSolution {
  Vec6 velocity = Vec6::Zero();  ///< u = (v, ω) after the contact impulses, world frame
  /// Per contact: (λ_n, λ_t1, λ_t2) along (normal, tangent1, tangent2)
  /// (N·s for a velocity problem, N for a displacement problem).
  std::vector<Vec3> impulses;
  std::vector<Vec3> tangent1;  ///< per contact, world, unit, ⟂ normal; tangent2 = normal × tangent1
  int sweeps = 0;
  double residual = 0;  ///< the last sweep's largest change of a contact point's velocity
  bool converged = false;
  bool stuck = false;  ///< stopped early: every loaded contact sticks clearly (stick_slip)
};

/// A deterministic unit vector perpendicular to the unit vector n.
Vec3 perpendicular_unit(const Vec3& n);

/// The share of its disk a clearly sticking contact's tangential impulse
/// stays inside (FrictionalContactSettings::stick_slip).
inline constexpr double kClearStickShare = 0.9;

/// Contacts carrying load that a polish (see above) takes at most.
inline constexpr int kPolishContacts = 6;

/// Reusable buffers, so a solve in the haptic loop does not allocate once
/// they have grown.
class FrictionalContactSolver {
 public:
  explicit FrictionalContactSolver(const FrictionalContactSettings& settings = {});

  /// response: R, 6 × 6, symmetric positive definite (kg⁻¹, (kg·m²)⁻¹
  /// blocks). free_velocity: u_free. warm: impulses to start from,
  /// one per contact in the same tangent basis (perpendicular_unit), or
  /// empty. The result stays valid until the next solve.
  const FrictionalContactSolution& solve(const Mat6& response, const Vec6& free_velocity,
                                         std::span<const FrictionalContactRow> contacts,
                                         std::span<const Vec3> warm = {});

 private:
  /// The polish (see above): a semismooth Newton method on the conditions
  /// of the contacts carrying load; true when it replaced the iterate
  /// (solution_'s impulses and velocity).
  bool polish(std::span<const FrictionalContactRow> contacts, const Vec6& free_velocity);
  /// The contacts a polish takes (taken_): those carrying load or below
  /// their bound; false when there are none or more than kPolishContacts.
  bool take_polish_contacts(std::span<const FrictionalContactRow> contacts);
  /// Whether every contact a polish left out stays clear of its bound at `velocity`.
  bool left_out_clear(std::span<const FrictionalContactRow> contacts, const Vec6& velocity) const;

  /// What the sweeps carry from one to the next (frictional_contact_solver.cpp).
  struct SweepHistory;
  /// Sizes the buffers and starts the solution at u_free with no impulses.
  void start_solve(std::size_t count, const Vec6& free_velocity);
  /// Contact k's Jacobian J_k, its response R J_kᵀ, block J_k R J_kᵀ and
  /// tangent basis.
  void build_contact(std::size_t k, const FrictionalContactRow& c, const Mat6& response);
  /// Starts contact k from its warm impulse, projected on λ_n ≥ 0 and its disk.
  void warm_start_contact(std::size_t k, const FrictionalContactRow& c, const Vec3& warm);
  /// Contact k's normal impulse that brings n·u to its bound, kept ≥ 0; returns it.
  double relax_normal(std::size_t k, const FrictionalContactRow& c);
  /// Contact k's tangential impulse that stops its slip, kept in the disk
  /// μ `normal` (the disk's minimiser of the contact's 2 × 2 quadratic).
  void relax_tangential(std::size_t k, const FrictionalContactRow& c, double normal);
  /// The largest change of a contact point's velocity (normal and
  /// tangential) for the change `change` of u.
  double largest_point_change(const Vec6& change) const;
  /// Marks the solution stuck (true) when every loaded contact clearly
  /// sticks (FrictionalContactSettings::stick_slip), sliding no more than at
  /// the sweep before.
  bool clearly_stuck(std::span<const FrictionalContactRow> contacts, SweepHistory& history);
  /// Polishes when the sweeps converge slowly: from kFirstPolishSweep on,
  /// when a sweep took off less than kSlowSweep of the last one's change,
  /// then at doubling intervals.
  void polish_if_slow(std::span<const FrictionalContactRow> contacts, const Vec6& free_velocity,
                      double largest_change, SweepHistory& history);
  /// Where every loaded contact with friction sticks clearly and none is
  /// below its bound by more than FrictionalContactSettings::stick_slip, the
  /// largest slip of a loaded contact (m/s, or m); else infinity.
  double clear_stick_slip(std::span<const FrictionalContactRow> contacts) const;

  FrictionalContactSettings settings_;
  std::vector<int> taken_;  ///< the contacts a polish solves
  std::vector<Eigen::Matrix<double, 3, 6>> jacobians_;
  std::vector<Eigen::Matrix<double, 6, 3>> responses_;  ///< R J_kᵀ
  std::vector<Mat3> blocks_;                            ///< J_k R J_kᵀ
  std::vector<Eigen::Matrix2d> tangential_inverses_;    ///< of each block's tangential 2 × 2
  /// Each tangential 2 × 2's eigen-decomposition, made the first time a
  /// sweep puts that contact on its friction circle (the block is fixed
  /// for the solve): values, then vectors as columns.
  std::vector<char> tangential_decomposed_;
  std::vector<Eigen::Vector2d> tangential_eigenvalues_;
  std::vector<Eigen::Matrix2d> tangential_eigenvectors_;
  FrictionalContactSolution solution_;
};

}  // namespace hb
