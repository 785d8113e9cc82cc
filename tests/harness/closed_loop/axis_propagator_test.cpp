// The exact propagator of one hand–device axis against the closed-form
// solutions of the mass–spring–damper it integrates.
#include "harness/closed_loop/axis_propagator.h"

#include <catch2/catch.hpp>
#include <cmath>

namespace hb {
namespace {

constexpr double kTickS = 1e-3;

struct AxisState {
  double y = 0, v = 0;
};

AxisState run(const AxisPropagator& propagator, AxisState state, double w, double f, int steps) {
  for (int i = 0; i < steps; ++i) {
    Eigen::Matrix<double, 1, 1> y{state.y}, v{state.v}, wv{w}, fv{f};
    propagator.advance(y, v, wv, fv);
    state = {y(0), v(0)};
  }
  return state;
}

TEST_CASE("an undamped hand spring oscillates as y0 cos(ωt) over a thousand ticks") {
  const double mass = 0.1, k = 400, y0 = 1e-3;
  const double omega = std::sqrt(k / mass);
  const AxisPropagator propagator = AxisPropagator::make(mass, k, 0, 0, kTickS);
  for (int ticks : {1, 7, 1000}) {
    const AxisState s = run(propagator, {y0, 0}, 0, 0, ticks);
    const double t = ticks * kTickS;
    CHECK(s.y == Approx(y0 * std::cos(omega * t)).margin(1e-15));
    CHECK(s.v == Approx(-y0 * omega * std::sin(omega * t)).margin(1e-13));
  }
}

TEST_CASE("a held force on a damped spring gives the underdamped step response") {
  const double mass = 0.05, k = 2000, b_hand = 0.5, b_device = 0.3, f = 2;
  const double sigma = (b_hand + b_device) / (2 * mass);
  const double omega_d = std::sqrt(k / mass - sigma * sigma);
  const AxisPropagator propagator = AxisPropagator::make(mass, k, b_hand, b_device, kTickS);
  for (int ticks : {1, 3, 50, 400}) {
    const double t = ticks * kTickS;
    const double expected = f / k *
                            (1 - std::exp(-sigma * t) * (std::cos(omega_d * t) +
                                                         sigma / omega_d * std::sin(omega_d * t)));
    CHECK(run(propagator, {}, 0, f, ticks).y == Approx(expected).margin(1e-14));
  }
}

TEST_CASE("a free mass under a held force moves by f t² / 2M whatever the intent does") {
  const double mass = 0.2, f = 0.7, w = 0.03;
  const AxisPropagator propagator = AxisPropagator::make(mass, 0, 0, 0, kTickS);
  const int ticks = 250;
  const double t = ticks * kTickS;
  const AxisState s = run(propagator, {0.001, 0.01}, w, f, ticks);
  // y is the offset from the intent, which moves at w.
  CHECK(s.y == Approx(0.001 + (0.01 - w) * t + f * t * t / (2 * mass)).margin(1e-14));
  CHECK(s.v == Approx(0.01 + f * t / mass).margin(1e-13));
}

TEST_CASE("a hand damper drags the device up to the intent's speed with time constant M/b") {
  const double mass = 0.1, b_hand = 2, w = 0.05;
  const double tau = mass / b_hand;
  const AxisPropagator propagator = AxisPropagator::make(mass, 0, b_hand, 0, kTickS);
  const int ticks = 120;
  const double t = ticks * kTickS;
  const AxisState s = run(propagator, {}, w, 0, ticks);
  CHECK(s.v == Approx(w * (1 - std::exp(-t / tau))).margin(1e-14));
  CHECK(s.y == Approx(-w * tau * (1 - std::exp(-t / tau))).margin(1e-15));
}

}  // namespace
}  // namespace hb
