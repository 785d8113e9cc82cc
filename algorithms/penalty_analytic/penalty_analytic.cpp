#include "algorithms/penalty_analytic/penalty_analytic.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <vector>

#include "algorithms/penalty_analytic/primitive_contacts.h"
#include "hapticbench/proxy/device_output.h"
#include "hapticbench/proxy/dynamic_proxy.h"
#include "hapticbench/proxy/proxy_settings.h"
#include "hapticbench/proxy/quasi_static.h"
#include "hapticbench/proxy/slow_loop_mailbox.h"

namespace hb {

namespace {

// Planes found by the slow contact loop, on their way to the haptic step.
using PlaneSet = std::vector<PrimitiveContact>;

// A fixed set of linearised planes evaluated at whatever state is asked.
class PlaneForces : public ForceModel {
 public:
  PlaneForces(const std::vector<PrimitiveContact>& planes, const PenaltyGains& gains)
      : planes_(planes), gains_(gains) {}
  ForceEvaluation evaluate(const RigidBodyState& state, bool with_jacobians) override {
    ForceEvaluation total;
    for (const PrimitiveContact& contact : planes_)
      total += evaluate_penalty_contact(contact.plane, gains_, state, with_jacobians);
    return total;
  }

 private:
  const std::vector<PrimitiveContact>& planes_;
  PenaltyGains gains_;
};

// Contacts found afresh at every state asked, for the quasi-static solver
// when contacts are found on the haptic loop.
class FreshContactForces : public ForceModel {
 public:
  // planes: scratch storage, reused across ticks.
  FreshContactForces(const PrimitiveContactFinder& finder, const PenaltyGains& gains,
                     std::vector<PrimitiveContact>& planes, WorkCounters& work)
      : finder_(finder), gains_(gains), planes_(planes), work_(work) {}
  ForceEvaluation evaluate(const RigidBodyState& state, bool with_jacobians) override {
    planes_.clear();
    finder_.find(state, 0, planes_, work_);
    return PlaneForces(planes_, gains_).evaluate(state, with_jacobians);
  }

 private:
  const PrimitiveContactFinder& finder_;
  PenaltyGains gains_;
  std::vector<PrimitiveContact>& planes_;
  WorkCounters& work_;
};

// How far beyond the surface the slow loop keeps planes, as a fraction of
// the tool's radius: a point that starts penetrating between two slow
// updates still meets its plane.
constexpr double kSlowMarginPerToolRadius = 0.1;

struct PenaltyAnalyticSettings {
  bool quasi_static = false;   ///< "proxy": "quasi_static" (massless) or "dynamic"
  bool slow_contacts = false;  ///< "contact_loop": "slow" or "haptic"
  ProxySettings proxy;         ///< dynamic proxy only
  PenaltyGains gains;          ///< damping 0 for the quasi-static proxy (springs only)
};

// Reads only what the chosen proxy uses, so a parameter that would be
// ignored is reported as unknown.
PenaltyAnalyticSettings read_settings(const RenderContext& context, const ParamSet& params) {
  PenaltyAnalyticSettings settings;
  settings.quasi_static =
      params.choice("proxy", "dynamic", {"dynamic", "quasi_static"}) == "quasi_static";
  settings.slow_contacts = params.choice("contact_loop", "haptic", {"haptic", "slow"}) == "slow";
  if (settings.quasi_static) {
    settings.gains = PenaltyGains{read_contact_stiffness(params), 0};
  } else {
    settings.proxy = read_proxy_settings(params, context.tool);
    settings.gains = read_penalty_gains(params);
  }
  return settings;
}

class PenaltyAnalyticRenderer : public Renderer, public SlowLoop {
 public:
  PenaltyAnalyticRenderer(const RenderContext& context, const PenaltyAnalyticSettings& settings)
      : limits_(context.device),
        dt_s_(context.dt_s),
        slow_contacts_(settings.slow_contacts),
        body_(settings.quasi_static
                  ? contact_frame(context.tool)
                  : proxy_body(context.tool, settings.proxy.proxy_mass_kg, context.gravity)),
        gains_(settings.gains),
        finder_(context.scene, context.tool, body_) {
    if (settings.quasi_static) {
      QuasiStaticSettings solver_settings;
      solver_settings.length_scale_m = std::max(finder_.tool_radius_m(), 1e-3);
      quasi_static_proxy_.emplace(body_, context.coupling, dt_s_, solver_settings);
    } else {
      dynamic_proxy_.emplace(body_, context.coupling, settings.proxy.integrator, dt_s_);
      dynamic_proxy_->follow_device_in_free_space({.tool_radius_m = finder_.tool_radius_m()});
    }
  }

  void reset(const Pose& start) override {
    if (dynamic_proxy_) dynamic_proxy_->reset(start);
    if (quasi_static_proxy_) quasi_static_proxy_->reset(start);
    planes_.clear();
    contacts_.clear();
    mailbox_.clear();
  }

  TickResult step(const DeviceSample& device) override {
    TickResult result;
    result.work.names = &PrimitiveWork::kNames;
    if (PlaneSet* installed = mailbox_.take(result.flags)) planes_.swap(*installed);

    Wrench raw;
    if (quasi_static_proxy_) {
      raw = step_quasi_static(device, result);
    } else {
      raw = step_dynamic(device, result);
    }
    result.display = device_output(raw, limits_, result.flags);
    result.proxy = tool_pose(body_, state());
    result.contacts = contacts_;
    return result;
  }

  SlowLoop* slow_loop() override { return slow_contacts_ ? this : nullptr; }

  std::unique_ptr<Result> run_slow_update() override {
    auto box = mailbox_.box();
    WorkCounters work;  // the slow loop's own cost is timed by the caller
    finder_.find(state(), kSlowMarginPerToolRadius * finder_.tool_radius_m(), box->data, work);
    return box;
  }

  void install_slow_result(std::unique_ptr<Result> result) override {
    mailbox_.install(std::move(result), "penalty_analytic");
  }

 private:
  // The massless proxy's frame: only the point the wrenches are taken about matters.
  static RigidBody contact_frame(const Tool& tool) {
    RigidBody frame;
    frame.centre_of_mass = tool.mass.centre_of_mass;
    return frame;
  }

  const RigidBodyState& state() const {
    return dynamic_proxy_ ? dynamic_proxy_->state() : quasi_static_proxy_->state();
  }

  Wrench step_dynamic(const DeviceSample& device, TickResult& result) {
    if (!slow_contacts_) {
      // Planes for every point that may reach the surface within this tick,
      // or at the device's pose (where a proxy in free space goes).
      const RigidBodyState& now = state();
      const Pose proxy = tool_pose(body_, now);
      const double radius = finder_.tool_radius_m();
      const double reach =
          std::max(dt_s_ * (now.v.norm() + now.w.norm() * radius),
                   (device.pose.p - proxy.p).norm() +
                       rotation_vector(device.pose.q * proxy.q.conjugate()).norm() * radius);
      planes_.clear();
      if (is_finite(now)) finder_.find(now, std::isfinite(reach) ? reach : 0, planes_, result.work);
    } else {
      result.work.add(PrimitiveWork::kPlanesEvaluated, static_cast<int64_t>(planes_.size()));
    }
    // The planes' penalty forces, clamped over the implicit step.
    plane_scratch_.clear();
    for (const PrimitiveContact& contact : planes_) plane_scratch_.push_back(contact.plane);
    contact_forces_.use(plane_scratch_, gains_);
    const Wrench raw = dynamic_proxy_->advance(device, &contact_forces_, result.flags);
    report_active(planes_);
    return raw;
  }

  Wrench step_quasi_static(const DeviceSample& device, TickResult& result) {
    if (slow_contacts_) {
      result.work.add(PrimitiveWork::kPlanesEvaluated, static_cast<int64_t>(planes_.size()));
      PlaneForces contacts(planes_, gains_);
      const Wrench raw = quasi_static_proxy_->advance(
          device, &contacts, result.flags, result.work.counts[PrimitiveWork::kNewtonSteps]);
      report_active(planes_);
      return raw;
    }
    FreshContactForces contacts(finder_, gains_, planes_, result.work);
    const Wrench raw = quasi_static_proxy_->advance(
        device, &contacts, result.flags, result.work.counts[PrimitiveWork::kNewtonSteps]);
    // The solver's last evaluation may have been a rejected trial: find the
    // contacts again at the pose it settled on.
    planes_.clear();
    finder_.find(state(), 0, planes_, result.work);
    report_active(planes_);
    return raw;
  }

  // Contacts at the proxy pose the tick reports, from the planes that acted.
  void report_active(const std::vector<PrimitiveContact>& planes) {
    contacts_.clear();
    for (const PrimitiveContact& plane : planes) {
      const Contact contact = PrimitiveContactFinder::report(plane, state());
      if (contact.depth > 0) contacts_.push_back(contact);
    }
  }

  DeviceLimits limits_;
  double dt_s_;
  bool slow_contacts_;
  RigidBody body_;
  PenaltyGains gains_;
  PrimitiveContactFinder finder_;
  std::optional<DynamicProxy> dynamic_proxy_;
  std::optional<QuasiStaticProxy> quasi_static_proxy_;
  /// The planes the haptic step evaluates: installed by the slow loop, or
  /// found by the haptic step itself (then also its scratch storage).
  std::vector<PrimitiveContact> planes_;
  std::vector<ContactPlane> plane_scratch_;  ///< planes_' planes, for the dynamic proxy's step
  PenaltyPlaneForces contact_forces_;        ///< the dynamic proxy's contacts, reused
  std::vector<Contact> contacts_;            ///< reported by the last step
  SlowLoopMailbox<PlaneSet> mailbox_;
};

}  // namespace

std::unique_ptr<Renderer> create_penalty_analytic(const RenderContext& context,
                                                  const ParamSet& params) {
  return std::make_unique<PenaltyAnalyticRenderer>(context, read_settings(context, params));
}

}  // namespace hb
