// Metrics of one algorithm over one replay, with the definitions DESIGN.md
// gives: timing, accuracy against ground truth, stability and passivity,
// transparency. A metric that does not apply is an empty optional (null in
// summary.json), never a made-up zero.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "hapticbench/pose.h"
#include "harness/metrics/limit_cycles.h"
#include "harness/metrics/passivity_energy.h"
#include "harness/metrics/percentiles.h"
#include "harness/metrics/spill_buffer.h"
#include "harness/reference/oracle_evaluation.h"
#include "harness/replay/replay.h"

namespace hb {

/// Ground truth for one tick, computed outside the timed window.
struct TickEvaluation {
  /// The ideal displayed wrench (N, N·m, tool origin): the analytic
  /// reference's, else the mesh force reference's on the ticks it evaluated.
  std::optional<Wrench> ideal_display;
  std::optional<double> penetration_m;  ///< proxy penetration into the scene by the reference (m)
  /// Scenes without inside/outside: whether the proxy's tool crosses the
  /// scene's surface (the primary oracle's; false with the tool's bounds
  /// clear of the scene); null where penetration is measured instead.
  std::optional<bool> crossing;
  std::optional<bool> reference_contact;       ///< the reference says the ideal proxy is in contact
  std::optional<OracleTickEvaluation> oracle;  ///< Embree / CGAL on the posed tool, when asked for
  /// Whether the proxy's tool origin has just passed through the scene
  /// (tunnelling.h: the analytic box where there is one, else the primary
  /// oracle); null without ground truth.
  std::optional<bool> tunnelled;
  /// Closed loop: the penetration of the device's own tool pose into the
  /// scene (m; the analytic reference's, else the primary oracle's).
  std::optional<double> device_penetration_m;
};

/// CPU time per tick of both loops together: the tick's step() plus, for
/// each slow update, its time spread evenly over the ticks from its start to
/// the installation of its result (the thread's work while the haptic loop
/// waits for it). What comparisons between algorithms use.
struct CpuPerTick {
  Percentiles percentiles;  ///< ns
  double mean = 0;          ///< ns
};

struct TimingMetrics {
  int64_t ticks = 0;
  Percentiles step_ns;  ///< all ticks
  /// step() times of at most 1000 ticks spread evenly over the run, in tick
  /// order: enough for a rank test against another run without its ticks CSV.
  std::vector<int64_t> step_ns_sample;
  int64_t over_budget = 0;                        ///< ticks whose step took longer than 1 ms
  std::optional<Percentiles> free_space_step_ns;  ///< ticks without contact
  std::optional<Percentiles> contact_step_ns;     ///< ticks with contact
  // Slow loop of a multi-rate algorithm; empty without one.
  std::optional<Percentiles> slow_update_ns;
  std::optional<double> slow_loop_rate_hz;         ///< updates per second of virtual time
  std::optional<int64_t> slow_updates_over_tick;   ///< updates that took longer than 1 ms
  std::optional<double> slow_data_age_mean_ticks;  ///< staleness of contact data seen by step()
  std::optional<int64_t> slow_data_age_max_ticks;
  /// Nearest-rank 99th percentile of the staleness over the ticks that had data.
  std::optional<int64_t> slow_data_age_p99_ticks;
  CpuPerTick cpu_per_tick_ns;
};

struct AccuracyMetrics {
  std::optional<double> force_err_rms_n;  ///< |F - F_ideal|, RMS over all ticks
  std::optional<double> force_err_max_n;
  /// angle(F, F_ideal) on ticks under load: |F_ideal| >= max(0.05 N, 10% of
  /// its peak in the run) and |F| >= 0.05 N
  std::optional<double> force_dir_err_rms_deg;
  std::optional<double> force_dir_err_max_deg;
  std::optional<double> torque_err_rms_nm;  ///< |tau - tau_ideal|, RMS over all ticks
  std::optional<double> torque_err_max_nm;
  std::optional<double> penetration_max_m;   ///< proxy penetration by the reference
  std::optional<double> penetration_rms_m;   ///< RMS over ticks with penetration > 0
  std::optional<int64_t> penetration_ticks;  ///< ticks with penetration > 0
  /// Scenes without inside/outside (every object distance_only): ticks at
  /// which the proxy's tool crosses (or exactly touches) the scene's
  /// surface, by the primary oracle; null on other scenes.
  std::optional<int64_t> crossing_ticks;
};

struct StabilityMetrics {
  int64_t nonfinite = 0;  ///< ticks whose wrench was non-finite (zeroed before display)
  bool diverged = false;  ///< proxy left the device by more than the divergence distance
  std::optional<int64_t> diverged_at_tick;
  int64_t proxy_resets = 0;     ///< ticks the renderer reset a non-finite proxy
  int64_t saturated_ticks = 0;  ///< ticks clipped to the device's force or torque limit
  double max_proxy_separation_m =
      0;  ///< max |x_proxy - x_device| of the tool frames (finite ticks)
  int64_t proxy_nonfinite_ticks = 0;  ///< ticks whose proxy pose (or its distance) was not finite
  /// J: minimum over the run of the port energy E (passivity_energy.h):
  /// the energy the device supplied through the held wrench, plus what the
  /// coupling stored at the first tick. Below zero: energy generated.
  double passivity_energy_min_j = 0;
  double passivity_energy_final_j = 0;  ///< J: E after the last tick
  double force_jump_max_n = 0;          ///< max |F(k) - F(k-1)|
  double force_hf_energy_fraction = 0;  ///< share of force signal energy above 100 Hz (no DC)
  /// J/s: the least-squares slope of the passivity energy E(t) over the
  /// run; negative when the rendering gives energy away steadily (drift),
  /// null for runs shorter than two ticks.
  std::optional<double> energy_drift_j_per_s;
  /// Ticks at which the proxy's tool (its origin or an extreme vertex) passed through a scene
  /// object (tunnelling.h); null where it is not measured (no ground truth).
  std::optional<int64_t> tunnelled;
  /// m: RMS over the last quarter of the run of the proxy tool origin's
  /// second difference |p(k+1) − 2 p(k) + p(k−1)|. A proxy that keeps
  /// oscillating from tick to tick (explicit Euler's bounded bouncing on a
  /// contact too stiff for it) shows here; a settled or smoothly moving
  /// proxy is near zero.
  double proxy_chatter_m = 0;
  /// m: the same for the device's tool origin as the renderer saw it (in
  /// closed loop the encoders' reading)
  double device_chatter_m = 0;
  /// The proxy still oscillates at the end of the run and the oscillation
  /// is not dying out: proxy_chatter_m > max(kChatterFloorM,
  /// kChatterDeviceRatio × device_chatter_m), in at least half of that
  /// quarter's blocks of ticks too (an oscillation, not one jump), and at
  /// least kChatterDecayRatio × its value over the quarter before.
  bool chatters = false;
};

inline constexpr double kChatterFloorM = 1e-6;  ///< m per tick², a relative 1 m/s²
inline constexpr double kChatterDeviceRatio = 10;
inline constexpr double kChatterDecayRatio = 0.9;

struct TransparencyMetrics {
  int64_t free_space_ticks = 0;
  std::optional<double> free_space_force_rms_n;  ///< displayed force in free space
  std::optional<double> free_space_force_max_n;
};

struct ContactMetrics {
  int64_t contact_ticks = 0;  ///< ticks with at least one reported contact
  int64_t max_contacts = 0;
  double mean_contacts = 0;  ///< over contact ticks
  /// The algorithm's work counters summed over the run, by name, in the
  /// order first seen.
  std::vector<std::pair<std::string, int64_t>> total_work;
};

/// One oracle backend over a run.
struct OracleBackendMetrics {
  std::string name;  ///< as in oracle_backends()
  int64_t ticks_evaluated = 0;
  double penetration_max_m = 0;  ///< deepest tool sample over the run
  double penetration_rms_m = 0;  ///< RMS over penetrating ticks of each tick's deepest sample
  int64_t penetrating_ticks = 0;
  int64_t inside_samples_max = 0;  ///< most tool samples inside the scene at one tick
  Percentiles evaluation_ns;       ///< cost per evaluated tick, apart from step()
};

struct OracleMetrics {
  /// Backends evaluated at least once, in oracle_backends() order.
  std::vector<OracleBackendMetrics> backends;
  int64_t broad_phase_skipped_ticks = 0;  ///< ticks with the tool's bounds clear of the scene
  int64_t inside_disagreements = 0;       ///< samples Embree and CGAL classified differently
  std::optional<double> intersection_volume_max_m3;
  int64_t volume_evaluations = 0;
  /// Distance-only scenes: the least and greatest of the per-tick distances
  /// from the tool to the scene (m) over the ticks evaluated.
  std::optional<double> distance_min_m;
  std::optional<double> distance_max_m;
  std::optional<Percentiles> volume_ns;
  int64_t contacts_checked = 0;  ///< reported contacts checked against the oracle
  std::optional<double> contact_normal_err_rms_deg;
  std::optional<double> contact_normal_err_max_deg;
  std::optional<double> contact_depth_err_rms_m;
  std::optional<double> contact_depth_err_max_m;  ///< largest |reported - oracle| depth

  /// The backend named `name`, or null when it was not evaluated.
  const OracleBackendMetrics* backend(std::string_view name) const {
    for (const OracleBackendMetrics& b : backends)
      if (b.name == name) return &b;
    return nullptr;
  }
};

/// Closed-loop replay only (docs/closed-loop.md): what the device held by
/// the hand did.
struct ClosedLoopMetrics {
  /// m: deepest penetration of the device's true tool pose into the scene;
  /// null without a reference that measures it.
  std::optional<double> device_penetration_max_m;
  /// N/m: the stiffness the user feels, the least-squares slope of the
  /// displayed force's magnitude against the device's penetration over the
  /// ticks with penetration (at least kMinStiffnessTicks, spanning at least
  /// kMinStiffnessSpanM and kMinStiffnessCounts encoder counts: over fewer
  /// counts the fit measures the encoder's staircase, +26 % at 2.6 counts);
  /// null otherwise, with displayed_stiffness_note saying why.
  std::optional<double> displayed_stiffness_n_per_m;
  std::string displayed_stiffness_note;
  LimitCycleMetrics limit_cycles;
  /// J: minimum over time of the energy the hand has put into the device
  /// through the grip: the port energy (passivity_energy_min_j's) plus what
  /// the device itself took in (its kinetic energy and friction losses).
  /// Below zero the display as a whole gives energy to the hand; Colgate &
  /// Schenkel's b > KT/2 + |B| is the condition that it never does.
  double display_energy_min_j = 0;
};

inline constexpr int64_t kMinStiffnessTicks = 10;
inline constexpr double kMinStiffnessSpanM = 1e-5;
inline constexpr double kMinStiffnessCounts = 10;

struct RunMetrics {
  TimingMetrics timing;
  AccuracyMetrics accuracy;
  StabilityMetrics stability;
  TransparencyMetrics transparency;
  ContactMetrics contacts;
  std::optional<OracleMetrics> oracle;           ///< empty when the scenario asks for no oracle
  std::optional<ClosedLoopMetrics> closed_loop;  ///< empty in open loop
};

struct MetricsSettings {
  double divergence_distance_m = 0.1;  ///< proxy-device separation that counts as divergence
  /// The scenario's coupling, for the energy it stores at the first tick
  /// (N/m, N·m/rad; 0: none counted).
  double coupling_k_t = 0, coupling_k_r = 0;
  /// Ticks the run will have (0: unknown), to spread the step-time sample
  /// evenly over the run without keeping every tick.
  int64_t expected_ticks = 0;
  /// Closed loop: the device's metrics are computed, with oscillations
  /// below this amplitude (m) not counted as limit cycles.
  bool closed_loop = false;
  double limit_cycle_floor_m = LimitCycleDetector::kDefaultFloorM;
  /// m: the device's encoder resolution (0: exact), which sets the span the
  /// displayed-stiffness fit needs.
  double encoder_m = 0;
  /// Values each timing percentile keeps exactly (StreamingPercentiles).
  std::size_t exact_percentile_capacity = StreamingPercentiles::kDefaultExactCapacity;
};

/// Accumulates ticks of one replay; finish() computes the metrics. Memory
/// does not grow with the run's length: percentiles are streamed
/// (StreamingPercentiles: exact up to exact_percentile_capacity values), and
/// the per-tick values that the end of the run needs (the force signal for
/// its spectrum, force pairs for the direction error) are spilled to a
/// temporary file past 1 MB each.
class MetricsAccumulator {
 public:
  explicit MetricsAccumulator(MetricsSettings settings);
  void add(const TickRecord& record, const TickEvaluation& evaluation);
  RunMetrics finish() const;

 private:
  // finish(), section by section: each fills its part of `m` from the sums.
  void finish_timing(RunMetrics& m) const;
  void finish_accuracy(RunMetrics& m) const;
  void finish_oracle(RunMetrics& m) const;
  void finish_force_spectrum(RunMetrics& m) const;
  void finish_chatter(RunMetrics& m) const;
  void finish_closed_loop(RunMetrics& m) const;
  void add_timing(const TickRecord& record, bool in_contact);
  void add_accuracy(const Wrench& display, const TickEvaluation& evaluation);
  /// Divergence, separation and the port energy; returns whether the proxy was finite.
  bool add_stability(const TickRecord& record, const Pose& device_at, const Wrench& display);
  void add_energy_fit(int64_t t_ns, double energy_j);
  void add_chatter(const Vec3& proxy_p, const Vec3& device_p);
  void add_work(const WorkCounters& work);
  void add_oracle(const OracleTickEvaluation& oracle);
  void add_closed_loop(const TickRecord& record, const TickEvaluation& evaluation,
                       const Vec3& force, bool in_contact, double port_energy_j);

  MetricsSettings settings_;
  PortEnergy port_energy_;
  struct BackendSums {
    StreamingPercentiles ns;
    double depth_sq = 0;
  };
  /// Indexed like oracle_backends(); empty until the backend is evaluated.
  std::vector<std::optional<OracleBackendMetrics>> backend_metrics_;
  std::vector<BackendSums> backend_sums_;
  StreamingPercentiles volume_ns_;
  double contact_normal_sq_ = 0, contact_depth_sq_ = 0;
  // Timing.
  int64_t ticks_ = 0;
  StreamingPercentiles step_ns_, free_step_ns_, contact_step_ns_, slow_ns_;
  std::vector<int64_t> step_ns_sample_;  ///< every sample_stride_-th tick's step time
  int64_t sample_stride_ = 1;
  /// A slow update's time spread over the ticks until its installation.
  struct CpuSpread {
    int64_t last_tick_index;
    double share_ns;
  };
  std::vector<CpuSpread> cpu_spreads_;  ///< those covering the current tick, oldest first
  StreamingPercentiles cpu_ns_;
  double cpu_sum_ns_ = 0;
  int64_t slow_age_sum_ = 0, slow_age_count_ = 0, slow_age_max_ = -1;
  StreamingPercentiles slow_age_;  ///< ticks
  int64_t slow_over_tick_ = 0;
  RunMetrics partial_;
  // Force signal and (ideal, displayed) force per reference tick, for finish().
  SpillBuffer<std::array<double, 3>> forces_;
  SpillBuffer<std::array<double, 6>> force_pairs_;
  double peak_ideal_force_n_ = 0;
  double force_err_sq_ = 0, torque_err_sq_ = 0, pen_sq_ = 0, free_force_sq_ = 0;
  int64_t ideal_ticks_ = 0, pen_ticks_ = 0, evaluated_pen_ticks_ = 0;
  int64_t contacts_sum_ = 0;
  // Streaming least-squares fit of the energy against time (Welford).
  int64_t energy_fit_n_ = 0;
  double energy_fit_mean_t_ = 0, energy_fit_mean_e_ = 0, energy_fit_cov_ = 0, energy_fit_var_t_ = 0;
  std::optional<Vec3> last_force_;
  // Chatter: the last two positions of the proxy's and the device's tool
  // origins (m, world), and sums of squared second differences per block of
  // kChatterBlockTicks ticks, so finish() can take the run's last quarter.
  // At most kMaxChatterBlocks blocks: past that, neighbouring blocks are
  // merged and the block length doubles, so memory stays bounded on long runs.
  static constexpr int64_t kChatterBlockTicks = 50;
  static constexpr std::size_t kMaxChatterBlocks = 4096;
  int64_t chatter_block_ticks_ = kChatterBlockTicks;
  std::array<Vec3, 2> last_proxy_p_, last_device_p_;
  int64_t positions_seen_ = 0;
  struct ChatterBlock {
    double proxy_sq = 0, device_sq = 0;
    int64_t ticks = 0;
  };
  std::vector<ChatterBlock> chatter_blocks_;
  // Closed loop: limit cycles, the deepest device penetration, and sums for
  // the displayed stiffness's least-squares fit (penetration d, force f).
  std::optional<LimitCycleDetector> limit_cycles_;
  std::optional<double> device_penetration_max_m_;
  double display_energy_min_j_ = 0;
  int64_t stiffness_n_ = 0;
  double stiffness_d_ = 0, stiffness_f_ = 0, stiffness_dd_ = 0, stiffness_df_ = 0;
  double stiffness_d_min_ = 0, stiffness_d_max_ = 0;
};

}  // namespace hb
