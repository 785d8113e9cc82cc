// The written-out inverse of a 6 × 6 Cholesky factor the frictionless QP
// uses: L L⁻¹ = I to within the rounding its condition allows, as Eigen's
// triangular solve finds it, lower triangular, from the lower part alone.
#include "algorithms/contact/small_inverse.h"

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <catch2/catch.hpp>
#include <limits>
#include <random>

namespace hb {
namespace {

// Q diag(scales) Qᵀ for a random orthogonal Q: symmetric positive definite
// with condition max(scales) / min(scales).
Mat6 spd_with_scales(std::mt19937& random, const Vec6& scales) {
  std::normal_distribution<double> normal;
  Mat6 gaussian;
  for (int i = 0; i < 36; ++i) gaussian.data()[i] = normal(random);
  const Eigen::HouseholderQR<Mat6> qr(gaussian);
  const Mat6 q = qr.householderQ();
  return q * scales.asDiagonal() * q.transpose();
}

}  // namespace

TEST_CASE("lower_triangular_inverse inverts a Cholesky factor and reads only the lower part") {
  std::mt19937 random(11);
  const double eps = std::numeric_limits<double>::epsilon();
  for (int trial = 0; trial < 200; ++trial) {
    const Vec6 scales = (Vec6() << 1e-4, 1e-2, 1, 10, 1e3, 1e5).finished();
    const Mat6 m = spd_with_scales(random, scales);
    Mat6 lower = Eigen::LLT<Mat6>(m).matrixL();
    const Mat6 expected = lower.triangularView<Eigen::Lower>().solve(Mat6::Identity());
    lower.triangularView<Eigen::StrictlyUpper>().setConstant(12345.0);  // not to be read
    const Mat6 inverse = lower_triangular_inverse(lower);
    CHECK(inverse.triangularView<Eigen::StrictlyUpper>().toDenseMatrix().norm() == 0);
    const Mat6 product = lower.triangularView<Eigen::Lower>() * inverse;
    // κ(L) = √κ(M) = 3e4.
    CHECK((product - Mat6::Identity()).norm() <= 100 * 3e4 * eps);
    CHECK((inverse - expected).norm() <= 100 * 3e4 * eps * expected.norm());
  }
}

}  // namespace hb
