#include "hapticbench/proxy/quasi_static.h"

#include <Eigen/Dense>

#include "hapticbench/proxy/device_output.h"
#include "hapticbench/proxy/virtual_coupling.h"

namespace hb {

namespace {
double residual(const Wrench& wrench, double length_scale_m) {
  return wrench.force.norm() + wrench.torque.norm() / length_scale_m;
}

RigidBodyState displaced(const RigidBodyState& state, const Vec6& step) {
  RigidBodyState moved = state;
  moved.x += step.head<3>();
  moved.q = (quat_from_rotation_vector(step.tail<3>()) * state.q).normalized();
  return moved;
}

}  // namespace

QuasiStaticSolution solve_quasi_static(ForceModel& springs, const RigidBodyState& start,
                                       const QuasiStaticSettings& settings) {
  QuasiStaticSolution solution;
  solution.state = start;
  ForceEvaluation current = springs.evaluate(start, true);
  double current_residual = residual(current.wrench, settings.length_scale_m);
  while (solution.iterations < settings.max_iterations) {
    if (current_residual <= settings.force_tolerance_n) {
      solution.converged = true;
      break;
    }
    Vec6 wrench;
    wrench << current.wrench.force, current.wrench.torque;
    Vec6 step = current.stiffness.completeOrthogonalDecomposition().solve(-wrench);
    ++solution.iterations;

    // Damping: halve the step until the residual decreases (contacts switching
    // on and off make the spring field only piecewise linear).
    bool accepted = false;
    for (int halving = 0; halving < 12; ++halving) {
      const RigidBodyState trial = displaced(solution.state, step);
      ForceEvaluation evaluation = springs.evaluate(trial, true);
      const double trial_residual = residual(evaluation.wrench, settings.length_scale_m);
      if (trial_residual < current_residual) {
        solution.state = trial;
        current = evaluation;
        current_residual = trial_residual;
        accepted = true;
        break;
      }
      step *= 0.5;
    }
    if (!accepted) break;  // no descent along the Newton direction: as close as it gets
    if (step.head<3>().norm() < settings.step_tolerance_m &&
        step.tail<3>().norm() < settings.step_tolerance_rad) {
      solution.converged = true;
      break;
    }
  }
  if (!solution.converged) solution.converged = current_residual <= settings.force_tolerance_n;
  return solution;
}

QuasiStaticProxy::QuasiStaticProxy(const RigidBody& frame, const CouplingGains& gains, double dt_s,
                                   const QuasiStaticSettings& settings)
    : frame_(frame), gains_(gains), dt_s_(dt_s), settings_(settings) {}

void QuasiStaticProxy::reset(const Pose& pose) {
  state_ = state_at_rest(frame_, pose);
  converged_ = true;
}

Wrench QuasiStaticProxy::advance(const DeviceSample& device, ForceModel* contact_springs,
                                 uint32_t& flags, int64_t& newton_steps) {
  if (!is_finite(device)) {
    flags |= kFlagNonFiniteZeroed;
    return Wrench{};
  }
  // Coupling springs (dampers off) plus the contact springs, for the solver.
  CouplingWithContacts springs(
      CouplingForce(CouplingGains{gains_.k_t, 0, gains_.k_r, 0}, frame_, device.pose, Twist{}),
      contact_springs);
  const QuasiStaticSolution solution = solve_quasi_static(springs, state_, settings_);
  newton_steps += solution.iterations;
  converged_ = solution.converged;

  RigidBodyState next = solution.state;
  next.v = (next.x - state_.x) / dt_s_;
  next.w = rotation_vector(next.q * state_.q.conjugate()) / dt_s_;
  state_ = next;
  if (reset_non_finite_proxy(frame_, device.pose, state_, flags)) converged_ = false;
  return evaluate_coupling(gains_, frame_, state_, device.pose, device.twist, false).display;
}

}  // namespace hb
