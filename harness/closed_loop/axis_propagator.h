// Exact propagation of one axis of the hand–device system over a fixed
// step h with its inputs held (a zero-order hold):
//   ẏ = v − w
//   M v̇ = −k y − b_hand (v − w) − b_device v + f
// where y is the device's offset from the operator's intent (m or rad), v
// the device's velocity, w the intent's velocity and f the applied force
// (the displayed force plus friction), w and f constant over the step.
// The state after the step is Φ (y, v) + Γ (w, f) with Φ = e^{A h} and
// Γ = ∫₀ʰ e^{A s} ds B, both from one matrix exponential: no truncation
// error, for any stiffness and step. The integral of v² over the step (what
// viscous friction dissipates, per unit damping) is the quadratic form
// zᵀ Q z of z = (y, v, w, f), Q from a second exponential (Van Loan 1978).
#pragma once

#include <Eigen/Core>

namespace hb {

struct AxisPropagator {
  Eigen::Matrix2d phi = Eigen::Matrix2d::Identity();          ///< state transition over h
  Eigen::Matrix2d gamma = Eigen::Matrix2d::Zero();            ///< columns: input w, input f
  Eigen::Matrix4d velocity_square = Eigen::Matrix4d::Zero();  ///< Q: ∫₀ʰ v² dt = zᵀ Q z

  /// mass > 0; the others >= 0; h > 0 (s).
  static AxisPropagator make(double mass, double k, double b_hand, double b_device, double h);

  /// Advances (y, v) of every axis of a vector at once (the model is
  /// isotropic): y, v, w, f are 3-vectors.
  /// ∫₀ʰ |v|² dt (m²/s or rad²/s) over the step that starts at (y, v)
  /// with inputs (w, f), every axis together.
  template <class V>
  double velocity_square_integral(const V& y, const V& v, const V& w, const V& f) const {
    const V* z[4] = {&y, &v, &w, &f};
    double sum = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) sum += velocity_square(i, j) * z[i]->dot(*z[j]);
    return sum;
  }

  template <class V>
  void advance(V& y, V& v, const V& w, const V& f) const {
    const V y0 = y;
    y = phi(0, 0) * y0 + phi(0, 1) * v + gamma(0, 0) * w + gamma(0, 1) * f;
    v = phi(1, 0) * y0 + phi(1, 1) * v + gamma(1, 0) * w + gamma(1, 1) * f;
  }
};

}  // namespace hb
