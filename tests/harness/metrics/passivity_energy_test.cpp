// The port energy of a sampled device against closed forms.
#include "harness/metrics/passivity_energy.h"

#include <catch2/catch.hpp>
#include <cmath>

namespace hb {
namespace {

Pose at_x(double x) {
  Pose pose;
  pose.p = Vec3(x, 0, 0);
  return pose;
}

Wrench force_x(double f) {
  Wrench w;
  w.force = Vec3(f, 0, 0);
  w.torque = Vec3::Zero();
  return w;
}

TEST_CASE("a still device exchanges no energy, whatever the wrench") {
  PortEnergy energy(0, 0);
  for (int n = 0; n < 100; ++n) {
    Wrench w;
    w.force = Vec3(3, -2, 1) * std::sin(0.1 * n);
    w.torque = Vec3(0.1, 0.2, -0.3);
    energy.add(w, at_x(0.01));
  }
  CHECK(energy.energy_j() == 0.0);
}

TEST_CASE("pushing into a sampled spring gains the held-force energy, not the spring's") {
  // The device moves Δ a tick into a wall F = −k x. With the force held
  // over each tick the device supplies k Δ² (0 + 1 + ... + (N−1)), short of
  // the continuous spring's ½ k (NΔ)² by ½ k Δ² N.
  const double k = 5000, delta = 1e-4;
  const int ticks = 50;
  PortEnergy energy(0, 0);
  for (int n = 0; n <= ticks; ++n) energy.add(force_x(-k * n * delta), at_x(n * delta));
  const double held = k * delta * delta * ticks * (ticks - 1) / 2.0;
  CHECK(energy.energy_j() == Approx(held).epsilon(1e-12));
  const double spring = 0.5 * k * std::pow(ticks * delta, 2);
  CHECK(spring - energy.energy_j() == Approx(0.5 * k * delta * delta * ticks).epsilon(1e-9));
}

TEST_CASE(
    "a sampled wall with backward-difference damping is passive only below k = 2b cos(wT)/T") {
  // x_n = A sin(nθ), F_n = −(k x_n + b (x_n − x_{n−1}) / T). Over whole
  // periods the held-force energy is (N A²/2)(1 − cos θ)(2 b cos θ / T − k):
  // it changes sign at k = 2 b cos θ / T (Colgate & Schenkel 1997: kT/2 < b
  // as θ → 0).
  const double T = 1e-3, b = 5, amplitude = 1e-3;
  const int period = 50;  // 20 Hz at 1 kHz
  const double theta = 2 * M_PI / period;
  const double limit = 2 * b * std::cos(theta) / T;
  for (const double k : {0.5 * limit, 0.98 * limit, 1.02 * limit, 3.0 * limit}) {
    PortEnergy energy(0, 0);
    const int periods = 4, n_ticks = periods * period;
    // One tick before the first so that the damping has its difference.
    double previous = amplitude * std::sin(-theta);
    for (int n = 0; n <= n_ticks; ++n) {
      const double x = amplitude * std::sin(n * theta);
      energy.add(force_x(-(k * x + b * (x - previous) / T)), at_x(x));
      previous = x;
    }
    const double closed_form = n_ticks * amplitude * amplitude / 2 * (1 - std::cos(theta)) *
                               (2 * b * std::cos(theta) / T - k);
    INFO("k = " << k << " N/m, limit " << limit << " N/m");
    CHECK(energy.energy_j() == Approx(closed_form).epsilon(1e-9));
    CHECK((energy.energy_j() > 0) == (k < limit));
  }
}

TEST_CASE("a held torque over a turn takes the rotation vector's energy") {
  // Turning by 0.01 rad a tick about z against τ = −κ θ: κ Σ θ_n Δθ.
  const double kappa = 2, step = 0.01;
  PortEnergy energy(0, 0);
  for (int n = 0; n <= 10; ++n) {
    Pose pose;
    pose.q = Quat(Eigen::AngleAxisd(n * step, Vec3::UnitZ()));
    Wrench w;
    w.force = Vec3::Zero();
    w.torque = Vec3(0, 0, -kappa * n * step);
    energy.add(w, pose);
  }
  CHECK(energy.energy_j() == Approx(kappa * step * step * 45).epsilon(1e-9));
}

TEST_CASE("a run starting in contact starts with the coupling's store") {
  // A coupling stretched by 2 mm (k_t = 2000 N/m) displays 4 N: 4 mJ stored.
  PortEnergy energy(2000, 5);
  Wrench w = force_x(4.0);
  w.torque = Vec3(0, 0.1, 0);
  CHECK(energy.add(w, at_x(0)) == Approx(4.0 * 4.0 / 4000 + 0.01 / 10).epsilon(1e-12));
  // A still device adds nothing to it.
  CHECK(energy.add(w, at_x(0)) == Approx(0.004 + 0.001).epsilon(1e-12));
}

}  // namespace
}  // namespace hb
