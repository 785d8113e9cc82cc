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

}  // namespace

bool FrictionalContactSolver::polish(std::span<const FrictionalContactRow> contacts,
                                     const Vec6& free_velocity) {
  FrictionalContactSolution& s = solution_;
  // The contacts taken: those carrying load and those the iterate pushes
  // below their bound; the others carry nothing (an unloaded contact's
  // disk is a point) and stay so when the result keeps them clear.
  taken_.clear();
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    if (!(s.impulses[k].x() > 0) && !(jacobians_[k].row(0).dot(s.velocity) - contacts[k].bound < 0))
      continue;
    if (taken_.size() == static_cast<std::size_t>(kPolishContacts)) return false;
    taken_.push_back(static_cast<int>(k));
  }
  const auto m = static_cast<Eigen::Index>(taken_.size());
  if (m == 0) return false;
  const Eigen::Index n = 3 * m;
  // v = J_L u = J_L u_free + G x over the contacts taken L, G = J_L R J_Lᵀ;
  // per contact the augmentation ρ_n = 1 / G_nn and ρ_t = 1 / (mean
  // tangential diagonal), which make every equation an impulse.
  PolishMatrix g(n, n);
  PolishVector free_rates(n), x(n), rho(n);
  for (Eigen::Index a = 0; a < m; ++a) {
    const int k = taken_[a];
    free_rates.segment<3>(3 * a) = jacobians_[k] * free_velocity;
    x.segment<3>(3 * a) = s.impulses[k];
    for (Eigen::Index b = 0; b < m; ++b)
      g.block<3, 3>(3 * a, 3 * b) = jacobians_[k] * responses_[taken_[b]];
    rho(3 * a) = 1 / g(3 * a, 3 * a);
    rho(3 * a + 1) = rho(3 * a + 2) = 2 / (g(3 * a + 1, 3 * a + 1) + g(3 * a + 2, 3 * a + 2));
  }
  // Alart & Curnier's equations, zero exactly where the conditions above
  // hold: with λ̂_n = λ_n − ρ_n (n·u − b) and τ = λ_t − ρ_t u_t,
  //   F_n = λ_n − max(0, λ̂_n),   F_t = λ_t − Π_{|·| ≤ μ max(0, λ̂_n)}(τ),
  // and a generalised Jacobian from the branch each contact is on.
  PolishMatrix jacobian(n, n);
  PolishVector equations(n), rates(n);
  PolishRows slip_change(2, n);
  const auto evaluate = [&](const PolishVector& at, bool with_jacobian) {
    rates = free_rates + g * at;
    for (Eigen::Index a = 0; a < m; ++a) {
      const FrictionalContactRow& c = contacts[taken_[a]];
      const Eigen::Index row = 3 * a;
      const double rho_n = rho(row), rho_t = rho(row + 1);
      const double augmented = at(row) - rho_n * (rates(row) - c.bound);
      const bool pressed = augmented > 0;
      if (pressed) {
        equations(row) = rho_n * (rates(row) - c.bound);
        if (with_jacobian) jacobian.row(row) = rho_n * g.row(row);
      } else {
        equations(row) = at(row);
        if (with_jacobian) {
          jacobian.row(row).setZero();
          jacobian(row, row) = 1;
        }
      }
      const double radius = c.friction * std::max(0.0, augmented);
      const Eigen::Vector2d tau = at.segment<2>(row + 1) - rho_t * rates.segment<2>(row + 1);
      const double length = tau.norm();
      if (length <= radius) {  // sticking: u_t = 0
        equations.segment<2>(row + 1) = rho_t * rates.segment<2>(row + 1);
        if (with_jacobian) jacobian.middleRows<2>(row + 1) = rho_t * g.middleRows<2>(row + 1);
        continue;
      }
      // Sliding: F_t = λ_t − r h, h = τ / |τ|, r = μ max(0, λ̂_n);
      // dF_t = dλ_t − h dr − (r / |τ|) (I − h hᵀ) dτ.
      const Eigen::Vector2d h = tau / length;
      equations.segment<2>(row + 1) = at.segment<2>(row + 1) - radius * h;
      if (!with_jacobian) continue;
      slip_change = -rho_t * g.middleRows<2>(row + 1);
      slip_change.block<2, 2>(0, row + 1) += Eigen::Matrix2d::Identity();
      jacobian.middleRows<2>(row + 1) =
          -(radius / length) * (Eigen::Matrix2d::Identity() - h * h.transpose()) * slip_change;
      jacobian.block<2, 2>(row + 1, row + 1) += Eigen::Matrix2d::Identity();
      if (pressed) {
        jacobian.middleRows<2>(row + 1) += (c.friction * rho_n) * h * g.row(row);
        jacobian.block<2, 1>(row + 1, row) -= c.friction * h;
      }
    }
  };
  // Levenberg–Marquardt steps on ½ |F|²: contacts at one point with
  // nearly parallel normals make the Jacobian nearly singular, and a plain
  // Newton step would trade load between them without bound. A step is
  // halved until it reduces |F|; when kPolishHalvings halvings do not, the
  // damping grows a hundredfold, at most kPolishDampings times.
  PolishVector trial(n);
  PolishMatrix damped(n, n);
  evaluate(x, true);
  double residual = equations.norm();
  for (int iteration = 0; iteration < kPolishIterations; ++iteration) {
    if (residual <= kPolishResidual * x.norm()) break;
    const PolishVector gradient = jacobian.transpose() * equations;
    const PolishMatrix normal_matrix = jacobian.transpose() * jacobian;
    // The mean diagonal of JᵀJ is |J|² / n.
    double damping = kPolishDamping * jacobian.squaredNorm() / static_cast<double>(n);
    bool reduced = false;
    for (int attempt = 0; attempt < kPolishDampings && !reduced; ++attempt, damping *= 100) {
      damped = normal_matrix;
      damped.diagonal().array() += damping;
      const PolishVector step = damped.ldlt().solve(-gradient);
      if (!step.allFinite()) return false;
      double fraction = 1;
      for (int halving = 0; halving <= kPolishHalvings && !reduced; ++halving, fraction *= 0.5) {
        trial = x + fraction * step;
        evaluate(trial, false);
        reduced = equations.norm() <= (1 - 1e-4 * fraction) * residual;
      }
    }
    if (!reduced) return false;
    x = trial;
    evaluate(x, true);
    // Stalled short of a root (the contacts taken or their states are not
    // the solution's): the sweeps go on.
    const double previous = residual;
    residual = equations.norm();
    if (residual > kPolishStall * previous) return false;
  }
  if (!(residual <= kPolishResidual * x.norm())) return false;
  // The result projected as the equations project it (λ_n = max(0, λ̂_n),
  // λ_t = Π(τ)), so that a contact left unpressed carries exactly nothing
  // and a sliding one lies on its circle; the contacts left out must still
  // be clear of their bounds (`rates` holds v at x from the last evaluation).
  Vec6 velocity = free_velocity;
  for (Eigen::Index a = 0; a < m; ++a) {
    const FrictionalContactRow& c = contacts[taken_[a]];
    const Eigen::Index row = 3 * a;
    const double normal = std::max(0.0, x(row) - rho(row) * (rates(row) - c.bound));
    const Eigen::Vector2d tau = x.segment<2>(row + 1) - rho(row + 1) * rates.segment<2>(row + 1);
    const double radius = c.friction * normal, length = tau.norm();
    x(row) = normal;
    x.segment<2>(row + 1) = length <= radius ? tau : Eigen::Vector2d(tau * (radius / length));
    velocity += responses_[taken_[a]] * x.segment<3>(row);
  }
  for (std::size_t k = 0; k < contacts.size(); ++k)
    if (!std::binary_search(taken_.begin(), taken_.end(), static_cast<int>(k)) &&
        jacobians_[k].row(0).dot(velocity) - contacts[k].bound < -options_.tolerance)
      return false;
  for (Eigen::Index a = 0; a < m; ++a) s.impulses[taken_[a]] = x.segment<3>(3 * a);
  s.velocity = velocity;
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
    if (rates.x() - c.bound < -options_.stick_slip) return kNot;
    const Vec3& impulse = s.impulses[k];
    if (!(impulse.x() > 0) || !(c.friction > 0)) continue;
    if (impulse.tail<2>().norm() > kClearStickShare * c.friction * impulse.x()) return kNot;
    largest = std::max(largest, rates.tail<2>().norm());
  }
  return largest < 0 ? kNot : largest;
}

FrictionalContactSolver::FrictionalContactSolver(const FrictionalContactOptions& options)
    : options_(options) {}

const FrictionalContactSolution& FrictionalContactSolver::solve(
    const Mat6& response, const Vec6& free_velocity, std::span<const FrictionalContactRow> contacts,
    std::span<const Vec3> warm) {
  const std::size_t count = contacts.size();
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

  for (std::size_t k = 0; k < count; ++k) {
    const FrictionalContactRow& c = contacts[k];
    const Vec3 t1 = perpendicular_unit(c.normal);
    const Vec3 t2 = c.normal.cross(t1);
    s.tangent1[k] = t1;
    Eigen::Matrix<double, 3, 6>& j = jacobians_[k];
    j.row(0) << c.normal.transpose(), c.lever.cross(c.normal).transpose();
    j.row(1) << t1.transpose(), c.lever.cross(t1).transpose();
    j.row(2) << t2.transpose(), c.lever.cross(t2).transpose();
    responses_[k] = response * j.transpose();
    blocks_[k] = j * responses_[k];
    tangential_inverses_[k] = blocks_[k].bottomRightCorner<2, 2>().inverse();
    if (warm.size() == count) {
      Vec3 start = warm[k];
      start.x() = std::max(0.0, start.x());
      const double radius = c.friction * start.x();
      const double tangential = start.tail<2>().norm();
      if (tangential > radius) start.tail<2>() *= tangential > 0 ? radius / tangential : 0.0;
      s.impulses[k] = start;
      s.velocity += responses_[k] * start;
    }
  }
  if (count == 0) return s;

  int next_polish = kFirstPolishSweep;
  double last_change = 0;
  int failed_polishes = 0;
  double last_slip =
      std::numeric_limits<double>::infinity();  // clear_stick_slip's, the sweep before
  for (int sweep = 0; sweep < options_.max_sweeps; ++sweep) {
    const Vec6 velocity_before = s.velocity;
    for (std::size_t k = 0; k < count; ++k) {
      const FrictionalContactRow& c = contacts[k];
      const Eigen::Matrix<double, 3, 6>& j = jacobians_[k];
      const Mat3& w = blocks_[k];
      Vec3& impulse = s.impulses[k];

      // Normal: the impulse that brings n·u to its bound, kept ≥ 0.
      const double normal_velocity = j.row(0).dot(s.velocity) - c.bound;
      const double normal = std::max(0.0, impulse.x() - normal_velocity / w(0, 0));
      const double normal_change = normal - impulse.x();
      if (normal_change != 0) {
        s.velocity += responses_[k].col(0) * normal_change;
        impulse.x() = normal;
      }

      // Tangential: the impulse that stops sliding, kept in the disk μ λ_n
      // (a point without friction or normal force keeps none).
      if ((c.friction <= 0 || impulse.x() == 0) && impulse.tail<2>().isZero()) continue;
      const Eigen::Matrix2d wt = w.bottomRightCorner<2, 2>();
      // The slip this contact's tangential impulse sees from everything else.
      const Eigen::Vector2d slip_without = j.bottomRows<2>() * s.velocity - wt * impulse.tail<2>();
      const Eigen::Vector2d tangential =
          disk_minimiser(tangential_inverses_[k], slip_without, c.friction * normal, [&, k] {
            if (!tangential_decomposed_[k]) {
              const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(0.5 *
                                                                         (wt + wt.transpose()));
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
    // The sweep's change of every contact point's velocity.
    const Vec6 change = s.velocity - velocity_before;
    double largest_squared = 0;
    for (std::size_t k = 0; k < count; ++k)
      largest_squared = std::max(largest_squared, (jacobians_[k] * change).squaredNorm());
    const double largest_change = std::sqrt(largest_squared);
    s.sweeps = sweep + 1;
    s.residual = largest_change;
    if (largest_change <= options_.tolerance) return s;
    if (options_.stick_slip > 0) {
      const double slip = clear_stick_slip(contacts);
      if (s.sweeps >= kFirstPolishSweep && slip <= options_.stick_slip && slip <= last_slip) {
        s.converged = false;
        s.stuck = true;
        return s;
      }
      last_slip = slip;
    }
    // Polish where the sweeps converge slowly: from kFirstPolishSweep on,
    // when a sweep took off less than kSlowSweep of the last one's change,
    // then at doubling intervals.
    if (s.sweeps >= next_polish && failed_polishes < kPolishFailures &&
        largest_change > kSlowSweep * last_change) {
      if (!polish(contacts, free_velocity)) ++failed_polishes;
      next_polish = 2 * s.sweeps;
    }
    last_change = largest_change;
  }
  s.converged = false;
  return s;
}

}  // namespace hb
