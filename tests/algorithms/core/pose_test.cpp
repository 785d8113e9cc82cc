// Tests for algorithms/core/pose.{h,cpp}: rotation vectors against Eigen's
// angle-axis, the inverse SO(3) Jacobians against finite differences of the
// logarithm, and Pose composition against Eigen's isometries.
#include "hapticbench/pose.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>

#include "tests/support/shape_fixtures.h"

namespace hb {
namespace {

using test::kPi;

// Angle between the rotations of two unit quaternions (rad).
double rotation_angle_between(const Quat& a, const Quat& b) { return a.angularDistance(b); }

Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  return Vec3(normal(rng), normal(rng), normal(rng)).normalized();
}

// log(exp(θ) exp(δ)) and log(exp(δ) exp(θ)) through quaternions.
Vec3 log_right_product(const Vec3& theta, const Vec3& delta) {
  return rotation_vector(quat_from_rotation_vector(theta) * quat_from_rotation_vector(delta));
}
Vec3 log_left_product(const Vec3& theta, const Vec3& delta) {
  return rotation_vector(quat_from_rotation_vector(delta) * quat_from_rotation_vector(theta));
}

// Central differences of f(θ, δ) in δ at δ = 0.
template <typename Log>
Mat3 finite_difference_jacobian(const Vec3& theta, Log log_of_product) {
  const double h = 1e-6;
  Mat3 jacobian;
  for (int i = 0; i < 3; ++i) {
    const Vec3 step = h * Vec3::Unit(i);
    jacobian.col(i) = (log_of_product(theta, step) - log_of_product(theta, -step)) / (2 * h);
  }
  return jacobian;
}

}  // namespace

TEST_CASE("rotation vector matches Eigen's angle-axis", "[pose]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(0.0, kPi);
  for (int i = 0; i < 200; ++i) {
    const Vec3 axis = random_unit(rng);
    const double a = angle(rng);
    const Quat q(Eigen::AngleAxisd(a, axis));
    CHECK((rotation_vector(q) - a * axis).norm() < 1e-12);
    CHECK(rotation_angle_between(quat_from_rotation_vector(a * axis), q) < 1e-12);
  }
}

TEST_CASE("rotation vector round trip, small and near-pi angles", "[pose]") {
  std::mt19937 rng(5);
  for (double a : {0.0, 1e-300, 1e-14, 1e-9, 1e-6, 1e-4, 0.5, 2.0, 3.0, kPi - 1e-6, kPi - 1e-9}) {
    for (int i = 0; i < 20; ++i) {
      const Vec3 theta = a * random_unit(rng);
      INFO("angle " << a);
      const Quat q = quat_from_rotation_vector(theta);
      CHECK(std::abs(q.norm() - 1.0) < 1e-15);
      // Near pi the angle is set by the quaternion's tiny w: its rounding
      // (1e-16) limits the recovered angle to about 2e-16 / sin(a/2) rad.
      CHECK((rotation_vector(q) - theta).norm() <= 1e-15 + 1e-15 * a);
      // q and -q are the same rotation.
      const Quat minus_q(-q.w(), -q.x(), -q.y(), -q.z());
      CHECK((rotation_vector(minus_q) - rotation_vector(q)).norm() <= 1e-15 + 1e-15 * a);
    }
  }
}

TEST_CASE("rotation by exactly pi: either sign of the axis, same rotation", "[pose]") {
  const Vec3 axis = Vec3(1, -2, 2) / 3.0;
  const Quat q = quat_from_rotation_vector(kPi * axis);
  for (const Quat& candidate : {q, Quat(-q.w(), -q.x(), -q.y(), -q.z())}) {
    const Vec3 theta = rotation_vector(candidate);
    CHECK(theta.norm() == Approx(kPi));
    CHECK(std::abs(std::abs(theta.normalized().dot(axis)) - 1.0) < 1e-12);
    CHECK(rotation_angle_between(quat_from_rotation_vector(theta), q) < 1e-12);
  }
}

TEST_CASE("inverse SO(3) Jacobians match finite differences of the logarithm", "[pose]") {
  std::mt19937 rng(9);
  // Angles on both sides of the small-angle series' switch (1e-4 rad) and
  // close to pi, where log is still smooth for small perturbations.
  for (double a : {0.0, 1e-7, 0.9e-4, 1.1e-4, 0.3, 1.0, 2.0, 2.8, kPi - 0.05}) {
    for (int i = 0; i < 5; ++i) {
      const Vec3 theta = a * random_unit(rng);
      INFO("angle " << a);
      const Mat3 right_fd = finite_difference_jacobian(theta, log_right_product);
      const Mat3 left_fd = finite_difference_jacobian(theta, log_left_product);
      CHECK((right_jacobian_inverse(theta) - right_fd).norm() < 1e-8);
      CHECK((left_jacobian_inverse(theta) - left_fd).norm() < 1e-8);
    }
  }
}

TEST_CASE("inverse Jacobians stay finite up to an angle of pi", "[pose]") {
  const Vec3 axis = Vec3(0, 0.6, 0.8);
  for (double a : {kPi - 1e-9, kPi}) {
    const Mat3 right = right_jacobian_inverse(a * axis);
    const Mat3 left = left_jacobian_inverse(a * axis);
    REQUIRE(right.allFinite());
    REQUIRE(left.allFinite());
    // The axis is an eigenvector with eigenvalue 1; across it the limit at
    // pi is 1 + skew/2 + skew²/pi² acting on a perpendicular vector u.
    CHECK((right * axis - axis).norm() < 1e-12);
    const Vec3 u = Vec3(1, 0, 0);
    const Vec3 expected = u + 0.5 * a * axis.cross(u) - u * (a * a) / (kPi * kPi);
    CHECK((right * u - expected).norm() < 1e-6);
  }
}

TEST_CASE("pose composition and inverse agree with Eigen isometries", "[pose]") {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> coordinate(-2.0, 2.0);
  std::uniform_real_distribution<double> angle(0.0, kPi);
  auto random_pose = [&] {
    return Pose{Vec3(coordinate(rng), coordinate(rng), coordinate(rng)),
                Quat(Eigen::AngleAxisd(angle(rng), random_unit(rng)))};
  };
  auto isometry = [](const Pose& x) {
    Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
    m.linear() = x.q.toRotationMatrix();
    m.translation() = x.p;
    return m;
  };
  for (int i = 0; i < 50; ++i) {
    const Pose a = random_pose(), b = random_pose();
    const Vec3 x(coordinate(rng), coordinate(rng), coordinate(rng));
    CHECK((a.transform_point(x) - isometry(a) * x).norm() < 1e-12);
    CHECK(((a * b).transform_point(x) - a.transform_point(b.transform_point(x))).norm() < 1e-12);
    CHECK(((a * b).transform_point(x) - isometry(a) * isometry(b) * x).norm() < 1e-12);
    CHECK((a.inverse().transform_point(a.transform_point(x)) - x).norm() < 1e-12);
    CHECK((a.inverse_transform_point(x) - isometry(a).inverse() * x).norm() < 1e-12);
    const Pose identity = a * a.inverse();
    CHECK(identity.p.norm() < 1e-12);
    CHECK(rotation_angle_between(identity.q, Quat::Identity()) < 1e-12);
  }
}

TEST_CASE("skew is the cross-product matrix", "[pose]") {
  const Vec3 a(1, -2, 3), b(0.5, 4, -1);
  CHECK((skew(a) * b - a.cross(b)).norm() < 1e-15);
  CHECK(is_finite(Pose{}));
  CHECK_FALSE(is_finite(Wrench{Vec3(NAN, 0, 0), Vec3::Zero()}));
}

}  // namespace hb
