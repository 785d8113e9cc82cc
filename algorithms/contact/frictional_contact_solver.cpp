#include "algorithms/contact/frictional_contact_solver.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace hb {

Vec3 perpendicular_unit(const Vec3& n) {
  // Cross with the world axis least aligned with n: never near-parallel.
  Vec3 axis = Vec3::UnitX();
  if (std::abs(n.y()) < std::abs(n.x()) && std::abs(n.y()) <= std::abs(n.z()))
    axis = Vec3::UnitY();
  else if (std::abs(n.z()) < std::abs(n.x()) && std::abs(n.z()) < std::abs(n.y()))
    axis = Vec3::UnitZ();
  return n.cross(axis).normalized();
}

namespace {

// The minimiser of ½ λᵀ W λ + gᵀ λ over the disk |λ| ≤ r, W symmetric
// positive definite 2 × 2: the impulse that stops the slip g when it fits
// in the disk, else the one on the circle with W λ + g = −γ λ, γ > 0, so the
// remaining slip W λ + g opposes λ (Coulomb's maximal dissipation). γ is the
// root of 1/|λ(γ)| = 1/r, found by Newton's method from γ = 0 (the function
// is concave and increasing in γ, so the iterates increase monotonically to
// the root, as in Moré and Sorensen's trust-region step).
// `decompose` gives W's eigenvalues and eigenvectors (W = Q diag(e) Qᵀ)
// when the disk's boundary is needed.
template <class Decompose>
Eigen::Vector2d disk_minimiser(const Eigen::Matrix2d& w_inverse, const Eigen::Vector2d& g, double r,
                               Decompose decompose) {
  if (!(r > 0)) return Eigen::Vector2d::Zero();
  const Eigen::Vector2d inside = -w_inverse * g;
  if (inside.norm() <= r) return inside;
  // In W's eigenbasis λ_i(γ) = −h_i / (e_i + γ), h = Qᵀ g.
  const auto [e, q] = decompose();
  const Eigen::Vector2d h = q.transpose() * g;
  double gamma = 0;
  for (int i = 0; i < 60; ++i) {
    const Eigen::Vector2d lambda = -(h.array() / (e.array() + gamma)).matrix();
    const double norm = lambda.norm();
    // d|λ|/dγ = −Σ λ_i² / (e_i + γ) / |λ|
    const double derivative = -(lambda.array().square() / (e.array() + gamma)).sum() / norm;
    // Newton on φ(γ) = 1/|λ| − 1/r, φ' = −d|λ|/dγ / |λ|².
    const double step = -(1 / norm - 1 / r) / (-derivative / (norm * norm));
    gamma += step;
    if (std::abs(step) <= 1e-15 * (gamma + e.maxCoeff())) break;
  }
  const Eigen::Vector2d lambda = -(h.array() / (e.array() + gamma)).matrix();
  return q * lambda * (r / lambda.norm());  // on the circle exactly
}

// The polish's iterations at most; the halvings of a step that does not
// reduce the equations before the damping grows, the damping (a share of
// the mean diagonal of JᵀJ) and how many times it may grow a hundredfold;
// the equations' norm (relative to the impulses) at which a polish is taken.
constexpr int kPolishIterations = 20;
constexpr int kPolishHalvings = 4;
constexpr double kPolishDamping = 1e-9;
constexpr int kPolishDampings = 4;
constexpr double kPolishResidual = 1e-12;
// An iteration that leaves more than this share of the equations' norm
// has stalled.
constexpr double kPolishStall = 0.9;
// The first sweep after which the sweeps may polish.
constexpr int kFirstPolishSweep = 8;
// A sweep that took off less than this share of the last sweep's change
// (change > this × last change) converges slowly: the sweeps polish, then
// at doubling intervals.
constexpr double kSlowSweep = 0.3;
// Polishes that may fail in one solve (the states of a hard problem do not
// settle; the sweeps go on alone).
constexpr int kPolishFailures = 2;

// Dense systems of the polish: 3 unknowns per contact taken, on the stack.
constexpr int kPolishUnknowns = 3 * kPolishContacts;
using PolishMatrix =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kPolishUnknowns, kPolishUnknowns>;
using PolishVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kPolishUnknowns, 1>;
using PolishRows = Eigen::Matrix<double, 2, Eigen::Dynamic, 0, 2, kPolishUnknowns>;

// The polish's dense system on the contacts taken L (3 unknowns each):
// v = J_L u = J_L u_free + G x, G = J_L R J_Lᵀ; per contact the
// augmentation ρ_n = 1 / G_nn and ρ_t = 1 / (mean tangential diagonal),
// which make every equation an impulse. Alart & Curnier's equations, zero
// exactly where Signorini and Coulomb hold: with λ̂_n = λ_n − ρ_n (n·u − b)
// and τ = λ_t − ρ_t u_t,
//   F_n = λ_n − max(0, λ̂_n),   F_t = λ_t − Π_{|·| ≤ μ max(0, λ̂_n)}(τ),
// with a generalised Jacobian from the branch each contact is on.
class PolishSystem {
 public:
  // Builds G, the free rates, ρ and the start x (the iterate's impulses).
  PolishSystem(std::span<const FrictionalContactRow> contacts, std::span<const int> taken,
               std::span<const Eigen::Matrix<double, 3, 6>> jacobians,
               std::span<const Eigen::Matrix<double, 6, 3>> responses,
               std::span<const Vec3> impulses, const Vec6& free_velocity);

  // Levenberg–Marquardt steps on ½ |F|² to a root; false when they stall
  // short of one.
  bool solve();
  // Projects the root as the equations project it (λ_n = max(0, λ̂_n),
  // λ_t = Π(τ)), so that a contact left unpressed carries exactly nothing
  // and a sliding one lies on its circle; returns the velocity it gives.
  Vec6 project(const Vec6& free_velocity);
  // The impulses (λ_n, λ_t1, λ_t2) of the a-th contact taken.
  Vec3 impulse(Eigen::Index a) const { return x_.segment<3>(3 * a); }

 private:
  // F (equations_) and the rates v (rates_) at `at`, and with_jacobian its
  // generalised Jacobian (jacobian_).
  void evaluate(const PolishVector& at, bool with_jacobian);
  // One damped step from x_ that reduces |F| below `residual`, in trial_;
  // false when none does.
  bool find_reducing_step(double residual);

  std::span<const FrictionalContactRow> contacts_;
  std::span<const int> taken_;
  std::span<const Eigen::Matrix<double, 6, 3>> responses_;
  Eigen::Index m_;  // contacts taken
  Eigen::Index n_;  // unknowns, 3 m_
  PolishMatrix g_;
  PolishVector free_rates_, x_, rho_;
  PolishMatrix jacobian_;
  PolishVector equations_, rates_;
  PolishRows slip_change_;
  PolishVector trial_;
  PolishMatrix damped_;
};

PolishSystem::PolishSystem(std::span<const FrictionalContactRow> contacts,
                           std::span<const int> taken,
                           std::span<const Eigen::Matrix<double, 3, 6>> jacobians,
                           std::span<const Eigen::Matrix<double, 6, 3>> responses,
                           std::span<const Vec3> impulses, const Vec6& free_velocity)
    : contacts_(contacts),
      taken_(taken),
      responses_(responses),
      m_(static_cast<Eigen::Index>(taken.size())),
      n_(3 * m_),
      g_(n_, n_),
      free_rates_(n_),
      x_(n_),
      rho_(n_),
      jacobian_(n_, n_),
      equations_(n_),
      rates_(n_),
      slip_change_(2, n_),
      trial_(n_),
      damped_(n_, n_) {
  for (Eigen::Index a = 0; a < m_; ++a) {
    const int k = taken_[a];
    free_rates_.segment<3>(3 * a) = jacobians[k] * free_velocity;
    x_.segment<3>(3 * a) = impulses[k];
    for (Eigen::Index b = 0; b < m_; ++b)
      g_.block<3, 3>(3 * a, 3 * b) = jacobians[k] * responses_[taken_[b]];
    rho_(3 * a) = 1 / g_(3 * a, 3 * a);
    rho_(3 * a + 1) = rho_(3 * a + 2) = 2 / (g_(3 * a + 1, 3 * a + 1) + g_(3 * a + 2, 3 * a + 2));
  }
}

void PolishSystem::evaluate(const PolishVector& at, bool with_jacobian) {
  rates_ = free_rates_ + g_ * at;
  for (Eigen::Index a = 0; a < m_; ++a) {
    const FrictionalContactRow& c = contacts_[taken_[a]];
    const Eigen::Index row = 3 * a;
    const double rho_n = rho_(row), rho_t = rho_(row + 1);
    const double augmented = at(row) - rho_n * (rates_(row) - c.bound);
    const bool pressed = augmented > 0;
    if (pressed) {
      equations_(row) = rho_n * (rates_(row) - c.bound);
      if (with_jacobian) jacobian_.row(row) = rho_n * g_.row(row);
    } else {
      equations_(row) = at(row);
      if (with_jacobian) {
        jacobian_.row(row).setZero();
        jacobian_(row, row) = 1;
      }
    }
    const double radius = c.friction * std::max(0.0, augmented);
    const Eigen::Vector2d tau = at.segment<2>(row + 1) - rho_t * rates_.segment<2>(row + 1);
    const double length = tau.norm();
    if (length <= radius) {  // sticking: u_t = 0
      equations_.segment<2>(row + 1) = rho_t * rates_.segment<2>(row + 1);
      if (with_jacobian) jacobian_.middleRows<2>(row + 1) = rho_t * g_.middleRows<2>(row + 1);
      continue;
    }
    // Sliding: F_t = λ_t − r h, h = τ / |τ|, r = μ max(0, λ̂_n);
    // dF_t = dλ_t − h dr − (r / |τ|) (I − h hᵀ) dτ.
    const Eigen::Vector2d h = tau / length;
    equations_.segment<2>(row + 1) = at.segment<2>(row + 1) - radius * h;
    if (!with_jacobian) continue;
    slip_change_ = -rho_t * g_.middleRows<2>(row + 1);
    slip_change_.block<2, 2>(0, row + 1) += Eigen::Matrix2d::Identity();
    jacobian_.middleRows<2>(row + 1) =
        -(radius / length) * (Eigen::Matrix2d::Identity() - h * h.transpose()) * slip_change_;
    jacobian_.block<2, 2>(row + 1, row + 1) += Eigen::Matrix2d::Identity();
    if (pressed) {
      jacobian_.middleRows<2>(row + 1) += (c.friction * rho_n) * h * g_.row(row);
      jacobian_.block<2, 1>(row + 1, row) -= c.friction * h;
    }
  }
}

// Contacts at one point with nearly parallel normals make the Jacobian
// nearly singular, and a plain Newton step would trade load between them
// without bound: hence the damping.
bool PolishSystem::solve() {
  evaluate(x_, true);
  double residual = equations_.norm();
  for (int iteration = 0; iteration < kPolishIterations; ++iteration) {
    if (residual <= kPolishResidual * x_.norm()) break;
    if (!find_reducing_step(residual)) return false;
    x_ = trial_;
    evaluate(x_, true);
    // Stalled short of a root (the contacts taken or their states are not
    // the solution's): the sweeps go on.
    const double previous = residual;
    residual = equations_.norm();
    if (residual > kPolishStall * previous) return false;
  }
  return residual <= kPolishResidual * x_.norm();
}

// A step is halved until it reduces |F|; when kPolishHalvings halvings do
// not, the damping (from a share of the mean diagonal of JᵀJ) grows a
// hundredfold, at most kPolishDampings times.
bool PolishSystem::find_reducing_step(double residual) {
  const PolishVector gradient = jacobian_.transpose() * equations_;
  const PolishMatrix normal_matrix = jacobian_.transpose() * jacobian_;
  // The mean diagonal of JᵀJ is |J|² / n.
  double damping = kPolishDamping * jacobian_.squaredNorm() / static_cast<double>(n_);
  bool reduced = false;
  for (int attempt = 0; attempt < kPolishDampings && !reduced; ++attempt, damping *= 100) {
    damped_ = normal_matrix;
    damped_.diagonal().array() += damping;
    const PolishVector step = damped_.ldlt().solve(-gradient);
    if (!step.allFinite()) return false;
    double fraction = 1;
    for (int halving = 0; halving <= kPolishHalvings && !reduced; ++halving, fraction *= 0.5) {
      trial_ = x_ + fraction * step;
      evaluate(trial_, false);
      reduced = equations_.norm() <= (1 - 1e-4 * fraction) * residual;
    }
  }
  return reduced;
}

// rates_ holds v at x_ from the last evaluation.
Vec6 PolishSystem::project(const Vec6& free_velocity) {
  Vec6 velocity = free_velocity;
  for (Eigen::Index a = 0; a < m_; ++a) {
    const FrictionalContactRow& c = contacts_[taken_[a]];
    const Eigen::Index row = 3 * a;
    const double normal = std::max(0.0, x_(row) - rho_(row) * (rates_(row) - c.bound));
    const Eigen::Vector2d tau = x_.segment<2>(row + 1) - rho_(row + 1) * rates_.segment<2>(row + 1);
    const double radius = c.friction * normal, length = tau.norm();
    x_(row) = normal;
    x_.segment<2>(row + 1) = length <= radius ? tau : Eigen::Vector2d(tau * (radius / length));
    velocity += responses_[taken_[a]] * x_.segment<3>(row);
  }
  return velocity;
}

}  // namespace

bool FrictionalContactSolver::polish(std::span<const FrictionalContactRow> contacts,
                                     const Vec6& free_velocity) {
  FrictionalContactSolution& s = solution_;
  // Take: the contacts carrying load or below their bound, at most kPolishContacts.
  if (!take_polish_contacts(contacts)) return false;
  // Build: G = J_L R J_Lᵀ, the free rates and ρ over the contacts taken.
  PolishSystem system(contacts, taken_, jacobians_, responses_, s.impulses, free_velocity);
  // Solve: Levenberg–Marquardt steps to a root of Alart & Curnier's equations.
  if (!system.solve()) return false;
  // Project: the root's impulses as the equations project them.
  const Vec6 velocity = system.project(free_velocity);
  // Check: the contacts left out must still be clear of their bounds.
  if (!left_out_clear(contacts, velocity)) return false;
  // Accept: the root replaces the iterate.
  for (std::size_t a = 0; a < taken_.size(); ++a)
    s.impulses[taken_[a]] = system.impulse(static_cast<Eigen::Index>(a));
  s.velocity = velocity;
  return true;
}

bool FrictionalContactSolver::take_polish_contacts(std::span<const FrictionalContactRow> contacts) {
  // The contacts taken: those carrying load and those the iterate pushes
  // below their bound; the others carry nothing (an unloaded contact's
  // disk is a point) and stay so when the result keeps them clear.
  const FrictionalContactSolution& s = solution_;
  taken_.clear();
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    if (!(s.impulses[k].x() > 0) && !(jacobians_[k].row(0).dot(s.velocity) - contacts[k].bound < 0))
      continue;
    if (taken_.size() == static_cast<std::size_t>(kPolishContacts)) return false;
    taken_.push_back(static_cast<int>(k));
  }
  return !taken_.empty();
}

bool FrictionalContactSolver::left_out_clear(std::span<const FrictionalContactRow> contacts,
                                             const Vec6& velocity) const {
  for (std::size_t k = 0; k < contacts.size(); ++k)
    if (!std::binary_search(taken_.begin(), taken_.end(), static_cast<int>(k)) &&
        jacobians_[k].row(0).dot(velocity) - contacts[k].bound < -settings_.tolerance)
      return false;
  return true;
}

double FrictionalContactSolver::clear_stick_slip(
    std::span<const FrictionalContactRow> contacts) const {
  constexpr double kNot = std::numeric_limits<double>::infinity();
  const FrictionalContactSolution& s = solution_;
  double largest = -1;
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const FrictionalContactRow& c = contacts[k];
    const Vec3 rates = jacobians_[k] * s.velocity;
    if (rates.x() - c.bound < -settings_.stick_slip) return kNot;
    const Vec3& impulse = s.impulses[k];
    if (!(impulse.x() > 0) || !(c.friction > 0)) continue;
    if (impulse.tail<2>().norm() > kClearStickShare * c.friction * impulse.x()) return kNot;
    largest = std::max(largest, rates.tail<2>().norm());
  }
  return largest < 0 ? kNot : largest;
}

FrictionalContactSolver::FrictionalContactSolver(const FrictionalContactSettings& settings)
    : settings_(settings) {}

// What the sweeps' stopping and polishing decisions carry from one sweep
// to the next.
struct FrictionalContactSolver::SweepHistory {
  int next_polish = kFirstPolishSweep;  ///< the first sweep that may polish next
  double last_change = 0;               ///< the last sweep's largest change
  int failed_polishes = 0;
  /// clear_stick_slip's, the sweep before.
  double last_slip = std::numeric_limits<double>::infinity();
};

const FrictionalContactSolution& FrictionalContactSolver::solve(
    const Mat6& response, const Vec6& free_velocity, std::span<const FrictionalContactRow> contacts,
    std::span<const Vec3> warm) {
  const std::size_t count = contacts.size();
  FrictionalContactSolution& s = solution_;
  start_solve(count, free_velocity);
  // Rows: each contact's Jacobian, response and block, and its warm start.
  for (std::size_t k = 0; k < count; ++k) {
    build_contact(k, contacts[k], response);
    if (warm.size() == count) warm_start_contact(k, contacts[k], warm[k]);
  }
  if (count == 0) return s;

  SweepHistory history;
  for (int sweep = 0; sweep < settings_.max_sweeps; ++sweep) {
    const Vec6 velocity_before = s.velocity;
    // Sweep: each contact's block solved exactly with the others held.
    for (std::size_t k = 0; k < count; ++k) {
      const double normal = relax_normal(k, contacts[k]);
      relax_tangential(k, contacts[k], normal);
    }
    // Converged when no contact point's velocity changed beyond the tolerance.
    const double largest_change = largest_point_change(s.velocity - velocity_before);
    s.sweeps = sweep + 1;
    s.residual = largest_change;
    if (largest_change <= settings_.tolerance) return s;
    // Stuck: every loaded contact clearly sticks (only when asked).
    if (settings_.stick_slip > 0 && clearly_stuck(contacts, history)) return s;
    // Polish: a semismooth Newton solve of the loaded contacts where the sweeps are slow.
    polish_if_slow(contacts, free_velocity, largest_change, history);
    history.last_change = largest_change;
  }
  s.converged = false;
  return s;
}

void FrictionalContactSolver::start_solve(std::size_t count, const Vec6& free_velocity) {
  FrictionalContactSolution& s = solution_;
  jacobians_.resize(count);
  responses_.resize(count);
  blocks_.resize(count);
  tangential_inverses_.resize(count);
  tangential_decomposed_.assign(count, 0);
  tangential_eigenvalues_.resize(count);
  tangential_eigenvectors_.resize(count);
  s.impulses.assign(count, Vec3::Zero());
  s.tangent1.resize(count);
  s.velocity = free_velocity;
  s.sweeps = 0;
  s.residual = 0;
  s.converged = true;
  s.stuck = false;
}

[[gnu::always_inline]] inline void FrictionalContactSolver::build_contact(
    std::size_t k, const FrictionalContactRow& c, const Mat6& response) {
  const Vec3 t1 = perpendicular_unit(c.normal);
  const Vec3 t2 = c.normal.cross(t1);
  solution_.tangent1[k] = t1;
  Eigen::Matrix<double, 3, 6>& j = jacobians_[k];
  j.row(0) << c.normal.transpose(), c.lever.cross(c.normal).transpose();
  j.row(1) << t1.transpose(), c.lever.cross(t1).transpose();
  j.row(2) << t2.transpose(), c.lever.cross(t2).transpose();
  responses_[k] = response * j.transpose();
  blocks_[k] = j * responses_[k];
  tangential_inverses_[k] = blocks_[k].bottomRightCorner<2, 2>().inverse();
}

[[gnu::always_inline]] inline void FrictionalContactSolver::warm_start_contact(
    std::size_t k, const FrictionalContactRow& c, const Vec3& warm) {
  FrictionalContactSolution& s = solution_;
  Vec3 start = warm;
  start.x() = std::max(0.0, start.x());
  const double radius = c.friction * start.x();
  const double tangential = start.tail<2>().norm();
  if (tangential > radius) start.tail<2>() *= tangential > 0 ? radius / tangential : 0.0;
  s.impulses[k] = start;
  s.velocity += responses_[k] * start;
}

[[gnu::always_inline]] inline double FrictionalContactSolver::relax_normal(
    std::size_t k, const FrictionalContactRow& c) {
  FrictionalContactSolution& s = solution_;
  Vec3& impulse = s.impulses[k];
  const double normal_velocity = jacobians_[k].row(0).dot(s.velocity) - c.bound;
  const double normal = std::max(0.0, impulse.x() - normal_velocity / blocks_[k](0, 0));
  const double normal_change = normal - impulse.x();
  if (normal_change != 0) {
    s.velocity += responses_[k].col(0) * normal_change;
    impulse.x() = normal;
  }
  return normal;
}

[[gnu::always_inline]] inline void FrictionalContactSolver::relax_tangential(
    std::size_t k, const FrictionalContactRow& c, double normal) {
  FrictionalContactSolution& s = solution_;
  Vec3& impulse = s.impulses[k];
  // A point without friction or normal force keeps none.
  if ((c.friction <= 0 || impulse.x() == 0) && impulse.tail<2>().isZero()) return;
  const Eigen::Matrix2d wt = blocks_[k].bottomRightCorner<2, 2>();
  // The slip this contact's tangential impulse sees from everything else.
  const Eigen::Vector2d slip_without =
      jacobians_[k].bottomRows<2>() * s.velocity - wt * impulse.tail<2>();
  const Eigen::Vector2d tangential =
      disk_minimiser(tangential_inverses_[k], slip_without, c.friction * normal, [&, k] {
        if (!tangential_decomposed_[k]) {
          const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(0.5 * (wt + wt.transpose()));
          tangential_eigenvalues_[k] = eigen.eigenvalues();
          tangential_eigenvectors_[k] = eigen.eigenvectors();
          tangential_decomposed_[k] = 1;
        }
        return std::pair<const Eigen::Vector2d&, const Eigen::Matrix2d&>(
            tangential_eigenvalues_[k], tangential_eigenvectors_[k]);
      });
  const Eigen::Vector2d tangential_change = tangential - impulse.tail<2>();
  if (!tangential_change.isZero()) {
    s.velocity += responses_[k].rightCols<2>() * tangential_change;
    impulse.tail<2>() = tangential;
  }
}

[[gnu::always_inline]] inline double FrictionalContactSolver::largest_point_change(
    const Vec6& change) const {
  double largest_squared = 0;
  for (const Eigen::Matrix<double, 3, 6>& j : jacobians_)
    largest_squared = std::max(largest_squared, (j * change).squaredNorm());
  return std::sqrt(largest_squared);
}

bool FrictionalContactSolver::clearly_stuck(std::span<const FrictionalContactRow> contacts,
                                            SweepHistory& history) {
  FrictionalContactSolution& s = solution_;
  const double slip = clear_stick_slip(contacts);
  if (s.sweeps >= kFirstPolishSweep && slip <= settings_.stick_slip && slip <= history.last_slip) {
    s.converged = false;
    s.stuck = true;
    return true;
  }
  history.last_slip = slip;
  return false;
}

void FrictionalContactSolver::polish_if_slow(std::span<const FrictionalContactRow> contacts,
                                             const Vec6& free_velocity, double largest_change,
                                             SweepHistory& history) {
  const int sweeps = solution_.sweeps;
  if (sweeps >= history.next_polish && history.failed_polishes < kPolishFailures &&
      largest_change > kSlowSweep * history.last_change) {
    if (!polish(contacts, free_velocity)) ++history.failed_polishes;
    history.next_polish = 2 * sweeps;
  }
}

}  // namespace hb
