#include "harness/metrics/metric_table.h"

namespace hb {

namespace {

// Absolute tolerances per unit below which a change is never a regression
// (compare's rel_tol can only widen them).
constexpr double kForceAbsTolN = 1e-6;
constexpr double kAngleAbsTolDeg = 0.01;
constexpr double kTorqueAbsTolNm = 1e-9;
constexpr double kLengthAbsTolM = 1e-7;
constexpr double kEnergyAbsTolJ = 1e-9;

std::optional<double> count(int64_t value) { return static_cast<double>(value); }

std::optional<double> embree_penetration_max(const RunMetrics& m) {
  const OracleBackendMetrics* embree = m.oracle ? m.oracle->backend("embree") : nullptr;
  if (!embree) return std::nullopt;
  return embree->penetration_max_m;
}

// Read it like the registry: one row per metric.
constexpr MetricDefinition kMetrics[] = {
    // Timing: budgets only (compare has its own wall-clock and instruction checks).
    {"tick_p50_us", "/timing/step_ns/p50", "ns", Better::kLower, true, 1e-3, CompareRule::kNone, 0,
     false, [](const RunMetrics& m) -> std::optional<double> { return m.timing.step_ns.p50; },
     "median wall time of Renderer::step", true},
    {"tick_p99_us", "/timing/step_ns/p99", "ns", Better::kLower, true, 1e-3, CompareRule::kNone, 0,
     false, [](const RunMetrics& m) -> std::optional<double> { return m.timing.step_ns.p99; },
     "99th percentile of the wall time of Renderer::step", true},
    {"tick_p999_us", "/timing/step_ns/p999", "ns", Better::kLower, true, 1e-3, CompareRule::kNone,
     0, false, [](const RunMetrics& m) -> std::optional<double> { return m.timing.step_ns.p999; },
     "99.9th percentile of the wall time of Renderer::step"},
    {"tick_max_us", "/timing/step_ns/max", "ns", Better::kLower, true, 1e-3, CompareRule::kNone, 0,
     false, [](const RunMetrics& m) -> std::optional<double> { return m.timing.step_ns.max; },
     "longest Renderer::step"},
    {"cpu_per_tick_p99_us", "/timing/cpu_per_tick_ns/p99", "ns", Better::kLower, true, 1e-3,
     CompareRule::kNone, 0, false,
     [](const RunMetrics& m) -> std::optional<double> {
       return m.timing.cpu_per_tick_ns.percentiles.p99;
     },
     "99th percentile of the CPU time per tick of both loops (step + attributed slow work)", true},
    {"cpu_per_tick_mean_us", "/timing/cpu_per_tick_ns/mean", "ns", Better::kLower, true, 1e-3,
     CompareRule::kNone, 0, false,
     [](const RunMetrics& m) -> std::optional<double> { return m.timing.cpu_per_tick_ns.mean; },
     "mean CPU time per tick of both loops: what the algorithm costs the machine on average"},
    {"over_budget_ticks", "/timing/over_budget", "ticks", Better::kLower, true, 1,
     CompareRule::kNone, 0, false, [](const RunMetrics& m) { return count(m.timing.over_budget); },
     "ticks whose step took longer than 1 ms", true},
    // The slow loop of a multi-rate algorithm (absent without one).
    {"slow_update_p99_us", "/timing/slow_loop/update_ns/p99", "ns", Better::kLower, true, 1e-3,
     CompareRule::kNone, 0, true,
     [](const RunMetrics& m) -> std::optional<double> {
       if (!m.timing.slow_update_ns) return std::nullopt;
       return m.timing.slow_update_ns->p99;
     },
     "99th percentile of the wall time of one slow-loop update"},
    {"slow_updates_per_s", "/timing/slow_loop/rate_hz", "Hz", Better::kHigher, true, 1,
     CompareRule::kNone, 0, true, [](const RunMetrics& m) { return m.timing.slow_loop_rate_hz; },
     "slow-loop updates achieved per second of the replay's virtual time"},
    {"slow_updates_over_1ms_share", "/timing/slow_loop/updates_over_1ms_share", "fraction",
     Better::kLower, true, 1, CompareRule::kNone, 0, true,
     [](const RunMetrics& m) -> std::optional<double> {
       if (!m.timing.slow_updates_over_tick || !m.timing.slow_update_ns ||
           m.timing.slow_update_ns->count == 0)
         return std::nullopt;
       return static_cast<double>(*m.timing.slow_updates_over_tick) /
              static_cast<double>(m.timing.slow_update_ns->count);
     },
     "share of slow-loop updates that took longer than 1 ms"},
    // Accuracy against ground truth.
    {"force_err_rms_n", "/accuracy/force_err_rms_n", "N", Better::kLower, true, 1,
     CompareRule::kTolerance, kForceAbsTolN, false,
     [](const RunMetrics& m) { return m.accuracy.force_err_rms_n; },
     "RMS over the reference's ticks of ‖F − F_ideal‖ (the analytic reference, else the mesh "
     "force reference)",
     true},
    {"force_err_max_n", "/accuracy/force_err_max_n", "N", Better::kLower, true, 1,
     CompareRule::kTolerance, kForceAbsTolN, true,
     [](const RunMetrics& m) { return m.accuracy.force_err_max_n; },
     "largest ‖F − F_ideal‖ over the reference's ticks"},
    {"force_dir_err_deg", "/accuracy/force_dir_err_max_deg", "deg", Better::kLower, true, 1,
     CompareRule::kTolerance, kAngleAbsTolDeg, false,
     [](const RunMetrics& m) { return m.accuracy.force_dir_err_max_deg; },
     "largest angle between F and F_ideal on ticks under load", true},
    {"torque_err_rms_nm", "/accuracy/torque_err_rms_nm", "N·m", Better::kLower, true, 1,
     CompareRule::kTolerance, kTorqueAbsTolNm, false,
     [](const RunMetrics& m) { return m.accuracy.torque_err_rms_nm; },
     "RMS over the reference's ticks of ‖τ − τ_ideal‖ (about the tool origin)"},
    {"torque_err_max_nm", "/accuracy/torque_err_max_nm", "N·m", Better::kLower, true, 1,
     CompareRule::kTolerance, kTorqueAbsTolNm, true,
     [](const RunMetrics& m) { return m.accuracy.torque_err_max_nm; },
     "largest ‖τ − τ_ideal‖ over the reference's ticks"},
    {"max_penetration_m", "/accuracy/penetration_max_m", "m", Better::kLower, true, 1,
     CompareRule::kTolerance, kLengthAbsTolM, false,
     [](const RunMetrics& m) { return m.accuracy.penetration_max_m; },
     "deepest penetration of the proxy's tool into the scene (analytic, else Embree)", true},
    {"penetration_rms_m", "/accuracy/penetration_rms_m", "m", Better::kLower, true, 1,
     CompareRule::kTolerance, kLengthAbsTolM, false,
     [](const RunMetrics& m) { return m.accuracy.penetration_rms_m; },
     "RMS penetration over the ticks that penetrate"},
    {"embree_penetration_max_m", "/oracle/embree/penetration_max_m", "m", Better::kLower, false, 1,
     CompareRule::kTolerance, kLengthAbsTolM, true, &embree_penetration_max,
     "deepest tool sample inside the scene by the Embree oracle"},
    {"contact_normal_err_rms_deg", "/oracle/contact_normal_err_rms_deg", "deg", Better::kLower,
     true, 1, CompareRule::kTolerance, kAngleAbsTolDeg, true,
     [](const RunMetrics& m) {
       return m.oracle ? m.oracle->contact_normal_err_rms_deg : std::nullopt;
     },
     "RMS angle between the reported contact normals and the oracle's surface normals"},
    // Stability and passivity.
    {"nonfinite", "/stability/nonfinite", "ticks", Better::kLower, true, 1, CompareRule::kCount, 0,
     false, [](const RunMetrics& m) { return count(m.stability.nonfinite); },
     "ticks whose wrench was non-finite (zeroed before display)", true},
    {"diverged", "/stability/diverged", "flag", Better::kLower, true, 1, CompareRule::kFlag, 0,
     false,
     [](const RunMetrics& m) -> std::optional<double> { return m.stability.diverged ? 1.0 : 0.0; },
     "the proxy left the device by more than the divergence distance", true},
    {"passivity_energy_min_j", "/stability/passivity_energy_min_j", "J", Better::kHigher, true, 1,
     CompareRule::kTolerance, kEnergyAbsTolJ, false,
     [](const RunMetrics& m) -> std::optional<double> {
       return m.stability.passivity_energy_min_j;
     },
     "minimum over time of the port energy: the held wrench's work on the device, plus the "
     "coupling's store at the first tick (below zero: energy generated)",
     true},
    {"tunnelled", "/stability/tunnelled", "passes", Better::kLower, true, 1, CompareRule::kCount, 0,
     true,
     [](const RunMetrics& m) -> std::
                                 optional<double> {
                                   if (!m.stability.tunnelled) return std::nullopt;
                                   return static_cast<double>(*m.stability.tunnelled);
                                 },
     "ticks at which the proxy's tool (its origin or an extreme vertex) passed through a scene "
     "object (tunnelling)",
     true},
    {"energy_drift_j_per_s", "/stability/energy_drift_j_per_s", "J/s", Better::kHigher, false, 1,
     CompareRule::kTolerance, kEnergyAbsTolJ, true,
     [](const RunMetrics& m) { return m.stability.energy_drift_j_per_s; },
     "least-squares slope of the port energy over the run (below zero: energy generated "
     "steadily)"},
    {"proxy_chatter_m", "/stability/proxy_chatter_m", "m", Better::kLower, true, 1,
     CompareRule::kNone, 0, false,
     [](const RunMetrics& m) -> std::optional<double> { return m.stability.proxy_chatter_m; },
     "RMS tick-to-tick second difference of the proxy's position over the run's last quarter"},
    {"chatters", "/stability/chatters", "flag", Better::kLower, true, 1, CompareRule::kFlag, 0,
     true,
     [](const RunMetrics& m) -> std::optional<double> { return m.stability.chatters ? 1.0 : 0.0; },
     "the proxy still oscillates from tick to tick at the end of the run (proxy chatter above "
     "1 um and 10 times the device's)"},
    {"force_jump_max_n", "/stability/force_jump_max_n", "N", Better::kLower, true, 1,
     CompareRule::kTolerance, kForceAbsTolN, false,
     [](const RunMetrics& m) -> std::optional<double> { return m.stability.force_jump_max_n; },
     "largest change of the displayed force between two ticks"},
    // Closed loop (docs/closed-loop.md): what the device held by the hand did.
    {"limit_cycle", "/closed_loop/limit_cycle", "flag", Better::kLower, true, 1, CompareRule::kFlag,
     0, true,
     [](const RunMetrics& m) -> std::
                                 optional<double> {
                                   if (!m.closed_loop) return std::nullopt;
                                   return m.closed_loop->limit_cycles.limit_cycle ? 1.0 : 0.0;
                                 },
     "closed loop: the device keeps oscillating in contact (at least a quarter of the contact "
     "blocks, not dying out), an oscillation the intent does not explain",
     true},
    {"limit_cycle_amplitude_m", "/closed_loop/limit_cycle_amplitude_m", "m", Better::kLower, true,
     1, CompareRule::kTolerance, kLengthAbsTolM, true,
     [](const RunMetrics&
            m) { return m.closed_loop ? m.closed_loop->limit_cycles.amplitude_m : std::nullopt; },
     "closed loop: median amplitude of the device's oscillation over the oscillating contact "
     "blocks"},
    {"limit_cycle_frequency_hz", "/closed_loop/limit_cycle_frequency_hz", "Hz", Better::kLower,
     false, 1, CompareRule::kNone, 0, true,
     [](const RunMetrics&
            m) { return m.closed_loop ? m.closed_loop->limit_cycles.frequency_hz : std::nullopt; },
     "closed loop: median frequency of the device's oscillation over the oscillating contact "
     "blocks"},
    {"limit_cycle_share", "/closed_loop/limit_cycle_share", "fraction", Better::kLower, true, 1,
     CompareRule::kTolerance, 0.01, true,
     [](const RunMetrics& m) -> std::
                                 optional<double> {
                                   if (!m.closed_loop) return std::nullopt;
                                   return m.closed_loop->limit_cycles.share;
                                 },
     "closed loop: share of the contact blocks in which the device oscillates"},
    {"display_energy_min_j", "/closed_loop/display_energy_min_j", "J", Better::kHigher, true, 1,
     CompareRule::kTolerance, kEnergyAbsTolJ, true,
     [](const RunMetrics& m) -> std::optional<double> {
       if (!m.closed_loop) return std::nullopt;
       return m.closed_loop->display_energy_min_j;
     },
     "closed loop: minimum over time of the energy the hand put into the device through the "
     "grip (port energy plus the device's own kinetic energy and friction losses; below zero: "
     "the display gives energy to the hand)"},
    {"device_penetration_max_m", "/closed_loop/device_penetration_max_m", "m", Better::kLower, true,
     1, CompareRule::kTolerance, kLengthAbsTolM, true,
     [](const RunMetrics&
            m) { return m.closed_loop ? m.closed_loop->device_penetration_max_m : std::nullopt; },
     "closed loop: deepest penetration of the device's own tool pose into the scene"},
    {"displayed_stiffness_n_per_m", "/closed_loop/displayed_stiffness_n_per_m", "N/m",
     Better::kHigher, true, 1, CompareRule::kTolerance, 1.0, true,
     [](const RunMetrics&
            m) { return m.closed_loop ? m.closed_loop->displayed_stiffness_n_per_m : std::nullopt; },
     "closed loop: least-squares slope of the displayed force against the device's "
     "penetration (the stiffness the user feels)"},
    // Transparency.
    {"free_space_force_max_n", "/transparency/free_space_force_max_n", "N", Better::kLower, true, 1,
     CompareRule::kNone, 0, false,
     [](const RunMetrics& m) { return m.transparency.free_space_force_max_n; },
     "largest displayed force on free-space ticks"},
};

}  // namespace

std::span<const MetricDefinition> metric_table() { return kMetrics; }

const MetricDefinition* find_metric(std::string_view name) {
  for (const MetricDefinition& metric : kMetrics)
    if (metric.name == name) return &metric;
  return nullptr;
}

nlohmann::json metric_table_json() {
  nlohmann::json table = nlohmann::json::array();
  for (const MetricDefinition& metric : kMetrics)
    table.push_back({{"name", metric.name},
                     {"pointer", metric.json_pointer},
                     {"unit", metric.unit},
                     {"better", metric.better == Better::kLower ? "lower" : "higher"},
                     {"budget", metric.budget},
                     {"report_column", metric.report_column},
                     {"description", metric.description}});
  return table;
}

std::string metric_check_name(const MetricDefinition& metric) {
  std::string name(metric.json_pointer.substr(1));
  for (char& c : name)
    if (c == '/') c = '.';
  return name;
}

}  // namespace hb
