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
    {.name = "tick_p50_us",
     .json_pointer = "/timing/step_ns/p50",
     .unit = "ns",
     .budget_unit = "µs",
     .budget_scale = 1e-3,
     .read = [](const RunMetrics& m) -> std::optional<double> { return m.timing.step_ns.p50; },
     .description = "median wall time of Renderer::step",
     .report_column = true},
    {.name = "tick_p99_us",
     .json_pointer = "/timing/step_ns/p99",
     .unit = "ns",
     .budget_unit = "µs",
     .budget_scale = 1e-3,
     .read = [](const RunMetrics& m) -> std::optional<double> { return m.timing.step_ns.p99; },
     .description = "99th percentile of the wall time of Renderer::step",
     .report_column = true},
    {.name = "tick_p999_us",
     .json_pointer = "/timing/step_ns/p999",
     .unit = "ns",
     .budget_unit = "µs",
     .budget_scale = 1e-3,
     .read = [](const RunMetrics& m) -> std::optional<double> { return m.timing.step_ns.p999; },
     .description = "99.9th percentile of the wall time of Renderer::step"},
    {.name = "tick_max_us",
     .json_pointer = "/timing/step_ns/max",
     .unit = "ns",
     .budget_unit = "µs",
     .budget_scale = 1e-3,
     .read = [](const RunMetrics& m) -> std::optional<double> { return m.timing.step_ns.max; },
     .description = "longest Renderer::step"},
    {.name = "cpu_per_tick_p99_us",
     .json_pointer = "/timing/cpu_per_tick_ns/p99",
     .unit = "ns",
     .budget_unit = "µs",
     .budget_scale = 1e-3,
     .read = [](const RunMetrics& m) -> std::optional<double> {
       return m.timing.cpu_per_tick_ns.percentiles.p99;
     },
     .description =
         "99th percentile of the CPU time per tick of both loops (step + attributed slow work)",
     .report_column = true},
    {.name = "cpu_per_tick_mean_us",
     .json_pointer = "/timing/cpu_per_tick_ns/mean",
     .unit = "ns",
     .budget_unit = "µs",
     .budget_scale = 1e-3,
     .read = [](const RunMetrics& m) -> std::optional<double> {
       return m.timing.cpu_per_tick_ns.mean;
     },
     .description =
         "mean CPU time per tick of both loops: what the algorithm costs the machine on average"},
    {.name = "over_budget_ticks",
     .json_pointer = "/timing/over_budget",
     .unit = "ticks",
     .kind = ValueKind::kCount,
     .read = [](const RunMetrics& m) { return count(m.timing.over_budget); },
     .description = "ticks whose step took longer than 1 ms",
     .report_column = true},
    // The slow loop of a multi-rate algorithm (absent without one).
    {.name = "slow_update_p99_us",
     .json_pointer = "/timing/slow_loop/update_ns/p99",
     .unit = "ns",
     .budget_unit = "µs",
     .budget_scale = 1e-3,
     .compare_when_present = true,
     .read = [](const RunMetrics& m) -> std::optional<double> {
       if (!m.timing.slow_update_ns) return std::nullopt;
       return m.timing.slow_update_ns->p99;
     },
     .description = "99th percentile of the wall time of one slow-loop update"},
    {.name = "slow_updates_per_s",
     .json_pointer = "/timing/slow_loop/rate_hz",
     .unit = "Hz",
     .better = Better::kHigher,
     .compare_when_present = true,
     .read = [](const RunMetrics& m) { return m.timing.slow_loop_rate_hz; },
     .description = "slow-loop updates achieved per second of the replay's virtual time"},
    {.name = "slow_data_age_p99_ticks",
     .json_pointer = "/timing/slow_loop/data_age_p99_ticks",
     .unit = "ticks",
     .kind = ValueKind::kCount,
     .compare_when_present = true,
     .read = [](const RunMetrics& m) -> std::optional<double> {
       if (!m.timing.slow_data_age_p99_ticks) return std::nullopt;
       return static_cast<double>(*m.timing.slow_data_age_p99_ticks);
     },
     .description = "99th percentile over the ticks of how many ticks old the slow loop's data "
                    "the step used was (from the start of the update that made it)"},
    {.name = "slow_updates_over_1ms_share",
     .json_pointer = "/timing/slow_loop/updates_over_1ms_share",
     .unit = "fraction",
     .compare_when_present = true,
     .read = [](const RunMetrics& m) -> std::optional<double> {
       if (!m.timing.slow_updates_over_tick || !m.timing.slow_update_ns ||
           m.timing.slow_update_ns->count == 0)
         return std::nullopt;
       return static_cast<double>(*m.timing.slow_updates_over_tick) /
              static_cast<double>(m.timing.slow_update_ns->count);
     },
     .description = "share of slow-loop updates that took longer than 1 ms"},
    // Accuracy against ground truth.
    {.name = "force_err_rms_n",
     .json_pointer = "/accuracy/force_err_rms_n",
     .unit = "N",
     .compare = CompareRule::kTolerance,
     .abs_tol = kForceAbsTolN,
     .read = [](const RunMetrics& m) { return m.accuracy.force_err_rms_n; },
     .description =
         "RMS over the reference's ticks of ‖F − F_ideal‖ (the analytic reference, else the mesh "
         "force reference)",
     .report_column = true,
     .headline = "accuracy"},
    {.name = "force_err_max_n",
     .json_pointer = "/accuracy/force_err_max_n",
     .unit = "N",
     .compare = CompareRule::kTolerance,
     .abs_tol = kForceAbsTolN,
     .compare_when_present = true,
     .read = [](const RunMetrics& m) { return m.accuracy.force_err_max_n; },
     .description = "largest ‖F − F_ideal‖ over the reference's ticks"},
    {.name = "force_dir_err_deg",
     .json_pointer = "/accuracy/force_dir_err_max_deg",
     .unit = "deg",
     .compare = CompareRule::kTolerance,
     .abs_tol = kAngleAbsTolDeg,
     .read = [](const RunMetrics& m) { return m.accuracy.force_dir_err_max_deg; },
     .description = "largest angle between F and F_ideal on ticks under load",
     .report_column = true},
    {.name = "torque_err_rms_nm",
     .json_pointer = "/accuracy/torque_err_rms_nm",
     .unit = "N·m",
     .compare = CompareRule::kTolerance,
     .abs_tol = kTorqueAbsTolNm,
     .read = [](const RunMetrics& m) { return m.accuracy.torque_err_rms_nm; },
     .description = "RMS over the reference's ticks of ‖τ − τ_ideal‖ (about the tool origin)"},
    {.name = "torque_err_max_nm",
     .json_pointer = "/accuracy/torque_err_max_nm",
     .unit = "N·m",
     .compare = CompareRule::kTolerance,
     .abs_tol = kTorqueAbsTolNm,
     .compare_when_present = true,
     .read = [](const RunMetrics& m) { return m.accuracy.torque_err_max_nm; },
     .description = "largest ‖τ − τ_ideal‖ over the reference's ticks"},
    {.name = "max_penetration_mm",
     .json_pointer = "/accuracy/penetration_max_m",
     .unit = "m",
     .budget_unit = "mm",
     .budget_scale = 1e3,
     .compare = CompareRule::kTolerance,
     .abs_tol = kLengthAbsTolM,
     .read = [](const RunMetrics& m) { return m.accuracy.penetration_max_m; },
     .description =
         "deepest penetration of the proxy's tool into the scene (analytic, else Embree)",
     .report_column = true,
     .headline = "accuracy_fallback"},
    {.name = "penetration_rms_mm",
     .json_pointer = "/accuracy/penetration_rms_m",
     .unit = "m",
     .budget_unit = "mm",
     .budget_scale = 1e3,
     .compare = CompareRule::kTolerance,
     .abs_tol = kLengthAbsTolM,
     .read = [](const RunMetrics& m) { return m.accuracy.penetration_rms_m; },
     .description = "RMS penetration over the ticks that penetrate"},
    {.name = "crossing_ticks",
     .json_pointer = "/accuracy/crossing_ticks",
     .unit = "ticks",
     .kind = ValueKind::kCount,
     .compare = CompareRule::kCount,
     .compare_when_present = true,
     .read = [](const RunMetrics& m) -> std::optional<double> {
       if (!m.accuracy.crossing_ticks) return std::nullopt;
       return static_cast<double>(*m.accuracy.crossing_ticks);
     },
     .description =
         "scenes without inside/outside (distance_only): ticks at which the proxy's tool crosses "
         "the scene's surface (a tool and a scene triangle intersect, exact predicates)",
     .counted_as = "ticks with the tool crossing the scene's surface"},
    {.name = "embree_penetration_max_mm",
     .json_pointer = "/oracle/embree/penetration_max_m",
     .unit = "m",
     .budget = false,
     .budget_unit = "mm",
     .budget_scale = 1e3,
     .compare = CompareRule::kTolerance,
     .abs_tol = kLengthAbsTolM,
     .compare_when_present = true,
     .read = &embree_penetration_max,
     .description = "deepest tool sample inside the scene by the Embree oracle"},
    {.name = "contact_normal_err_rms_deg",
     .json_pointer = "/oracle/contact_normal_err_rms_deg",
     .unit = "deg",
     .compare = CompareRule::kTolerance,
     .abs_tol = kAngleAbsTolDeg,
     .compare_when_present = true,
     .read =
         [](const RunMetrics& m) {
           return m.oracle ? m.oracle->contact_normal_err_rms_deg : std::nullopt;
         },
     .description =
         "RMS angle between the reported contact normals and the oracle's surface normals"},
    // Stability and passivity.
    {.name = "nonfinite",
     .json_pointer = "/stability/nonfinite",
     .unit = "ticks",
     .kind = ValueKind::kCount,
     .compare = CompareRule::kCount,
     .read = [](const RunMetrics& m) { return count(m.stability.nonfinite); },
     .description = "ticks whose wrench was non-finite (zeroed before display)",
     .report_column = true,
     .counted_as = "ticks with a non-finite wrench"},
    {.name = "diverged",
     .json_pointer = "/stability/diverged",
     .unit = "flag",
     .kind = ValueKind::kFlag,
     .compare = CompareRule::kFlag,
     .read = [](const RunMetrics& m) -> std::optional<double> {
       return m.stability.diverged ? 1.0 : 0.0;
     },
     .description = "the proxy left the device by more than the divergence distance",
     .report_column = true},
    {.name = "passivity_energy_min_mj",
     .json_pointer = "/stability/passivity_energy_min_j",
     .unit = "J",
     .better = Better::kHigher,
     .budget_unit = "mJ",
     .budget_scale = 1e3,
     .compare = CompareRule::kGeneratedEnergy,
     .abs_tol = kEnergyAbsTolJ,
     .read = [](const RunMetrics& m) -> std::optional<double> {
       return m.stability.passivity_energy_min_j;
     },
     .description =
         "minimum over time of the port energy: the held wrench's work on the device, plus the "
         "coupling's store at the first tick (below zero: energy generated)",
     .report_column = true},
    {.name = "tunnelled",
     .json_pointer = "/stability/tunnelled",
     .unit = "passes",
     .kind = ValueKind::kCount,
     .compare = CompareRule::kCount,
     .compare_when_present = true,
     .read = [](const RunMetrics& m) -> std::optional<double> {
       if (!m.stability.tunnelled) return std::nullopt;
       return static_cast<double>(*m.stability.tunnelled);
     },
     .description =
         "ticks at which the proxy's tool (its origin or an extreme vertex) passed through a scene "
         "object (tunnelling)",
     .report_column = true,
     .counted_as = "passes through the scene"},
    {.name = "energy_drift_j_per_s",
     .json_pointer = "/stability/energy_drift_j_per_s",
     .unit = "J/s",
     .better = Better::kHigher,
     .budget = false,
     .compare = CompareRule::kGeneratedEnergy,
     .abs_tol = kEnergyAbsTolJ,
     .compare_when_present = true,
     .read = [](const RunMetrics& m) { return m.stability.energy_drift_j_per_s; },
     .description =
         "least-squares slope of the port energy over the run (below zero: energy generated "
         "steadily)"},
    {.name = "proxy_chatter_mm",
     .json_pointer = "/stability/proxy_chatter_m",
     .unit = "m",
     .budget_unit = "mm",
     .budget_scale = 1e3,
     .read = [](const RunMetrics& m) -> std::optional<double> {
       return m.stability.proxy_chatter_m;
     },
     .description =
         "RMS tick-to-tick second difference of the proxy's position over the run's last quarter"},
    {.name = "chatters",
     .json_pointer = "/stability/chatters",
     .unit = "flag",
     .kind = ValueKind::kFlag,
     .compare = CompareRule::kFlag,
     .compare_when_present = true,
     .read = [](const RunMetrics& m) -> std::optional<double> {
       return m.stability.chatters ? 1.0 : 0.0;
     },
     .description =
         "the proxy still oscillates from tick to tick at the end of the run (proxy chatter above "
         "1 um and 10 times the device's, over the last quarter and in at least half of its "
         "50-tick blocks)"},
    {.name = "force_jump_max_n",
     .json_pointer = "/stability/force_jump_max_n",
     .unit = "N",
     .compare = CompareRule::kTolerance,
     .abs_tol = kForceAbsTolN,
     .read = [](const RunMetrics& m) -> std::optional<double> {
       return m.stability.force_jump_max_n;
     },
     .description = "largest change of the displayed force between two ticks"},
    // Closed loop (docs/closed-loop.md): what the device held by the hand did.
    {.name = "limit_cycle",
     .json_pointer = "/closed_loop/limit_cycle",
     .unit = "flag",
     .kind = ValueKind::kFlag,
     .compare = CompareRule::kFlag,
     .compare_when_present = true,
     .read = [](const RunMetrics& m) -> std::optional<double> {
       if (!m.closed_loop) return std::nullopt;
       return m.closed_loop->limit_cycles.limit_cycle ? 1.0 : 0.0;
     },
     .description =
         "closed loop: the device keeps oscillating in contact (at least a quarter of the contact "
         "blocks, not dying out), an oscillation the intent does not explain",
     .report_column = true},
    {.name = "limit_cycle_amplitude_mm",
     .json_pointer = "/closed_loop/limit_cycle_amplitude_m",
     .unit = "m",
     .budget_unit = "mm",
     .budget_scale = 1e3,
     .compare = CompareRule::kTolerance,
     .abs_tol = kLengthAbsTolM,
     .compare_when_present = true,
     .read =
         [](const RunMetrics& m) {
           return m.closed_loop ? m.closed_loop->limit_cycles.amplitude_m : std::nullopt;
         },
     .description =
         "closed loop: median amplitude of the device's oscillation over the oscillating contact "
         "blocks"},
    {.name = "limit_cycle_frequency_hz",
     .json_pointer = "/closed_loop/limit_cycle_frequency_hz",
     .unit = "Hz",
     .budget = false,
     .compare_when_present = true,
     .read =
         [](const RunMetrics& m) {
           return m.closed_loop ? m.closed_loop->limit_cycles.frequency_hz : std::nullopt;
         },
     .description =
         "closed loop: median frequency of the device's oscillation over the oscillating contact "
         "blocks"},
    {.name = "limit_cycle_share",
     .json_pointer = "/closed_loop/limit_cycle_share",
     .unit = "fraction",
     .compare = CompareRule::kTolerance,
     .abs_tol = 0.01,
     .compare_when_present = true,
     .read = [](const RunMetrics& m) -> std::optional<double> {
       if (!m.closed_loop) return std::nullopt;
       return m.closed_loop->limit_cycles.share;
     },
     .description = "closed loop: share of the contact blocks in which the device oscillates"},
    {.name = "display_energy_min_mj",
     .json_pointer = "/closed_loop/display_energy_min_j",
     .unit = "J",
     .better = Better::kHigher,
     .budget_unit = "mJ",
     .budget_scale = 1e3,
     .compare = CompareRule::kTolerance,
     .abs_tol = kEnergyAbsTolJ,
     .compare_when_present = true,
     .read = [](const RunMetrics& m) -> std::optional<double> {
       if (!m.closed_loop) return std::nullopt;
       return m.closed_loop->display_energy_min_j;
     },
     .description =
         "closed loop: minimum over time of the energy the hand put into the device through the "
         "grip (port energy plus the device's own kinetic energy and friction losses; below zero: "
         "the display gives energy to the hand)"},
    {.name = "device_penetration_max_mm",
     .json_pointer = "/closed_loop/device_penetration_max_m",
     .unit = "m",
     .budget_unit = "mm",
     .budget_scale = 1e3,
     .compare = CompareRule::kTolerance,
     .abs_tol = kLengthAbsTolM,
     .compare_when_present = true,
     .read =
         [](const RunMetrics& m) {
           return m.closed_loop ? m.closed_loop->device_penetration_max_m : std::nullopt;
         },
     .description =
         "closed loop: deepest penetration of the device's own tool pose into the scene"},
    {.name = "displayed_stiffness_n_per_m",
     .json_pointer = "/closed_loop/displayed_stiffness_n_per_m",
     .unit = "N/m",
     .better = Better::kHigher,
     .compare = CompareRule::kTolerance,
     .abs_tol = 1.0,
     .compare_when_present = true,
     .read =
         [](const RunMetrics& m) {
           return m.closed_loop ? m.closed_loop->displayed_stiffness_n_per_m : std::nullopt;
         },
     .description = "closed loop: least-squares slope of the displayed force against the device's "
                    "penetration (the stiffness the user feels)"},
    // Transparency.
    {.name = "free_space_force_max_n",
     .json_pointer = "/transparency/free_space_force_max_n",
     .unit = "N",
     .read = [](const RunMetrics& m) { return m.transparency.free_space_force_max_n; },
     .description = "largest displayed force on free-space ticks"},
};

}  // namespace

std::span<const MetricDefinition> metric_table() { return kMetrics; }

const MetricDefinition* headline_metric(std::string_view role) {
  for (const MetricDefinition& metric : kMetrics)
    if (!role.empty() && metric.headline == role) return &metric;
  return nullptr;
}

const MetricDefinition* find_metric(std::string_view name) {
  for (const MetricDefinition& metric : kMetrics)
    if (metric.name == name) return &metric;
  return nullptr;
}

namespace {
/// Each rule's name for data and its meaning for people, by rule.
struct CompareRuleText {
  CompareRule rule;
  const char* name;
  const char* meaning;
};
constexpr CompareRuleText kCompareRuleTexts[] = {
    {CompareRule::kNone, "none", "-"},
    {CompareRule::kTolerance, "tolerance", "tolerance"},
    {CompareRule::kCount, "count", "any increase"},
    {CompareRule::kFlag, "flag", "false -> true"},
    {CompareRule::kGeneratedEnergy, "generated_energy", "tolerance below zero"},
};
const CompareRuleText& compare_rule_text(CompareRule rule) {
  for (const CompareRuleText& text : kCompareRuleTexts)
    if (text.rule == rule) return text;
  return kCompareRuleTexts[0];
}
}  // namespace

const char* compare_rule_name(CompareRule rule) { return compare_rule_text(rule).name; }
const char* compare_rule_meaning(CompareRule rule) { return compare_rule_text(rule).meaning; }

nlohmann::json metric_table_json() {
  nlohmann::json table = nlohmann::json::array();
  for (const MetricDefinition& metric : kMetrics)
    table.push_back({{"name", metric.name},
                     {"pointer", metric.json_pointer},
                     {"unit", metric.unit},
                     {"budget_unit", metric.budget_unit.empty() ? metric.unit : metric.budget_unit},
                     {"budget_scale", metric.budget_scale},
                     {"better", metric.better == Better::kLower ? "lower" : "higher"},
                     {"budget", metric.budget},
                     {"report_column", metric.report_column},
                     {"compare", compare_rule_name(metric.compare)},
                     {"abs_tol", metric.abs_tol},
                     {"headline", metric.headline},
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
