#include "harness/metrics/limit_cycles.h"

#include <algorithm>
#include <cmath>

namespace hb {

namespace {

// The residual of `values` about their least-squares line over the index.
std::vector<double> detrended(const std::vector<double>& values) {
  const auto n = static_cast<double>(values.size());
  double mean_i = (n - 1) / 2, mean_v = 0;
  for (double v : values) mean_v += v / n;
  double cov = 0, var = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double di = static_cast<double>(i) - mean_i;
    cov += di * (values[i] - mean_v);
    var += di * di;
  }
  const double slope = var > 0 ? cov / var : 0;
  std::vector<double> residual(values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    residual[i] = values[i] - mean_v - slope * (static_cast<double>(i) - mean_i);
  return residual;
}

double amplitude_of(const std::vector<double>& residual) {
  double sum_sq = 0;
  for (double r : residual) sum_sq += r * r;
  return std::sqrt(2 * sum_sq / static_cast<double>(residual.size()));
}

int sign_changes(const std::vector<double>& residual) {
  int changes = 0;
  double last = 0;
  for (double r : residual) {
    if (r == 0) continue;
    if (last != 0 && (r > 0) != (last > 0)) ++changes;
    last = r;
  }
  return changes;
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
}

double mean_amplitude(const auto& first, const auto& last) {
  double sum = 0;
  for (auto it = first; it != last; ++it) sum += it->amplitude_m;
  return sum / static_cast<double>(last - first);
}

}  // namespace

LimitCycleDetector::LimitCycleDetector(double floor_m, double tick_s)
    : floor_m_(floor_m), tick_s_(tick_s) {
  device_.reserve(kBlockTicks);
  intent_.reserve(kBlockTicks);
}

void LimitCycleDetector::add(const Vec3& device_p, const Vec3& intent_p, const Vec3& force,
                             bool in_contact) {
  device_.push_back(device_p);
  intent_.push_back(intent_p);
  force_sum_ += force;
  if (in_contact) ++contact_ticks_;
  if (static_cast<int>(device_.size()) == kBlockTicks) close_block();
}

void LimitCycleDetector::close_block() {
  const bool contact =
      contact_ticks_ >= kMinContactShare * kBlockTicks && force_sum_.squaredNorm() > 0;
  if (contact) {
    const Vec3 direction = force_sum_.normalized();
    std::vector<double> device(device_.size()), intent(intent_.size());
    for (std::size_t i = 0; i < device_.size(); ++i) {
      device[i] = direction.dot(device_[i]);
      intent[i] = direction.dot(intent_[i]);
    }
    const std::vector<double> residual = detrended(device);
    Block block;
    block.amplitude_m = amplitude_of(residual);
    const int changes = sign_changes(residual);
    block.frequency_hz = changes / (2 * static_cast<double>(device.size()) * tick_s_);
    block.oscillates = block.amplitude_m >= floor_m_ &&
                       block.amplitude_m >= kIntentRatio * amplitude_of(detrended(intent)) &&
                       changes >= kMinSignChanges;
    contact_blocks_.push_back(block);
  }
  device_.clear();
  intent_.clear();
  force_sum_.setZero();
  contact_ticks_ = 0;
}

LimitCycleMetrics LimitCycleDetector::finish() const {
  LimitCycleMetrics m;
  m.contact_blocks = static_cast<int64_t>(contact_blocks_.size());
  std::vector<double> amplitudes, frequencies;
  for (const Block& block : contact_blocks_) {
    if (!block.oscillates) continue;
    amplitudes.push_back(block.amplitude_m);
    frequencies.push_back(block.frequency_hz);
  }
  m.oscillating_blocks = static_cast<int64_t>(amplitudes.size());
  if (m.contact_blocks == 0) return m;
  m.share = static_cast<double>(m.oscillating_blocks) / static_cast<double>(m.contact_blocks);
  if (amplitudes.empty()) return m;
  m.amplitude_m = median(amplitudes);
  m.frequency_hz = median(frequencies);
  // Sustained: enough oscillating blocks, and the last quarter of the
  // oscillating blocks not quieter than the quarter before by kDecayRatio.
  // Over the oscillating blocks, not all contact blocks: a press, hold and
  // release ends in quiet contact blocks (the release), which made a bounce
  // through the whole hold look like one dying out.
  std::vector<Block> oscillating;
  for (const Block& block : contact_blocks_)
    if (block.oscillates) oscillating.push_back(block);
  const std::size_t quarter = oscillating.size() / 4;
  bool dying = false;
  if (quarter > 0) {
    const auto end = oscillating.end();
    const double last = mean_amplitude(end - static_cast<std::ptrdiff_t>(quarter), end);
    const double before = mean_amplitude(end - static_cast<std::ptrdiff_t>(2 * quarter),
                                         end - static_cast<std::ptrdiff_t>(quarter));
    dying = last < kDecayRatio * before;
  }
  m.limit_cycle = m.share >= kMinShare && !dying;
  return m;
}

}  // namespace hb
