#include "harness/metrics/run_metrics.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "harness/metrics/spectrum.h"

namespace hb {

namespace {
constexpr double kDirectionThresholdN = 0.05;  // below this a force has no reliable direction
constexpr double kDirectionPeakShare = 0.1;    // direction counted under at least 10% of peak load
constexpr double kJitterCutoffHz = 100.0;
constexpr int64_t kStepSampleSize = 1000;  // step times kept for rank tests

double angle_deg(const Vec3& a, const Vec3& b) {
  const double c = std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0);
  return std::acos(c) * 180.0 / std::numbers::pi;
}

}  // namespace

MetricsAccumulator::MetricsAccumulator(MetricsSettings settings)
    : settings_(settings),
      port_energy_(settings.coupling_k_t, settings.coupling_k_r),
      volume_ns_(settings.exact_percentile_capacity),
      step_ns_(settings.exact_percentile_capacity),
      free_step_ns_(settings.exact_percentile_capacity),
      contact_step_ns_(settings.exact_percentile_capacity),
      slow_ns_(settings.exact_percentile_capacity),
      sample_stride_(
          std::max<int64_t>(1, (settings.expected_ticks + kStepSampleSize - 1) / kStepSampleSize)),
      cpu_ns_(settings.exact_percentile_capacity) {
  if (settings.closed_loop) limit_cycles_.emplace(settings.limit_cycle_floor_m);
}

void MetricsAccumulator::add_closed_loop(const TickRecord& record, const TickEvaluation& evaluation,
                                         const Vec3& force, bool in_contact, double port_energy_j) {
  display_energy_min_j_ = std::min(display_energy_min_j_, port_energy_j + record.device_absorbed_j);
  const Vec3& intent = record.intent ? record.intent->pose.p : record.device->pose.p;
  limit_cycles_->add(device_pose(record).p, intent, force, in_contact);
  if (!evaluation.device_penetration_m) return;
  const double d = *evaluation.device_penetration_m;
  device_penetration_max_m_ = std::max(device_penetration_max_m_.value_or(0.0), d);
  if (d <= 0) return;
  const double f = force.norm();
  stiffness_d_min_ = stiffness_n_ == 0 ? d : std::min(stiffness_d_min_, d);
  stiffness_d_max_ = std::max(stiffness_d_max_, d);
  ++stiffness_n_;
  stiffness_d_ += d;
  stiffness_f_ += f;
  stiffness_dd_ += d * d;
  stiffness_df_ += d * f;
}

void MetricsAccumulator::add_timing(const TickRecord& record, bool in_contact) {
  const int64_t index = ticks_++;
  step_ns_.add(record.step_ns);
  if (record.step_ns > kTickNs) ++partial_.timing.over_budget;
  (in_contact ? contact_step_ns_ : free_step_ns_).add(record.step_ns);
  if (index % sample_stride_ == 0) {
    if (step_ns_sample_.size() == kStepSampleSize) {
      // Longer than expected: keep every other sample, at twice the stride.
      for (std::size_t i = 0; 2 * i < step_ns_sample_.size(); ++i)
        step_ns_sample_[i] = step_ns_sample_[2 * i];
      step_ns_sample_.resize(kStepSampleSize / 2);
      sample_stride_ *= 2;
    }
    if (index % sample_stride_ == 0) step_ns_sample_.push_back(record.step_ns);
  }
  // CPU time of the tick: its step plus its share of each slow update that
  // covers it (spread from the update's start to its installation).
  if (record.slow_started) {
    slow_ns_.add(record.slow_ns);
    if (record.slow_ns > kTickNs) ++slow_over_tick_;
    const int64_t latency = std::max<int64_t>(1, record.slow_latency_ticks);
    cpu_spreads_.push_back(
        {index + latency - 1, static_cast<double>(record.slow_ns) / static_cast<double>(latency)});
  }
  double cpu_ns = static_cast<double>(record.step_ns);
  for (const CpuSpread& spread : cpu_spreads_) cpu_ns += spread.share_ns;
  std::erase_if(cpu_spreads_, [index](const CpuSpread& s) { return s.last_tick_index <= index; });
  cpu_ns_.add(std::llround(cpu_ns));
  cpu_sum_ns_ += cpu_ns;
  if (record.slow_data_age_ticks >= 0) {
    slow_age_sum_ += record.slow_data_age_ticks;
    ++slow_age_count_;
    slow_age_max_ = std::max(slow_age_max_, record.slow_data_age_ticks);
    slow_age_.add(record.slow_data_age_ticks);
  }
}

void MetricsAccumulator::add(const TickRecord& record, const TickEvaluation& evaluation) {
  const TickResult& result = record.result;
  const DeviceSample& device = *record.device;
  // Energy and separation are the physical device's: in closed loop its
  // true pose, not the encoders' reading the renderer saw. Chatter compares
  // the proxy with what the renderer saw (a proxy following a quantized
  // reading steps with it).
  const Pose& device_at = device_pose(record);

  // Harness-side guard: a renderer must never display non-finite numbers,
  // but if one does, the run counts it and uses zero instead.
  Wrench display = result.display;
  const bool nonfinite = !is_finite(display) || (result.flags & kFlagNonFiniteZeroed);
  if (!is_finite(display)) display = Wrench{};
  if (nonfinite) ++partial_.stability.nonfinite;
  if (result.flags & kFlagProxyReset) ++partial_.stability.proxy_resets;
  if (result.flags & (kFlagForceSaturated | kFlagTorqueSaturated))
    ++partial_.stability.saturated_ticks;

  if (evaluation.tunnelled)
    partial_.stability.tunnelled = partial_.stability.tunnelled.value_or(0) + *evaluation.tunnelled;
  const bool reported_contact = !result.contacts.empty();
  const bool in_contact = reported_contact || evaluation.reference_contact.value_or(false);
  add_timing(record, in_contact);
  add_accuracy(display, evaluation);

  if (add_stability(record, device_at, display))
    add_chatter(result.proxy.p, device.pose.p);
  else
    positions_seen_ = 0;  // a reset proxy starts afresh
  if (last_force_) {
    partial_.stability.force_jump_max_n =
        std::max(partial_.stability.force_jump_max_n, (display.force - *last_force_).norm());
  }
  last_force_ = display.force;
  forces_.push_back({display.force.x(), display.force.y(), display.force.z()});

  // Transparency: what the user feels when nothing is touched.
  if (!in_contact) {
    ++partial_.transparency.free_space_ticks;
    const double f = display.force.norm();
    free_force_sq_ += f * f;
    partial_.transparency.free_space_force_max_n =
        std::max(partial_.transparency.free_space_force_max_n.value_or(0.0), f);
  }

  if (reported_contact) {
    ++partial_.contacts.contact_ticks;
    const auto n = static_cast<int64_t>(result.contacts.size());
    contacts_sum_ += n;
    partial_.contacts.max_contacts = std::max(partial_.contacts.max_contacts, n);
  }
  add_work(result.work);
  if (evaluation.oracle) add_oracle(*evaluation.oracle);
  if (limit_cycles_)
    add_closed_loop(record, evaluation, display.force, in_contact, port_energy_.energy_j());
}

// Accuracy against the reference (analytic, else the mesh force reference).
void MetricsAccumulator::add_accuracy(const Wrench& display, const TickEvaluation& evaluation) {
  if (evaluation.ideal_display) {
    ++ideal_ticks_;
    const Wrench& ideal = *evaluation.ideal_display;
    const double force_err = (display.force - ideal.force).norm();
    force_err_sq_ += force_err * force_err;
    partial_.accuracy.force_err_max_n =
        std::max(partial_.accuracy.force_err_max_n.value_or(0.0), force_err);
    const double torque_err = (display.torque - ideal.torque).norm();
    torque_err_sq_ += torque_err * torque_err;
    partial_.accuracy.torque_err_max_nm =
        std::max(partial_.accuracy.torque_err_max_nm.value_or(0.0), torque_err);
    force_pairs_.push_back({ideal.force.x(), ideal.force.y(), ideal.force.z(), display.force.x(),
                            display.force.y(), display.force.z()});
    peak_ideal_force_n_ = std::max(peak_ideal_force_n_, ideal.force.norm());
  }
  if (evaluation.penetration_m) {
    ++evaluated_pen_ticks_;
    const double depth = *evaluation.penetration_m;
    partial_.accuracy.penetration_max_m =
        std::max(partial_.accuracy.penetration_max_m.value_or(0.0), depth);
    if (depth > 0) {
      pen_sq_ += depth * depth;
      ++pen_ticks_;
    }
  }
  if (evaluation.crossing)
    partial_.accuracy.crossing_ticks =
        partial_.accuracy.crossing_ticks.value_or(0) + (*evaluation.crossing ? 1 : 0);
}

// Stability and passivity (the port energy: passivity_energy.h).
bool MetricsAccumulator::add_stability(const TickRecord& record, const Pose& device_at,
                                       const Wrench& display) {
  const TickResult& result = record.result;
  // A finite proxy far enough away overflows the distance: that counts as non-finite too.
  const double raw_separation_m = (result.proxy.p - device_at.p).norm();
  const bool proxy_finite = is_finite(result.proxy) && std::isfinite(raw_separation_m);
  if (!proxy_finite) ++partial_.stability.proxy_nonfinite_ticks;
  const double separation_m = proxy_finite ? raw_separation_m : 0.0;
  partial_.stability.max_proxy_separation_m =
      std::max(partial_.stability.max_proxy_separation_m, separation_m);
  if (!partial_.stability.diverged &&
      (!proxy_finite || separation_m > settings_.divergence_distance_m ||
       (result.flags & kFlagProxyReset))) {
    partial_.stability.diverged = true;
    partial_.stability.diverged_at_tick = record.device->tick;
  }
  const double energy = port_energy_.add(display, device_at);
  partial_.stability.passivity_energy_min_j =
      std::min(partial_.stability.passivity_energy_min_j, energy);
  partial_.stability.passivity_energy_final_j = energy;
  add_energy_fit(record.device->t_ns, energy);
  return proxy_finite;
}

// Running sums of the least-squares line of the port energy against time.
void MetricsAccumulator::add_energy_fit(int64_t t_ns, double energy_j) {
  const double t = 1e-9 * static_cast<double>(t_ns);
  ++energy_fit_n_;
  const double n = static_cast<double>(energy_fit_n_);
  const double dt_mean = t - energy_fit_mean_t_;
  energy_fit_mean_t_ += dt_mean / n;
  energy_fit_mean_e_ += (energy_j - energy_fit_mean_e_) / n;
  energy_fit_cov_ += dt_mean * (energy_j - energy_fit_mean_e_);
  energy_fit_var_t_ += dt_mean * (t - energy_fit_mean_t_);
}

// The second differences of the proxy's and the device's positions, summed
// in blocks (merged pairwise when there are too many, so memory stays
// bounded over any run).
void MetricsAccumulator::add_chatter(const Vec3& proxy_p, const Vec3& device_p) {
  if (positions_seen_ >= 2) {
    if (chatter_blocks_.empty() || chatter_blocks_.back().ticks == chatter_block_ticks_) {
      if (chatter_blocks_.size() == kMaxChatterBlocks) {
        for (std::size_t i = 0; i < kMaxChatterBlocks / 2; ++i) {
          const ChatterBlock& a = chatter_blocks_[2 * i];
          const ChatterBlock& b = chatter_blocks_[2 * i + 1];
          chatter_blocks_[i] = {a.proxy_sq + b.proxy_sq, a.device_sq + b.device_sq,
                                a.ticks + b.ticks};
        }
        chatter_blocks_.resize(kMaxChatterBlocks / 2);
        chatter_block_ticks_ *= 2;
      }
      chatter_blocks_.emplace_back();
    }
    ChatterBlock& block = chatter_blocks_.back();
    block.proxy_sq += (proxy_p - 2 * last_proxy_p_[1] + last_proxy_p_[0]).squaredNorm();
    block.device_sq += (device_p - 2 * last_device_p_[1] + last_device_p_[0]).squaredNorm();
    ++block.ticks;
  }
  last_proxy_p_ = {last_proxy_p_[1], proxy_p};
  last_device_p_ = {last_device_p_[1], device_p};
  ++positions_seen_;
}

// The renderer's work counters, summed by name over the run.
void MetricsAccumulator::add_work(const WorkCounters& work) {
  if (!work.names) return;
  for (std::size_t i = 0; i < WorkCounters::kSlots; ++i) {
    const std::string_view name = (*work.names)[i];
    if (name.empty()) continue;
    auto& totals = partial_.contacts.total_work;
    auto it = std::find_if(totals.begin(), totals.end(),
                           [&](const auto& entry) { return entry.first == name; });
    if (it == totals.end()) it = totals.emplace(totals.end(), std::string(name), 0);
    it->second += work.counts[i];
  }
}

namespace {
void add_backend(std::optional<OracleBackendMetrics>& metrics, std::string_view name,
                 const PenetrationResult& result, int64_t ns, StreamingPercentiles& all_ns,
                 double& depth_sq) {
  if (!metrics) metrics.emplace().name = name;
  ++metrics->ticks_evaluated;
  all_ns.add(ns);
  metrics->inside_samples_max = std::max(metrics->inside_samples_max, result.inside);
  if (result.inside > 0) {
    ++metrics->penetrating_ticks;
    metrics->penetration_max_m = std::max(metrics->penetration_max_m, result.max_depth_m);
    depth_sq += result.max_depth_m * result.max_depth_m;
  }
}
}  // namespace

void MetricsAccumulator::add_oracle(const OracleTickEvaluation& oracle) {
  if (!partial_.oracle) partial_.oracle.emplace();
  OracleMetrics& m = *partial_.oracle;
  if (oracle.broad_phase_skipped) ++m.broad_phase_skipped_ticks;
  const auto entries = oracle_backends();
  backend_metrics_.resize(entries.size());
  while (backend_sums_.size() < entries.size())
    backend_sums_.push_back({StreamingPercentiles(settings_.exact_percentile_capacity), 0.0});
  for (std::size_t i = 0; i < oracle.backends.size(); ++i) {
    if (!oracle.backends[i]) continue;
    add_backend(backend_metrics_[i], entries[i].name, oracle.backends[i]->result,
                oracle.backends[i]->ns, backend_sums_[i].ns, backend_sums_[i].depth_sq);
  }
  m.inside_disagreements += oracle.inside_disagreements;
  if (oracle.min_distance_m) {
    m.distance_min_m =
        std::min(m.distance_min_m.value_or(*oracle.min_distance_m), *oracle.min_distance_m);
    m.distance_max_m =
        std::max(m.distance_max_m.value_or(*oracle.min_distance_m), *oracle.min_distance_m);
  }
  if (oracle.intersection_volume_m3) {
    ++m.volume_evaluations;
    volume_ns_.add(oracle.volume_ns);
    m.intersection_volume_max_m3 =
        std::max(m.intersection_volume_max_m3.value_or(0.0), *oracle.intersection_volume_m3);
  }
  for (const ContactCheck& check : oracle.contact_checks) {
    ++m.contacts_checked;
    contact_normal_sq_ += check.normal_error_deg * check.normal_error_deg;
    contact_depth_sq_ += check.depth_error_m * check.depth_error_m;
    m.contact_normal_err_max_deg =
        std::max(m.contact_normal_err_max_deg.value_or(0.0), check.normal_error_deg);
    m.contact_depth_err_max_m =
        std::max(m.contact_depth_err_max_m.value_or(0.0), std::abs(check.depth_error_m));
  }
}

RunMetrics MetricsAccumulator::finish() const {
  RunMetrics m = partial_;
  finish_timing(m);
  finish_accuracy(m);
  finish_oracle(m);
  finish_force_spectrum(m);
  finish_chatter(m);
  if (energy_fit_n_ >= 2 && energy_fit_var_t_ > 0)
    m.stability.energy_drift_j_per_s = energy_fit_cov_ / energy_fit_var_t_;
  finish_closed_loop(m);
  return m;
}

// Step and CPU times, the slow loop's rate and its data's age.
void MetricsAccumulator::finish_timing(RunMetrics& m) const {
  m.timing.ticks = ticks_;
  m.timing.step_ns = step_ns_.result();
  m.timing.step_ns_sample = step_ns_sample_;
  if (free_step_ns_.count() > 0) m.timing.free_space_step_ns = free_step_ns_.result();
  if (contact_step_ns_.count() > 0) m.timing.contact_step_ns = contact_step_ns_.result();
  m.timing.cpu_per_tick_ns.percentiles = cpu_ns_.result();
  m.timing.cpu_per_tick_ns.mean = ticks_ == 0 ? 0 : cpu_sum_ns_ / static_cast<double>(ticks_);
  if (slow_ns_.count() > 0) {
    m.timing.slow_update_ns = slow_ns_.result();
    const double seconds =
        static_cast<double>(m.timing.ticks) * 1e-9 * static_cast<double>(kTickNs);
    m.timing.slow_loop_rate_hz = static_cast<double>(slow_ns_.count()) / seconds;
    m.timing.slow_updates_over_tick = slow_over_tick_;
  }
  if (slow_age_count_ > 0) {
    m.timing.slow_data_age_mean_ticks =
        static_cast<double>(slow_age_sum_) / static_cast<double>(slow_age_count_);
    m.timing.slow_data_age_max_ticks = slow_age_max_;
    m.timing.slow_data_age_p99_ticks = std::llround(slow_age_.result().p99);
  }
}

// Force and torque error against the ideal, direction error under load, penetration,
// free-space force, contacts per contact tick.
void MetricsAccumulator::finish_accuracy(RunMetrics& m) const {
  if (ideal_ticks_ > 0) {
    m.accuracy.force_err_rms_n = std::sqrt(force_err_sq_ / static_cast<double>(ideal_ticks_));
    m.accuracy.torque_err_rms_nm = std::sqrt(torque_err_sq_ / static_cast<double>(ideal_ticks_));
  }
  // Direction error under load: ticks where the ideal force is at least
  // 10% of its peak in the run (and >= 0.05 N) and the rendered force is
  // not negligible; near contact onset and release a direction means little.
  const double threshold =
      std::max(kDirectionThresholdN, kDirectionPeakShare * peak_ideal_force_n_);
  double dir_err_sq = 0;
  int64_t dir_err_count = 0;
  force_pairs_.for_each([&](const std::array<double, 6>& pair) {
    const Vec3 ideal(pair[0], pair[1], pair[2]);
    const Vec3 rendered(pair[3], pair[4], pair[5]);
    if (ideal.norm() < threshold || rendered.norm() < kDirectionThresholdN) return;
    const double angle = angle_deg(rendered, ideal);
    dir_err_sq += angle * angle;
    ++dir_err_count;
    m.accuracy.force_dir_err_max_deg =
        std::max(m.accuracy.force_dir_err_max_deg.value_or(0.0), angle);
  });
  if (dir_err_count > 0) {
    m.accuracy.force_dir_err_rms_deg = std::sqrt(dir_err_sq / static_cast<double>(dir_err_count));
  }
  if (evaluated_pen_ticks_ > 0) {
    m.accuracy.penetration_ticks = pen_ticks_;
    m.accuracy.penetration_rms_m =
        pen_ticks_ > 0 ? std::sqrt(pen_sq_ / static_cast<double>(pen_ticks_)) : 0.0;
  }
  if (m.transparency.free_space_ticks > 0) {
    m.transparency.free_space_force_rms_n =
        std::sqrt(free_force_sq_ / static_cast<double>(m.transparency.free_space_ticks));
  }
  if (m.contacts.contact_ticks > 0) {
    m.contacts.mean_contacts =
        static_cast<double>(contacts_sum_) / static_cast<double>(m.contacts.contact_ticks);
  }
}

// Each oracle backend's figures, the intersection volume's time, contact checks.
void MetricsAccumulator::finish_oracle(RunMetrics& m) const {
  if (m.oracle) {
    for (std::size_t i = 0; i < backend_metrics_.size(); ++i) {
      if (!backend_metrics_[i]) continue;
      OracleBackendMetrics backend = *backend_metrics_[i];
      backend.evaluation_ns = backend_sums_[i].ns.result();
      if (backend.penetrating_ticks > 0)
        backend.penetration_rms_m =
            std::sqrt(backend_sums_[i].depth_sq / static_cast<double>(backend.penetrating_ticks));
      m.oracle->backends.push_back(std::move(backend));
    }
    if (volume_ns_.count() > 0) m.oracle->volume_ns = volume_ns_.result();
    if (m.oracle->contacts_checked > 0) {
      const auto n = static_cast<double>(m.oracle->contacts_checked);
      m.oracle->contact_normal_err_rms_deg = std::sqrt(contact_normal_sq_ / n);
      m.oracle->contact_depth_err_rms_m = std::sqrt(contact_depth_sq_ / n);
    }
  }
}

// The share of the force signal's energy above the jitter cutoff, over the three axes.
void MetricsAccumulator::finish_force_spectrum(RunMetrics& m) const {
  double hf = 0, total_weight = 0;
  std::vector<double> component;  // one axis of the force signal at a time
  component.reserve(forces_.size());
  for (std::size_t axis = 0; axis < 3; ++axis) {
    component.clear();
    double variance = 0, mean = 0;
    forces_.for_each([&](const std::array<double, 3>& force) {
      component.push_back(force[axis]);
      mean += force[axis];
    });
    if (!component.empty()) mean /= static_cast<double>(component.size());
    for (double x : component) variance += (x - mean) * (x - mean);
    hf += variance *
          energy_fraction_above(component, 1e9 / static_cast<double>(kTickNs), kJitterCutoffHz);
    total_weight += variance;
  }
  m.stability.force_hf_energy_fraction = total_weight > 0 ? hf / total_weight : 0.0;
}

// Proxy and device chatter in the run's last quarter, and whether the proxy chatters.
void MetricsAccumulator::finish_chatter(RunMetrics& m) const {
  // The last quarter of the run (at least one block) and the quarter
  // before it: an oscillation that dies out shrinks from one to the next.
  const std::size_t blocks = chatter_blocks_.size();
  const std::size_t quarter = std::max<std::size_t>(1, blocks / 4);
  const auto rms_of = [&](std::size_t first, std::size_t end, double ChatterBlock::*sum) {
    double total = 0;
    int64_t ticks = 0;
    for (std::size_t i = first; i < end; ++i) {
      total += chatter_blocks_[i].*sum;
      ticks += chatter_blocks_[i].ticks;
    }
    return ticks > 0 ? std::sqrt(total / static_cast<double>(ticks)) : 0.0;
  };
  const std::size_t last = blocks - std::min(blocks, quarter);
  const std::size_t before = last - std::min(last, quarter);
  m.stability.proxy_chatter_m = rms_of(last, blocks, &ChatterBlock::proxy_sq);
  m.stability.device_chatter_m = rms_of(last, blocks, &ChatterBlock::device_sq);
  const double earlier_chatter_m = rms_of(before, last, &ChatterBlock::proxy_sq);
  const double threshold_m =
      std::max(kChatterFloorM, kChatterDeviceRatio * m.stability.device_chatter_m);
  // An oscillation, not one jump (a proxy leaving contact that becomes
  // the device): above the threshold in at least half of the blocks.
  std::size_t blocks_above = 0;
  for (std::size_t i = last; i < blocks; ++i)
    blocks_above += rms_of(i, i + 1, &ChatterBlock::proxy_sq) > threshold_m;
  m.stability.chatters = m.stability.proxy_chatter_m > threshold_m &&
                         2 * blocks_above >= blocks - last &&
                         m.stability.proxy_chatter_m >= kChatterDecayRatio * earlier_chatter_m;
}

// Closed loop: limit cycles, the device's penetration, the display's energy and the
// displayed stiffness (a fit, or why there is none).
void MetricsAccumulator::finish_closed_loop(RunMetrics& m) const {
  if (!limit_cycles_) return;
  ClosedLoopMetrics& closed = m.closed_loop.emplace();
  closed.limit_cycles = limit_cycles_->finish();
  closed.device_penetration_max_m = device_penetration_max_m_;
  closed.display_energy_min_j = display_energy_min_j_;
  const double n = static_cast<double>(stiffness_n_);
  const double variance = stiffness_dd_ - stiffness_d_ * stiffness_d_ / std::max(n, 1.0);
  const double span_m = stiffness_d_max_ - stiffness_d_min_;
  const double needed_m = std::max(kMinStiffnessSpanM, kMinStiffnessCounts * settings_.encoder_m);
  std::ostringstream note;
  if (stiffness_n_ < kMinStiffnessTicks) {
    note << stiffness_n_ << " ticks with the device in the scene; the fit needs "
         << kMinStiffnessTicks;
  } else if (span_m < needed_m) {
    note << "the device's penetration spans " << span_m * 1e6 << " µm; the fit needs "
         << needed_m * 1e6 << " µm"
         << (settings_.encoder_m > 0 ? " (10 encoder counts: over fewer it measures the "
                                       "encoder's staircase, not the stiffness)"
                                     : "");
  } else if (variance > 0) {
    closed.displayed_stiffness_n_per_m =
        (stiffness_df_ - stiffness_d_ * stiffness_f_ / n) / variance;
  } else {
    note << "the device's penetration does not vary";
  }
  closed.displayed_stiffness_note = note.str();
}

}  // namespace hb
