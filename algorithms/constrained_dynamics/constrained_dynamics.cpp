#include "algorithms/constrained_dynamics/constrained_dynamics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "algorithms/contact/constrained_step.h"
#include "algorithms/contact/contact_geometry.h"
#include "algorithms/contact/proximity_certifier.h"
#include "hapticbench/input_error.h"
#include "hapticbench/proxy/device_output.h"
#include "hapticbench/proxy/dynamic_proxy.h"
#include "hapticbench/proxy/integrator.h"
#include "hapticbench/proxy/proxy_settings.h"
#include "hapticbench/proxy/rigid_body.h"
#include "hapticbench/proxy/slow_loop_mailbox.h"
#include "hapticbench/proxy/virtual_coupling.h"

namespace hb {

namespace {

// A finished slow update on its way to the haptic loop.
struct Certification {
  ProximityCertificate certificate;
};

// Constrained dynamics' work counters (WorkCounters slots and names).
struct ConstrainedDynamicsWork {
  enum Slot : std::size_t {
    kPairsEvaluated,
    kSolverIterations,
    kUnconverged,
    kActiveContacts,
    kReachBounded,
    kCertificatesTaken,
    kCertificatesKept,
    kStartEscapes,
    kStartEscapeUm,
    kCoulombViolations,
    kSkewResolves,
    kProximitySearches,
    kProximitySearchesAhead,
  };
  // Each slot beside its name, so that the two cannot drift apart.
  static constexpr WorkCounters::Names kNames = [] {
    WorkCounters::Names names{};
    names[kPairsEvaluated] = "pairs_evaluated";
    names[kSolverIterations] = "solver_iterations";
    names[kUnconverged] = "solver_unconverged";
    names[kActiveContacts] = "active_contacts";
    names[kReachBounded] = "reach_bounded";
    names[kCertificatesTaken] = "certificates_taken";
    names[kCertificatesKept] = "certificates_kept";
    names[kStartEscapes] = "start_escapes";
    names[kStartEscapeUm] = "start_escape_um";
    names[kCoulombViolations] = "coulomb_violations";
    names[kSkewResolves] = "skew_resolves";
    names[kProximitySearches] = "proximity_searches";
    names[kProximitySearchesAhead] = "proximity_searches_ahead";
    return names;
  }();
};

class ConstrainedDynamicsRenderer : public Renderer, public SlowLoop {
 public:
  /// How far below the standoff a near pair may end a tick (m).
  static constexpr double kStandoffSlackM = 1e-7;
  /// Halvings of the fraction when a step is cut.
  static constexpr int kCutBisections = 20;

  ConstrainedDynamicsRenderer(const RenderContext& context,
                              const ConstrainedDynamicsSettings& settings)
      : settings_(settings),
        gains_(context.coupling),
        limits_(context.device),
        dt_s_(context.dt_s),
        body_(proxy_body(context.tool, settings.proxy_mass_kg, context.gravity)),
        geometry_(context.tool, context.scene, settings.contacts),
        certifier_(geometry_.ccd(), settings.contacts, geometry_.centre_of_mass()),
        solver_(settings.solver) {}

  void reset(const Pose& start) override {
    escape_ = geometry_.escape(start);
    escape_reported_ = false;
    state_ = state_at_rest(body_, escape_.pose);
    target_ = start;
    queries_.forget();
    certificate_ = certifier_.certify(queries_, escape_.pose, certifier_.widest_band());
    impulses_.assign(certificate_.pairs.size(), Vec3::Zero());
    warm_active_.clear();
    contacts_.clear();
    mailbox_.clear();
    previous_update_target_.reset();
    previous_update_proxy_.reset();
    last_device_.reset();
    at_device_now_ = false;
  }

  TickResult step(const DeviceSample& device) override {
    TickResult result;
    result.work.names = &ConstrainedDynamicsWork::kNames;
    if (!is_finite(device)) {
      result.flags |= kFlagNonFiniteZeroed;
      result.proxy = tool_pose(body_, state_);
      result.contacts = contacts_;
      return result;
    }
    target_ = device.pose;
    if (Certification* update = mailbox_.take(result.flags)) install(*update, result.work);

    const Pose start = certifier_.frames().com_frame(tool_pose(body_, state_));
    // A proxy that is the device stays it while nothing touches.
    const bool stays_at_device = at_device_now_ && follow_device(device, start, result.work);
    at_device_now_ = stays_at_device;
    if (!stays_at_device) solve_and_advance(device, start, result.work);
    last_device_ = device.pose;
    finish_step(device, result);
    return result;
  }

  // The tick's contact solve and the proxy's move; a proxy leaving contact
  // then becomes the device once its dynamics have brought it near enough
  // (display_allows_jump_to_device).
  void solve_and_advance(const DeviceSample& device, const Pose& start, WorkCounters& work) {
    const Mat6 effective_mass = free_step(device);
    const double reach_limit = build_rows(start, work);
    const std::span<const Vec3> warm(impulses_.data(), rows_.size());
    const ConstrainedStep& solved = solver_.solve_system(
        effective_mass, free_velocity_, rows_, friction_, warm_active_,
        std::all_of(warm.begin(), warm.end(), [](const Vec3& i) { return i.isZero(); })
            ? std::span<const Vec3>()
            : warm);
    work.add(ConstrainedDynamicsWork::kSolverIterations, solved.iterations);
    work.add(ConstrainedDynamicsWork::kUnconverged, solved.converged ? 0 : 1);
    work.add(ConstrainedDynamicsWork::kCoulombViolations,
             solved.coulomb_residual > kCoulombResidualTolerance);
    work.add(ConstrainedDynamicsWork::kSkewResolves, solved.skew_passes - 1);
    std::fill(impulses_.begin(), impulses_.end(), Vec3::Zero());
    for (std::size_t k = 0; k < rows_.size(); ++k) {
      impulses_[k] = solved.impulses[k];
      work.add(ConstrainedDynamicsWork::kActiveContacts, solved.impulses[k].x() > 0);
    }
    advance(start, solved.step, reach_limit, work);
    if (!last_device_ || !body_.gravity.isZero()) return;
    const Wrench display =
        evaluate_coupling(gains_, body_, state_, device.pose, device.twist, false).display;
    if (display_allows_jump_to_device(gains_, display, device.pose, *last_device_,
                                      certifier_.radius()))
      at_device_now_ = follow_device(device, start, work);
  }

  // The tick's display, proxy and contacts once the proxy has moved.
  void finish_step(const DeviceSample& device, TickResult& result) {
    if (!is_finite(state_)) {  // restart at rest where the device is, out of the scene
      state_ = state_at_rest(body_, geometry_.escape(device.pose).pose);
      certificate_ =
          certifier_.certify(queries_, tool_pose(body_, state_), certifier_.widest_band());
      impulses_.assign(certificate_.pairs.size(), Vec3::Zero());
      result.flags |= kFlagProxyReset;
    }
    const Wrench raw =
        evaluate_coupling(gains_, body_, state_, device.pose, device.twist, false).display;
    result.display = device_output(raw, limits_, result.flags);
    result.proxy = tool_pose(body_, state_);
    report_contacts(result);
    if (!escape_reported_ && escape_.escaped) {
      result.work.add(ConstrainedDynamicsWork::kStartEscapes);
      result.work.add(ConstrainedDynamicsWork::kStartEscapeUm,
                      std::llround(escape_.distance_m * 1e6));
    }
    escape_reported_ = true;
  }

  // Out of contact the proxy is the device (as DynamicProxy's
  // follow_device_in_free_space): when the move to the device's pose keeps
  // every pair it can bring near above its floor at the end (worst_margin,
  // exact distances) and stays within the certificate's reach, the proxy
  // goes there with the device's velocity, and the coupling displays
  // nothing. Not under gravity, whose weight the coupling displays.
  bool follow_device(const DeviceSample& device, const Pose& start, WorkCounters& work) {
    if (!body_.gravity.isZero()) return false;
    const RigidBodyState at_device = state_moving_with(body_, device.pose, device.twist);
    const Pose end = certifier_.frames().com_frame(tool_pose(body_, at_device));
    free_velocity_ = displacement(start, end) / dt_s_;
    const double reach_limit = build_rows(start, work);
    if (!rows_.empty() && worst_margin(end, work) < 0) return false;
    if (fraction_within_reach(certificate_.anchor, start, dt_s_ * free_velocity_,
                              certifier_.radius(), reach_limit) < 1)
      return false;
    std::fill(impulses_.begin(), impulses_.end(), Vec3::Zero());
    warm_active_.clear();
    moved_ = dt_s_ * free_velocity_;
    state_ = at_device;
    return true;
  }

  SlowLoop* slow_loop() override { return this; }

  BuildReport build_report() const override {
    BuildReport report;
    report.cache_hit = geometry_.ccd().cache_hit();
    report.memory_bytes = static_cast<int64_t>(geometry_.ccd().memory_bytes());
    return report;
  }

  // The proximity query at the proxy's pose, in a band from the device's
  // or the proxy's motion since the last update, whichever moved more (a
  // proxy sliding under gravity moves without the device; the widest band
  // for the first update).
  std::unique_ptr<Result> run_slow_update() override {
    auto box = mailbox_.box();
    const Pose proxy = tool_pose(body_, state_);
    const double band = previous_update_target_
                            ? std::max(certifier_.band_for(*previous_update_target_, target_),
                                       certifier_.band_for(*previous_update_proxy_, proxy))
                            : certifier_.widest_band();
    previous_update_target_ = target_;
    previous_update_proxy_ = proxy;
    box->data.certificate = certifier_.certify(queries_, proxy, band);
    return box;
  }

  void install_slow_result(std::unique_ptr<Result> result) override {
    mailbox_.install(std::move(result), "constrained_dynamics");
  }

 private:
  // Takes the new certificate when the proxy lies within its reach, and
  // carries each pair's impulse over to it for the warm start.
  void install(Certification& update, WorkCounters& work) {
    work.add(ConstrainedDynamicsWork::kProximitySearches, update.certificate.searches);
    work.add(ConstrainedDynamicsWork::kProximitySearchesAhead, update.certificate.ahead_searches);
    if (!certifier_.within_reach(update.certificate, tool_pose(body_, state_))) {
      work.add(ConstrainedDynamicsWork::kCertificatesKept);
      return;
    }
    work.add(ConstrainedDynamicsWork::kCertificatesTaken);
    carry_impulses(certificate_.pairs, impulses_, update.certificate.pairs, carried_);
    impulses_.swap(carried_);
    std::swap(certificate_, update.certificate);
  }

  // One contact row per listed pair that this tick's motion could bring
  // within the standoff, at the centre-of-mass pose `start`; returns how
  // far (point_reach from the anchor, m) the proxy may move this tick.
  // The certificate lists its pairs nearest first with their distances at
  // the anchor; a pair at distance d there is at least d − ρ away at the
  // start (ρ: the start's reach from the anchor), so only the nearest ones,
  // up to s + w + ρ with w twice the free motion's reach (at least the
  // contact distance), are evaluated, and the motion is held within the
  // first pair left out (which keeps at least w of room).
  double build_rows(const Pose& start, WorkCounters& work) {
    rows_.clear();
    friction_.clear();
    distances_.clear();
    const double standoff = settings_.contacts.standoff_m;
    const double radius = certifier_.radius();
    const double reach = point_reach(displacement(certificate_.anchor, start), radius);
    const double window = std::max(settings_.contacts.contact_distance_m,
                                   2 * point_reach(dt_s_ * free_velocity_, radius));
    double limit = certifier_.reach(certificate_);
    std::size_t near = 0;  // the pairs that may come within the window, a prefix
    for (; near < certificate_.pairs.size(); ++near)
      if (certificate_.distances[near] - reach > standoff + window) {
        limit = std::min(limit, certificate_.distances[near] - standoff);
        break;
      }
    certifier_.evaluate_listed(evaluation_, certificate_, near, start, evaluated_);
    work.add(ConstrainedDynamicsWork::kPairsEvaluated, static_cast<int64_t>(near));
    for (std::size_t k = 0; k < near; ++k) {
      const ContactFeatures& pair = certificate_.pairs[k];
      const PairContact& contact = evaluated_[k];
      const double gap = contact.distance - standoff;
      const double bound =
          gap >= 0 ? -gap / dt_s_
                   : std::min(settings_.stabilisation * -gap / dt_s_, settings_.max_correction_mps);
      rows_.push_back(GaussConstraint{contact.normal, contact.tool_point - start.p, bound});
      friction_.push_back(geometry_.friction()[pair.scene_object]);
      distances_.push_back(contact.distance);
    }
    return limit;
  }

  // The linearised implicit Euler step without contacts: sets free_velocity_
  // and returns the step's effective mass, which the contact solve uses
  // whole (not symmetric: gyroscopic and rotational-coupling terms).
  Mat6 free_step(const DeviceSample& device) {
    const ImplicitStepSystem system = implicit_step_system(
        body_, state_,
        evaluate_coupling(gains_, body_, state_, device.pose, device.twist, true).on_proxy, dt_s_);
    Vec6 velocity;
    velocity << state_.v, state_.w;
    free_velocity_ = velocity + system.matrix.partialPivLu().solve(system.rhs);
    return system.matrix;
  }

  // Moves the proxy by Δt u, within `reach_limit` of the certificate's anchor.
  // The rows are linear in the step: they miss a rotation's second-order
  // motion (a hook's tip beyond the centre of mass along the normal) and an
  // edge pair's closest points sliding along nearly parallel edges. So every
  // near pair's exact distance at the end is measured too, and a step that
  // takes one below its floor is cut to the largest fraction (to 2⁻²⁰)
  // that keeps every pair above (the start does), as the god-object's
  // haptic step is.
  void advance(const Pose& start, const Vec6& velocity, double reach_limit, WorkCounters& work) {
    const Vec6 step = dt_s_ * velocity;
    double fraction =
        fraction_within_reach(certificate_.anchor, start, step, certifier_.radius(), reach_limit);
    bool bounded = fraction < 1;
    if (!rows_.empty() && worst_margin(displaced(start, fraction * step), work) < 0) {
      double safe = 0, unsafe = fraction;
      for (int i = 0; i < kCutBisections; ++i) {
        const double middle = 0.5 * (safe + unsafe);
        (worst_margin(displaced(start, middle * step), work) >= 0 ? safe : unsafe) = middle;
      }
      fraction = safe;
      bounded = true;
    }
    if (bounded) work.add(ConstrainedDynamicsWork::kReachBounded);
    moved_ = fraction * step;
    const Pose end = displaced(start, moved_);
    state_.x = end.p;
    state_.q = end.q;
    state_.v = fraction * velocity.head<3>();
    state_.w = fraction * velocity.tail<3>();
  }

  // The least margin (m) of the near pairs above their floors at `end`:
  // each pair's exact distance there, signed by the side it started the
  // tick on (a pair whose direction between closest points turned over has
  // crossed), less min(standoff − kStandoffSlackM, its distance at the start).
  double worst_margin(const Pose& end, WorkCounters& work) {
    certifier_.evaluate_listed(evaluation_, certificate_, rows_.size(), end, end_contacts_);
    work.add(ConstrainedDynamicsWork::kPairsEvaluated, static_cast<int64_t>(rows_.size()));
    const double standoff_floor = settings_.contacts.standoff_m - kStandoffSlackM;
    double worst = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < rows_.size(); ++k) {
      const PairContact& contact = end_contacts_[k];
      const double side = contact.normal.dot(rows_[k].normal) >= 0 ? 1.0 : -1.0;
      worst = std::min(worst, side * contact.distance - std::min(standoff_floor, distances_[k]));
    }
    return worst;
  }

  // Pairs within the contact distance at the new pose, for the oracle.
  void report_contacts(TickResult& result) {
    contacts_.clear();
    const double moved_reach = point_reach(moved_, certifier_.radius());
    const Pose end = certifier_.frames().com_frame(result.proxy);
    const double contact_distance = settings_.contacts.contact_distance_m;
    reported_pairs_.clear();
    for (std::size_t k = 0; k < certificate_.pairs.size() && k < distances_.size(); ++k)
      if (distances_[k] <= contact_distance + moved_reach)
        reported_pairs_.push_back(certificate_.pairs[k]);
    certifier_.evaluate(evaluation_, reported_pairs_, end, reported_);
    for (const PairContact& contact : reported_) {
      if (contact.distance > contact_distance) continue;
      contacts_.push_back(Contact{contact.scene_point, contact.normal, -contact.distance});
    }
    result.contacts = contacts_;
  }

  ConstrainedDynamicsSettings settings_;
  CouplingGains gains_;
  DeviceLimits limits_;
  double dt_s_;
  RigidBody body_;
  ContactGeometry geometry_;  ///< the mesh CCD, the scene's friction and the start escape
  ProximityCertifier certifier_;
  /// The proximity queries' memory and scratch: the slow loop's, also used
  /// by reset and by the restart after a non-finite state (finish_step).
  ProximityCertifier::QueryWorkspace queries_;
  /// The haptic tick's scratch of the certifier's evaluations.
  ProximityCertifier::EvaluationWorkspace evaluation_;
  RigidBodyState state_;
  Pose target_;  ///< the latest finite device pose, read by the slow loop
  ProximityCertificate certificate_;
  std::vector<Vec3> impulses_;  ///< last tick's impulses, one per listed pair
  std::vector<Vec3> carried_;
  ConstrainedStepSolver solver_;
  std::vector<GaussConstraint> rows_;
  std::vector<double> friction_;           ///< μ per row
  std::vector<int> warm_active_;           ///< the frictionless solve's last active set
  std::vector<double> distances_;          ///< per listed pair at the start of the tick (m)
  std::vector<PairContact> evaluated_;     ///< the near pairs at the start of the tick (scratch)
  std::vector<PairContact> end_contacts_;  ///< the near pairs at a trial end (scratch)
  std::vector<ContactFeatures> reported_pairs_;  ///< report_contacts' candidates (scratch)
  std::vector<PairContact> reported_;            ///< and their contacts at the tick's end
  Vec6 free_velocity_ = Vec6::Zero();
  Vec6 moved_ = Vec6::Zero();
  std::vector<Contact> contacts_;
  SlowLoopMailbox<Certification> mailbox_;
  std::optional<Pose> previous_update_target_;  ///< the device's pose at the last slow update
  std::optional<Pose> previous_update_proxy_;   ///< the proxy's pose at the last slow update
  StartEscape escape_;
  bool escape_reported_ = false;
  std::optional<Pose> last_device_;  ///< the last finite device pose (tool frame)
  bool at_device_now_ = false;       ///< the proxy is the device (free space)
};

}  // namespace

ConstrainedDynamicsSettings read_constrained_dynamics_settings(const ParamSet& params,
                                                               const Tool& tool) {
  ConstrainedDynamicsSettings settings;
  const ContactSettings contact_defaults;
  if (params.has("max_iterations"))
    throw InputError("", params.field("max_iterations"),
                     "constrained_dynamics makes no slow-loop moves; its solver's limit is "
                     "\"solver_sweeps\"");
  settings.contacts = read_contact_settings(params, false, contact_defaults);
  settings.solver.max_sweeps =
      static_cast<int>(params.integer("solver_sweeps", settings.solver.max_sweeps, 1, 100000));
  settings.solver.tolerance = params.number("solver_tolerance", 1e-6, 0, 1.0);
  settings.stabilisation = params.number("stabilisation", settings.stabilisation, 0, 1);
  if (!(settings.stabilisation > 0))
    throw InputError("", params.field("stabilisation"), "expected a fraction in (0, 1]");
  settings.max_correction_mps =
      params.number("max_correction_speed", settings.max_correction_mps, 1e-6, 10);
  settings.proxy_mass_kg = read_proxy_mass(params, tool);
  return settings;
}

std::unique_ptr<Renderer> create_constrained_dynamics(const RenderContext& context,
                                                      const ParamSet& params) {
  return std::make_unique<ConstrainedDynamicsRenderer>(
      context, read_constrained_dynamics_settings(params, context.tool));
}

}  // namespace hb
