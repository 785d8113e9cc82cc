#include "harness/metrics/run_metrics.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "harness/metrics/spectrum.h"

namespace hb {

namespace {
constexpr double kDirectionThresholdN = 0.05;  // below this a force has no reliable direction
constexpr double kDirectionPeakShare = 0.1;    // direction counted under at least 10% of peak load
constexpr double kJitterCutoffHz = 100.0;

double angle_deg(const Vec3& a, const Vec3& b) {
  const double c = std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0);
  return std::acos(c) * 180.0 / std::numbers::pi;
}

}  // namespace

Percentiles percentiles_of(std::vector<int64_t> values) {
  Percentiles p;
  p.count = static_cast<int64_t>(values.size());
  if (values.empty()) return p;
  std::sort(values.begin(), values.end());
  // Nearest rank: the smallest value with at least q of the sample at or below it.
  auto rank = [&](double q) {
    const auto n = values.size();
    auto index = static_cast<std::size_t>(std::ceil(q * static_cast<double>(n)));
    index = std::clamp<std::size_t>(index, 1, n);
    return static_cast<double>(values[index - 1]);
  };
  p.p50 = rank(0.5);
  p.p90 = rank(0.9);
  p.p99 = rank(0.99);
  p.p999 = rank(0.999);
  p.max = static_cast<double>(values.back());
  return p;
}

void MetricsAccumulator::add(const TickRecord& record, const TickEvaluation& evaluation) {
  const TickResult& result = record.result;
  const DeviceSample& device = *record.device;
  const double dt = 1e-9 * static_cast<double>(kTickNs);

  // Harness-side guard: a renderer must never display non-finite numbers,
  // but if one does, the run counts it and uses zero instead.
  Wrench display = result.display;
  const bool nonfinite = !is_finite(display) || (result.flags & kFlagNonFiniteZeroed);
  if (!is_finite(display)) display = Wrench{};
  if (nonfinite) ++partial_.stability.nonfinite;
  if (result.flags & kFlagProxyReset) ++partial_.stability.proxy_resets;
  if (result.flags & (kFlagForceSaturated | kFlagTorqueSaturated))
    ++partial_.stability.saturated_ticks;

  step_ns_.push_back(record.step_ns);
  if (record.step_ns > kTickNs) ++partial_.timing.over_budget;
  const bool reported_contact = !result.contacts.empty();
  const bool in_contact = reported_contact || evaluation.reference_contact.value_or(false);
  (in_contact ? contact_step_ns_ : free_step_ns_).push_back(record.step_ns);
  if (record.slow_started) {
    slow_ns_.push_back(record.slow_ns);
    slow_starts_.push_back({step_ns_.size() - 1, record.slow_ns, record.slow_latency_ticks});
  }
  if (record.slow_data_age_ticks >= 0) {
    slow_age_sum_ += record.slow_data_age_ticks;
    ++slow_age_count_;
    slow_age_max_ = std::max(slow_age_max_, record.slow_data_age_ticks);
  }

  // Accuracy against the analytic reference.
  if (evaluation.ideal_display) {
    ++ideal_ticks_;
    const Wrench& ideal = *evaluation.ideal_display;
    const double force_err = (display.force - ideal.force).norm();
    force_err_sq_ += force_err * force_err;
    partial_.accuracy.force_err_max_n =
        std::max(partial_.accuracy.force_err_max_n.value_or(0.0), force_err);
    const double torque_err = (display.torque - ideal.torque).norm();
    torque_err_sq_ += torque_err * torque_err;
    force_pairs_.push_back({ideal.force, display.force});
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

  // Stability and passivity. The coupling force on the proxy is the
  // negated display; its power at the device port is F_c·v_h + tau_c·w_h.
  // A finite proxy far enough away overflows the distance: that counts as non-finite too.
  const double raw_separation_m = (result.proxy.p - device.pose.p).norm();
  const bool proxy_finite = is_finite(result.proxy) && std::isfinite(raw_separation_m);
  if (!proxy_finite) ++partial_.stability.proxy_nonfinite_ticks;
  const double separation_m = proxy_finite ? raw_separation_m : 0.0;
  partial_.stability.max_proxy_separation_m =
      std::max(partial_.stability.max_proxy_separation_m, separation_m);
  if (!partial_.stability.diverged &&
      (!proxy_finite || separation_m > settings_.divergence_distance_m ||
       (result.flags & kFlagProxyReset))) {
    partial_.stability.diverged = true;
    partial_.stability.diverged_at_tick = device.tick;
  }
  energy_ += (-display.force.dot(device.twist.v) - display.torque.dot(device.twist.w)) * dt;
  partial_.stability.passivity_energy_min_j =
      std::min(partial_.stability.passivity_energy_min_j, energy_);
  partial_.stability.passivity_energy_final_j = energy_;
  if (last_force_) {
    partial_.stability.force_jump_max_n =
        std::max(partial_.stability.force_jump_max_n, (display.force - *last_force_).norm());
  }
  last_force_ = display.force;
  forces_.push_back(display.force);

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
  if (result.work.names) {
    for (std::size_t i = 0; i < WorkCounters::kSlots; ++i) {
      const std::string_view name = (*result.work.names)[i];
      if (name.empty()) continue;
      auto& totals = partial_.contacts.total_work;
      auto it = std::find_if(totals.begin(), totals.end(),
                             [&](const auto& entry) { return entry.first == name; });
      if (it == totals.end()) it = totals.emplace(totals.end(), std::string(name), 0);
      it->second += result.work.counts[i];
    }
  }
  if (evaluation.oracle) add_oracle(*evaluation.oracle);
}

namespace {
void add_backend(std::optional<OracleBackendMetrics>& metrics, std::string_view name,
                 const PenetrationResult& result, int64_t ns, std::vector<int64_t>& all_ns,
                 double& depth_sq) {
  if (!metrics) metrics.emplace().name = name;
  ++metrics->ticks_evaluated;
  all_ns.push_back(ns);
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
  backend_sums_.resize(entries.size());
  for (std::size_t i = 0; i < oracle.backends.size(); ++i) {
    if (!oracle.backends[i]) continue;
    add_backend(backend_metrics_[i], entries[i].name, oracle.backends[i]->result,
                oracle.backends[i]->ns, backend_sums_[i].ns, backend_sums_[i].depth_sq);
  }
  m.inside_disagreements += oracle.inside_disagreements;
  if (oracle.intersection_volume_m3) {
    ++m.volume_evaluations;
    volume_ns_.push_back(oracle.volume_ns);
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
  m.timing.ticks = static_cast<int64_t>(step_ns_.size());
  m.timing.step_ns = percentiles_of(step_ns_);
  constexpr std::size_t kSampleSize = 1000;
  const std::size_t stride = (step_ns_.size() + kSampleSize - 1) / kSampleSize;
  for (std::size_t i = 0; stride > 0 && i < step_ns_.size(); i += stride)
    m.timing.step_ns_sample.push_back(step_ns_[i]);
  if (!free_step_ns_.empty()) m.timing.free_space_step_ns = percentiles_of(free_step_ns_);
  if (!contact_step_ns_.empty()) m.timing.contact_step_ns = percentiles_of(contact_step_ns_);
  {
    std::vector<double> cpu(step_ns_.begin(), step_ns_.end());
    for (const SlowStart& slow : slow_starts_) {
      const int64_t latency = std::max<int64_t>(1, slow.latency_ticks);
      const double share = static_cast<double>(slow.ns) / static_cast<double>(latency);
      for (std::size_t k = slow.tick_index;
           k < cpu.size() && k < slow.tick_index + static_cast<std::size_t>(latency); ++k)
        cpu[k] += share;
    }
    std::vector<int64_t> rounded;
    rounded.reserve(cpu.size());
    double sum = 0;
    for (double value : cpu) {
      rounded.push_back(std::llround(value));
      sum += value;
    }
    m.timing.cpu_per_tick_ns.percentiles = percentiles_of(std::move(rounded));
    m.timing.cpu_per_tick_ns.mean = cpu.empty() ? 0 : sum / static_cast<double>(cpu.size());
  }
  if (!slow_ns_.empty()) {
    m.timing.slow_update_ns = percentiles_of(slow_ns_);
    const double seconds =
        static_cast<double>(m.timing.ticks) * 1e-9 * static_cast<double>(kTickNs);
    m.timing.slow_loop_rate_hz = static_cast<double>(slow_ns_.size()) / seconds;
  }
  if (slow_age_count_ > 0) {
    m.timing.slow_data_age_mean_ticks =
        static_cast<double>(slow_age_sum_) / static_cast<double>(slow_age_count_);
    m.timing.slow_data_age_max_ticks = slow_age_max_;
  }
  if (ideal_ticks_ > 0) {
    m.accuracy.force_err_rms_n = std::sqrt(force_err_sq_ / static_cast<double>(ideal_ticks_));
    m.accuracy.torque_err_rms_nm = std::sqrt(torque_err_sq_ / static_cast<double>(ideal_ticks_));
  }
  // Direction error under load: ticks where the ideal force is at least
  // 10% of its peak in the run (and >= 0.05 N) and the rendered force is
  // not negligible; near contact onset and release a direction means little.
  double peak_ideal = 0;
  for (const auto& [ideal, rendered] : force_pairs_)
    peak_ideal = std::max(peak_ideal, ideal.norm());
  const double threshold = std::max(kDirectionThresholdN, kDirectionPeakShare * peak_ideal);
  double dir_err_sq = 0;
  int64_t dir_err_count = 0;
  for (const auto& [ideal, rendered] : force_pairs_) {
    if (ideal.norm() < threshold || rendered.norm() < kDirectionThresholdN) continue;
    const double angle = angle_deg(rendered, ideal);
    dir_err_sq += angle * angle;
    ++dir_err_count;
    m.accuracy.force_dir_err_max_deg =
        std::max(m.accuracy.force_dir_err_max_deg.value_or(0.0), angle);
  }
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
  if (m.oracle) {
    for (std::size_t i = 0; i < backend_metrics_.size(); ++i) {
      if (!backend_metrics_[i]) continue;
      OracleBackendMetrics backend = *backend_metrics_[i];
      backend.evaluation_ns = percentiles_of(backend_sums_[i].ns);
      if (backend.penetrating_ticks > 0)
        backend.penetration_rms_m =
            std::sqrt(backend_sums_[i].depth_sq / static_cast<double>(backend.penetrating_ticks));
      m.oracle->backends.push_back(std::move(backend));
    }
    if (!volume_ns_.empty()) m.oracle->volume_ns = percentiles_of(volume_ns_);
    if (m.oracle->contacts_checked > 0) {
      const auto n = static_cast<double>(m.oracle->contacts_checked);
      m.oracle->contact_normal_err_rms_deg = std::sqrt(contact_normal_sq_ / n);
      m.oracle->contact_depth_err_rms_m = std::sqrt(contact_depth_sq_ / n);
    }
  }
  double hf = 0, total_weight = 0;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> component(forces_.size());
    double variance = 0, mean = 0;
    for (std::size_t i = 0; i < forces_.size(); ++i) mean += component[i] = forces_[i][axis];
    if (!forces_.empty()) mean /= static_cast<double>(forces_.size());
    for (double x : component) variance += (x - mean) * (x - mean);
    hf += variance *
          energy_fraction_above(component, 1e9 / static_cast<double>(kTickNs), kJitterCutoffHz);
    total_weight += variance;
  }
  m.stability.force_hf_energy_fraction = total_weight > 0 ? hf / total_weight : 0.0;
  return m;
}

}  // namespace hb
