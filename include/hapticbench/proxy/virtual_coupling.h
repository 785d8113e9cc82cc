// Virtual coupling between the device's tool frame and the proxy's tool
// frame (lecture notes, "Virtual Coupling"):
//   F_c = k_T (x_h − x_p) + b_T (v_h − v_p)
//   τ_c = k_R θ + b_R (ω_h − ω_p),   θ = rotation_vector(q_h · q_p⁻¹)
// x and v are the tool-frame origins and their velocities, world frame. The
// spring force acts at the proxy's tool-frame origin, so about the proxy's
// centre of mass the coupling also has the moment a × F_c with
// a = origin − COM = −R c. The device displays the reaction (−F_c, −τ_c)
// about its tool-frame origin.
#pragma once

#include <utility>

#include "hapticbench/pose.h"
#include "hapticbench/proxy/force_model.h"
#include "hapticbench/proxy/rigid_body.h"
#include "hapticbench/scene.h"

namespace hb {

/// The coupling's wrench in the two forms the proxy model needs.
struct CouplingEvaluation {
  /// On the proxy: N, and N·m about the proxy's centre of mass, world frame,
  /// with K and D with respect to the proxy state (force_model.h coordinates).
  ForceEvaluation on_proxy;
  /// What the device displays: (−F_c, −τ_c), N and N·m about the tool-frame origin, world frame.
  Wrench display;
};

/// Evaluates the coupling for the proxy at `state` and the device's tool
/// frame at `device_pose` moving with `device_twist` (velocity of its origin).
CouplingEvaluation evaluate_coupling(const CouplingGains& gains, const RigidBody& body,
                                     const RigidBodyState& state, const Pose& device_pose,
                                     const Twist& device_twist, bool with_jacobians);

/// The coupling as a force model, for a device held at a fixed pose and twist
/// during one integration step.
class CouplingForce : public ForceModel {
 public:
  CouplingForce(const CouplingGains& gains, const RigidBody& body, const Pose& device_pose,
                const Twist& device_twist)
      : gains_(gains), body_(body), device_pose_(device_pose), device_twist_(device_twist) {}
  ForceEvaluation evaluate(const RigidBodyState& state, bool with_jacobians) override {
    return evaluate_coupling(gains_, body_, state, device_pose_, device_twist_, with_jacobians)
        .on_proxy;
  }

 private:
  CouplingGains gains_;
  RigidBody body_;
  Pose device_pose_;
  Twist device_twist_;
};

/// The coupling plus an algorithm's contact forces (may be null), as one
/// force model for an integrator or the quasi-static solver.
class CouplingWithContacts : public ForceModel {
 public:
  CouplingWithContacts(CouplingForce coupling, ForceModel* contacts)
      : coupling_(std::move(coupling)), contacts_(contacts) {}
  ForceEvaluation evaluate(const RigidBodyState& state, bool with_jacobians) override {
    ForceEvaluation total = coupling_.evaluate(state, with_jacobians);
    if (contacts_) total += contacts_->evaluate(state, with_jacobians);
    return total;
  }
  bool release_pulling(const RigidBodyState& state, const Vec6& displacement,
                       const Vec6& velocity_change) override {
    return contacts_ && contacts_->release_pulling(state, displacement, velocity_change);
  }

 private:
  CouplingForce coupling_;
  ForceModel* contacts_;
};

}  // namespace hb
