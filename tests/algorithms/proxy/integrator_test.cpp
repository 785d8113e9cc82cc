#include "hapticbench/proxy/integrator.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <vector>

#include "hapticbench/proxy/virtual_coupling.h"
#include "tests/support/proxy_fixtures.h"

namespace hb {
namespace {

constexpr double kDt = 1e-3;

class NoForce : public ForceModel {
 public:
  ForceEvaluation evaluate(const RigidBodyState&, bool) override { return {}; }
};

// The proxy on the coupling spring along x: m ẍ = −k x − b ẋ, device at the origin.
struct Oscillator {
  double mass = 0.05;       // kg
  double stiffness = 2000;  // N/m
  double damping = 0.5;     // N·s/m

  std::vector<double> positions(IntegratorKind kind, int steps) const {
    RigidBody body;
    body.mass_kg = mass;
    body.inertia_body = 1e-5 * Mat3::Identity();
    CouplingForce spring(CouplingGains{stiffness, damping, 0, 0}, body, Pose{}, Twist{});
    RigidBodyState state;
    state.x = Vec3(0.01, 0, 0);
    std::vector<double> x{state.x.x()};
    for (int n = 0; n < steps; ++n) {
      state = integrate_step(kind, body, state, spring, kDt);
      x.push_back(state.x.x());
    }
    return x;
  }
  double energy(double x, double v) const { return 0.5 * mass * v * v + 0.5 * stiffness * x * x; }
};

// Trace and determinant of the amplification matrix A with z⁺ = A z, z = (x, v).
struct Amplification {
  double trace;
  double determinant;
  std::complex<double> eigenvalue() const {
    return 0.5 * (trace + std::sqrt(std::complex<double>(trace * trace - 4 * determinant)));
  }
};

// Explicit Euler: x⁺ = x + h v, v⁺ = v + h(−k x − b v)/m.
Amplification explicit_amplification(const Oscillator& o) {
  const double h = kDt;
  return {2 - h * o.damping / o.mass, 1 - h * o.damping / o.mass + h * h * o.stiffness / o.mass};
}

// Backward Euler: A = B⁻¹ with B = [[1, −h], [h k/m, 1 + h b/m]].
Amplification implicit_amplification(const Oscillator& o) {
  const double h = kDt;
  const double det_b = 1 + h * o.damping / o.mass + h * h * o.stiffness / o.mass;
  return {(2 + h * o.damping / o.mass) / det_b, 1 / det_b};
}

// A 2×2 linear recurrence obeys its characteristic polynomial (Cayley–Hamilton):
// x_{n+2} = tr·x_{n+1} − det·x_n. Returns the largest violation relative to |x_n|'s scale.
double recurrence_violation(const std::vector<double>& x, const Amplification& a) {
  double worst = 0;
  for (std::size_t n = 0; n + 2 < x.size(); ++n) {
    const double scale = std::abs(x[n]) + std::abs(x[n + 1]) + std::abs(x[n + 2]);
    worst = std::max(worst, std::abs(x[n + 2] - a.trace * x[n + 1] + a.determinant * x[n]) / scale);
  }
  return worst;
}

TEST_CASE("explicit Euler follows its amplification matrix and diverges on the coupling spring",
          "[integrator]") {
  const Oscillator o;  // k h = 2 N/m·s > b = 0.5 N·s/m: beyond explicit Euler's limit
  const Amplification a = explicit_amplification(o);
  const std::complex<double> lambda = a.eigenvalue();
  REQUIRE(lambda.imag() != 0);
  // |λ|² = det = 1 − h b/m + h² k/m = 1.03.
  CHECK(std::norm(lambda) == Approx(1.03).epsilon(1e-12));

  const int steps = 300;
  const std::vector<double> x = o.positions(IntegratorKind::kExplicitEuler, steps);
  CHECK(recurrence_violation(x, a) < 1e-10);

  // Closed form x_n = Re(α λⁿ) with α from x_0 and x_1.
  const std::complex<double> alpha =
      (x[1] - std::conj(lambda) * x[0]) / (lambda - std::conj(lambda)) * 2.0;
  const double closed_form = std::real(alpha * std::pow(lambda, steps));
  CHECK(std::abs(x[steps] - closed_form) <
        1e-8 * std::abs(alpha) * std::pow(std::abs(lambda), steps));

  // Energy grows like |λ|^(2n): compare peak energies a whole number of steps apart,
  // through the invariant scale factor |λ|² per step, within the ripple of a peak.
  auto energy_at = [&](int n) { return o.energy(x[n], (x[n + 1] - x[n]) / kDt); };
  const double growth = energy_at(steps - 1) / energy_at(0);
  CHECK(growth > 100);
  const double expected = std::pow(std::norm(lambda), steps - 1);
  CHECK(growth > 0.5 * expected);
  CHECK(growth < 2.0 * expected);
}

TEST_CASE("implicit Euler is backward Euler on the coupling spring and decays", "[integrator]") {
  const Oscillator o;
  const Amplification a = implicit_amplification(o);
  const std::complex<double> lambda = a.eigenvalue();
  CHECK(std::abs(lambda) < 1);
  const std::vector<double> x = o.positions(IntegratorKind::kImplicitEuler, 300);
  CHECK(recurrence_violation(x, a) < 1e-10);
  // Backward Euler: x⁺ = x + h v⁺, so v_n = (x_n − x_{n−1}) / h.
  auto energy_at = [&](int n) { return o.energy(x[n], (x[n] - x[n - 1]) / kDt); };
  CHECK(energy_at(300) < 1e-4 * o.energy(x[0], 0));
}

TEST_CASE("explicit Euler's stability limit on a spring-damper is k·dt < b", "[integrator]") {
  // |λ|² = 1 − h b/m + h² k/m < 1  <=>  k h < b (underdamped, b < 2m/h + k h/2).
  Oscillator stable;
  stable.damping = 2.5;  // k h = 2 < 2.5
  Oscillator unstable;
  unstable.damping = 1.5;  // k h = 2 > 1.5
  const std::vector<double> decaying = stable.positions(IntegratorKind::kExplicitEuler, 3000);
  const std::vector<double> growing = unstable.positions(IntegratorKind::kExplicitEuler, 3000);
  auto peak = [](const std::vector<double>& x, std::size_t from) {
    double m = 0;
    for (std::size_t n = from; n < x.size(); ++n) m = std::max(m, std::abs(x[n]));
    return m;
  };
  CHECK(peak(decaying, 2900) < 0.1 * std::abs(decaying[0]));
  CHECK(peak(growing, 2900) > 10 * std::abs(growing[0]));
  CHECK(std::norm(explicit_amplification(stable).eigenvalue()) < 1);
  CHECK(std::norm(explicit_amplification(unstable).eigenvalue()) > 1);
}

TEST_CASE("free fall: explicit moves with the old velocity, implicit with the new",
          "[integrator]") {
  RigidBody body;
  body.mass_kg = 0.2;
  body.gravity = Vec3(0, 0, -9.81);
  NoForce none;
  RigidBodyState explicit_state;
  RigidBodyState implicit_state;
  const int n = 50;
  for (int i = 0; i < n; ++i) {
    explicit_state = explicit_euler_step(body, explicit_state, none, kDt);
    implicit_state = implicit_euler_step(body, implicit_state, none, kDt);
  }
  const double g = -9.81;
  CHECK(explicit_state.v.z() == Approx(g * n * kDt).epsilon(1e-12));
  CHECK(implicit_state.v.z() == Approx(g * n * kDt).epsilon(1e-12));
  CHECK(explicit_state.x.z() == Approx(g * kDt * kDt * n * (n - 1) / 2).epsilon(1e-12));
  CHECK(implicit_state.x.z() == Approx(g * kDt * kDt * n * (n + 1) / 2).epsilon(1e-12));
}

TEST_CASE("torque-free spin conserves world angular momentum", "[integrator]") {
  RigidBody body;
  body.mass_kg = 0.1;
  body.inertia_body = Vec3(1e-3, 2e-3, 4e-3).asDiagonal();
  NoForce none;
  RigidBodyState start;
  start.q = Quat(Eigen::AngleAxisd(0.3, Vec3(1, 1, 0).normalized()));
  start.w = Vec3(1, 0.5, 2);
  const Vec3 momentum = world_inertia(body, start.q) * start.w;

  RigidBodyState explicit_state = start;
  RigidBodyState implicit_state = start;
  for (int i = 0; i < 200; ++i) {
    explicit_state = explicit_euler_step(body, explicit_state, none, kDt);
    implicit_state = implicit_euler_step(body, implicit_state, none, kDt);
  }
  // Explicit Euler on (q, L) keeps L exactly.
  CHECK((world_inertia(body, explicit_state.q) * explicit_state.w - momentum).norm() <
        1e-12 * momentum.norm());
  // The spin axis moves (the gyroscopic term is doing work on ω) ...
  const double turned = (implicit_state.w - start.w).norm();
  CHECK(turned > 0.2 * start.w.norm());
  // ... while L stays put to first order in dt; without the gyroscopic term
  // L would turn with the body by as much as ω does.
  const double drift = (world_inertia(body, implicit_state.q) * implicit_state.w - momentum).norm();
  CHECK(drift < 0.02 * momentum.norm());
}

}  // namespace
}  // namespace hb
