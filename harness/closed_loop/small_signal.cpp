#include "harness/closed_loop/small_signal.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>

#include "harness/closed_loop/axis_propagator.h"

namespace hb {

double small_signal_spectral_radius(const ClosedLoopModel& model, double k_t, double b_t,
                                    double tick_s) {
  const HandModel& hand = model.hand;
  const DeviceModel& device = model.device;
  const AxisPropagator axis =
      AxisPropagator::make(hand.mass_kg + device.mass_kg, hand.k_t, hand.b_t, device.b_t, tick_s);
  const double keep = device.velocity_filter_hz > 0
                          ? std::exp(-2 * std::numbers::pi * device.velocity_filter_hz * tick_s)
                          : 0.0;
  // State (y, v, v̂) at a tick: the renderer's force from y and v̂ is held
  // over the next tick; the estimate then takes the new backward difference.
  const double g0 = axis.gamma(0, 1), g1 = axis.gamma(1, 1);
  Eigen::Matrix3d m;
  m(0, 0) = axis.phi(0, 0) - g0 * k_t;
  m(0, 1) = axis.phi(0, 1);
  m(0, 2) = -g0 * b_t;
  m(1, 0) = axis.phi(1, 0) - g1 * k_t;
  m(1, 1) = axis.phi(1, 1);
  m(1, 2) = -g1 * b_t;
  const double blend = (1 - keep) / tick_s;
  m(2, 0) = blend * (m(0, 0) - 1);
  m(2, 1) = blend * m(0, 1);
  m(2, 2) = blend * m(0, 2) + keep;
  return Eigen::EigenSolver<Eigen::Matrix3d>(m, false).eigenvalues().cwiseAbs().maxCoeff();
}

SmallSignalLimit small_signal_k_t_limit(const ClosedLoopModel& model, double b_t, double tick_s,
                                        const std::string& algorithm) {
  SmallSignalLimit limit;
  if (algorithm != "god_object" && algorithm != "constrained_dynamics") {
    limit.note = "not modelled for " + algorithm +
                 ": the small-signal model has a rigid proxy behind the coupling (god_object, "
                 "constrained_dynamics)";
    return limit;
  }
  const auto stable = [&](double k) {
    return small_signal_spectral_radius(model, k, b_t, tick_s) < 1;
  };
  double low = 1, high = 1e9;
  if (!stable(low)) {
    limit.note = "unstable at 1 N/m already";
    return limit;
  }
  if (stable(high)) {
    limit.note = "stable up to 1e9 N/m";
    return limit;
  }
  while (high / low - 1 > 1e-6) {
    const double middle = std::sqrt(low * high);
    (stable(middle) ? low : high) = middle;
  }
  limit.k_t_n_per_m = low;
  limit.note =
      "the sampled loop linearised at a contact with a rigid proxy: hand and device, "
      "zero-order-held coupling, filtered velocity; without the device's Coulomb friction and "
      "encoder quantisation, which the large-signal search includes";
  return limit;
}

}  // namespace hb
