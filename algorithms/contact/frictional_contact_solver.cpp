#include "algorithms/contact/frictional_contact_solver.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
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

}  // namespace

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

      // Tangential: the impulse that stops sliding, kept in the disk μ λ_n.
      if (c.friction <= 0 && impulse.tail<2>().isZero()) continue;
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
    double largest_change = 0;
    for (std::size_t k = 0; k < count; ++k)
      largest_change = std::max(largest_change, (jacobians_[k] * change).norm());
    s.sweeps = sweep + 1;
    s.residual = largest_change;
    if (largest_change <= options_.tolerance) return s;
  }
  s.converged = false;
  return s;
}

}  // namespace hb
