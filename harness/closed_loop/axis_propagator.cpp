#include "harness/closed_loop/axis_propagator.h"

#include <unsupported/Eigen/MatrixFunctions>

namespace hb {

AxisPropagator AxisPropagator::make(double mass, double k, double b_hand, double b_device,
                                    double h) {
  // The augmented system d/dt (y, v, w, f) = [[A, B], [0, 0]] (y, v, w, f):
  // its exponential over h holds Φ in the top-left block and Γ in the top-right.
  Eigen::Matrix4d augmented = Eigen::Matrix4d::Zero();
  augmented(0, 1) = 1;
  augmented(0, 2) = -1;
  augmented(1, 0) = -k / mass;
  augmented(1, 1) = -(b_hand + b_device) / mass;
  augmented(1, 2) = b_hand / mass;
  augmented(1, 3) = 1 / mass;
  const Eigen::Matrix4d exponential = (augmented * h).exp();
  AxisPropagator propagator;
  propagator.phi = exponential.topLeftCorner<2, 2>();
  propagator.gamma = exponential.topRightCorner<2, 2>();
  // Van Loan: exp([[−Āᵀ, c cᵀ], [0, Ā]] h) = [[·, F12], [0, F22]] with
  // F22 = e^{Āh}; ∫₀ʰ e^{Āᵀt} c cᵀ e^{Āt} dt = F22ᵀ F12, c picking v.
  Eigen::Matrix<double, 8, 8> van_loan = Eigen::Matrix<double, 8, 8>::Zero();
  van_loan.topLeftCorner<4, 4>() = -augmented.transpose();
  van_loan(1, 5) = 1;  // c cᵀ with c = e_v
  van_loan.bottomRightCorner<4, 4>() = augmented;
  const Eigen::Matrix<double, 8, 8> blocks = (van_loan * h).exp();
  propagator.velocity_square =
      blocks.bottomRightCorner<4, 4>().transpose() * blocks.topRightCorner<4, 4>();
  return propagator;
}

}  // namespace hb
