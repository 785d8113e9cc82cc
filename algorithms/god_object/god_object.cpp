#include "algorithms/god_object/god_object.h"

#include <cmath>
#include <optional>
#include <stdexcept>
#include <vector>

#include "algorithms/contact/contact_settings.h"
#include "algorithms/god_object/haptic_proxy.h"
#include "hapticbench/proxy/device_output.h"
#include "hapticbench/proxy/slow_loop_mailbox.h"
#include "hapticbench/proxy/virtual_coupling.h"

namespace hb {

namespace {

// A finished update on its way to the haptic loop: where its CCD-limited
// moves left the proxy, and the proximity certificate found there.
struct GodObjectUpdate {
  Pose proxy;
  ProximityCertificate certificate;
  GodObjectUpdateStats stats;
};

// The god-object's work counters (WorkCounters slots and names).
struct GodObjectWork {
  enum Slot : std::size_t {
    kCcdBoundTests,
    kCcdPrimitiveQueries,
    kQpIterations,
    kCcdMoves,
    kPairsEvaluated,
    kCcdBudgetHits,
    kCcdCertifiedMoves,
    kProximityQueries,
    kStartEscapes,
    kStartEscapeUm,
    kCoulombViolations,
    kProximitySearches,
    kProximitySearchesAhead,
  };
  // Each slot beside its name, so that the two cannot drift apart.
  static constexpr WorkCounters::Names kNames = [] {
    WorkCounters::Names names{};
    names[kCcdBoundTests] = "ccd_bound_tests";
    names[kCcdPrimitiveQueries] = "ccd_primitive_queries";
    names[kQpIterations] = "qp_iterations";
    names[kCcdMoves] = "ccd_moves";
    names[kPairsEvaluated] = "pairs_evaluated";
    names[kCcdBudgetHits] = "ccd_budget_hits";
    names[kCcdCertifiedMoves] = "ccd_certified_moves";
    names[kProximityQueries] = "proximity_queries";
    names[kStartEscapes] = "start_escapes";
    names[kStartEscapeUm] = "start_escape_um";
    names[kCoulombViolations] = "coulomb_violations";
    names[kProximitySearches] = "proximity_searches";
    names[kProximitySearchesAhead] = "proximity_searches_ahead";
    return names;
  }();
};

class GodObjectRenderer : public Renderer, public SlowLoop {
 public:
  GodObjectRenderer(const RenderContext& context, const GodObjectSettings& settings)
      : point_tool_(settings.point_tool),
        gains_(context.coupling),
        limits_(context.device),
        dt_s_(context.dt_s),
        solver_(context, settings),
        haptic_(solver_.geometry().ccd(), context.coupling, settings,
                solver_.geometry().centre_of_mass(), solver_.geometry().friction()) {
    body_.centre_of_mass = solver_.geometry().centre_of_mass();
  }

  // A start inside the scene (or within the standoff of it) is moved out
  // the shortest way found (ContactGeometry::escape); the first tick
  // reports it in the work counters start_escapes and start_escape_um.
  void reset(const Pose& start) override {
    escape_ = solver_.geometry().escape(start);
    escape_reported_ = false;
    solver_.reset(escape_.pose);
    haptic_.reset(escape_.pose, queries_);
    target_ = start;
    proxy_ = state_at_rest(body_, escape_.pose);
    mailbox_.clear();
    previous_update_target_.reset();
  }

  // Installs a finished update, then moves the proxy toward the device by
  // the constraint solve on the certificate's pairs (haptic_proxy.h); the
  // proxy's velocity, for the coupling's damping, is its motion this tick.
  TickResult step(const DeviceSample& device) override {
    TickResult result;
    if (is_finite(device)) target_ = device.pose;
    if (GodObjectUpdate* update = mailbox_.take(result.flags)) install_update(*update, result);
    const HapticSolveStats haptic = haptic_.step(target_);
    const RigidBodyState next = state_at_rest(body_, haptic_.pose());
    proxy_.v = (next.x - proxy_.x) / dt_s_;
    proxy_.w = rotation_vector(next.q * proxy_.q.conjugate()) / dt_s_;
    proxy_.x = next.x;
    proxy_.q = next.q;
    if (haptic_.contacts().empty() && is_finite(device)) {
      // Out of contact the proxy is the device: its velocity is the
      // device's own estimate, so that the coupling's damper compares like
      // with like (the device's filtered velocity against the proxy's raw
      // backward difference rattled at every encoder step: 63 mN peaks in
      // closed loop with the default device).
      proxy_.w = device.twist.w;
      proxy_.v = device.twist.v - proxy_.w.cross(com_to_tool_origin(body_, proxy_.q));
    }
    Wrench raw = evaluate_coupling(gains_, body_, proxy_, device.pose, device.twist, false).display;
    if (point_tool_) raw.torque.setZero();
    result.display = device_output(raw, limits_, result.flags);
    result.proxy = tool_pose(body_, proxy_);
    result.contacts = haptic_.contacts();
    result.work.names = &GodObjectWork::kNames;
    result.work.add(GodObjectWork::kPairsEvaluated, haptic.pairs_evaluated);
    result.work.add(GodObjectWork::kQpIterations, haptic.qp_iterations);
    result.work.add(GodObjectWork::kCoulombViolations, haptic.coulomb_violations);
    if (!escape_reported_ && escape_.escaped) {
      result.work.add(GodObjectWork::kStartEscapes);
      result.work.add(GodObjectWork::kStartEscapeUm, std::llround(escape_.distance_m * 1e6));
    }
    escape_reported_ = true;
    return result;
  }

  SlowLoop* slow_loop() override { return this; }

  BuildReport build_report() const override {
    BuildReport report;
    report.cache_hit = solver_.geometry().ccd().cache_hit();
    report.memory_bytes = static_cast<int64_t>(solver_.geometry().ccd().memory_bytes());
    return report;
  }

  // From the haptic proxy's pose: the proximity query there, then
  // CCD-limited moves toward the device (which also discover contacts),
  // checked on the query's pairs while they stay within its reach. The
  // certificate goes to the haptic loop when the moves ended within its
  // reach; otherwise a second query at the pose they reached.
  std::unique_ptr<Result> run_slow_update() override {
    auto box = mailbox_.box();
    GodObjectUpdate& update = box->data;
    const Pose start = haptic_.pose();
    solver_.move_proxy(start);
    // The first update has no earlier device pose to tell the speed: widest band.
    const double band = previous_update_target_
                            ? haptic_.band_for(*previous_update_target_, target_)
                            : haptic_.widest_band();
    previous_update_target_ = target_;
    update.certificate = haptic_.certify(queries_, start, band);
    update.stats = solver_.update(target_, &update.certificate);
    update.stats.certificates = 1;
    update.stats.proximity_searches = update.certificate.searches;
    update.stats.proximity_searches_ahead = update.certificate.ahead_searches;
    update.proxy = solver_.proxy_pose();
    if (!haptic_.within_reach(update.certificate, update.proxy)) {
      update.certificate = haptic_.certify(queries_, update.proxy, band);
      ++update.stats.certificates;
      update.stats.proximity_searches += update.certificate.searches;
      update.stats.proximity_searches_ahead += update.certificate.ahead_searches;
    }
    return box;
  }

  void install_slow_result(std::unique_ptr<Result> result) override {
    mailbox_.install(std::move(result), "god_object");
  }

 private:
  // Hands the update's certificate (and, when the haptic proxy has fallen
  // behind it, its pose) to the haptic proxy; counts the update's work.
  void install_update(GodObjectUpdate& update, TickResult& result) {
    const Pose before = haptic_.pose();
    haptic_.offer(std::move(update.certificate), update.proxy, target_);
    if (!(haptic_.pose().p == before.p && haptic_.pose().q.coeffs() == before.q.coeffs())) {
      // Took the slow loop's pose: the proxy's velocity (the coupling's
      // damping) is this tick's motion from there, not the jump.
      const RigidBodyState jumped = state_at_rest(body_, haptic_.pose());
      proxy_.x = jumped.x;
      proxy_.q = jumped.q;
    }
    // The slow update's work, counted on the tick that installs it.
    result.work.names = &GodObjectWork::kNames;
    result.work.add(GodObjectWork::kCcdBoundTests, update.stats.bv_tests);
    result.work.add(GodObjectWork::kCcdPrimitiveQueries, update.stats.primitive_queries);
    result.work.add(GodObjectWork::kQpIterations, update.stats.qp_iterations);
    result.work.add(GodObjectWork::kCcdMoves, update.stats.iterations);
    result.work.add(GodObjectWork::kCcdBudgetHits, update.stats.budget_hits);
    result.work.add(GodObjectWork::kCcdCertifiedMoves, update.stats.certified_moves);
    result.work.add(GodObjectWork::kProximityQueries, update.stats.certificates);
    result.work.add(GodObjectWork::kProximitySearches, update.stats.proximity_searches);
    result.work.add(GodObjectWork::kProximitySearchesAhead, update.stats.proximity_searches_ahead);
    result.work.add(GodObjectWork::kCoulombViolations, update.stats.coulomb_violations);
  }

  bool point_tool_;
  CouplingGains gains_;
  DeviceLimits limits_;
  double dt_s_;
  RigidBody body_;          ///< only its centre of mass matters: the coupling's lever arm
  GodObjectSolver solver_;  ///< owned by the slow loop
  HapticProxy haptic_;      ///< owned by the haptic loop; its pose is read by the slow loop
  /// The proximity queries' memory and scratch: owned by the slow loop
  /// (reset, with no update running, starts it afresh).
  ProximityCertifier::QueryWorkspace queries_;
  Pose target_;           ///< the latest finite device pose, read by the slow loop
  RigidBodyState proxy_;  ///< the displayed proxy: the haptic proxy's pose and velocity
  SlowLoopMailbox<GodObjectUpdate> mailbox_;
  std::optional<Pose> previous_update_target_;  ///< the device's pose at the last slow update
  StartEscape escape_;                          ///< how reset() moved the start, if it did
  bool escape_reported_ = false;
};

}  // namespace

GodObjectSettings read_god_object_settings(const ParamSet& params, bool point_tool,
                                           const GodObjectSettings& defaults) {
  GodObjectSettings settings = defaults;
  settings.point_tool = point_tool;
  read_contact_distances(params, settings);
  settings.max_iterations =
      static_cast<int>(params.integer("max_iterations", settings.max_iterations, 1, 1000));
  read_contact_discovery(params, settings);
  return settings;
}

std::unique_ptr<Renderer> create_god_object(const RenderContext& context, const ParamSet& params) {
  return std::make_unique<GodObjectRenderer>(context, read_god_object_settings(params, false));
}

std::unique_ptr<Renderer> create_god_object_3dof(const RenderContext& context,
                                                 const ParamSet& params) {
  return std::make_unique<GodObjectRenderer>(context, read_god_object_settings(params, true));
}

}  // namespace hb
