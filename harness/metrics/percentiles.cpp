#include "harness/metrics/percentiles.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace hb {

namespace {

constexpr int64_t kSubBuckets = int64_t{1} << StreamingPercentiles::kSubBucketBits;

// Rank of quantile q in a sample of n: the smallest rank with at least q of
// the sample at or below it, in [1, n].
int64_t nearest_rank(double q, int64_t n) {
  const auto rank = static_cast<int64_t>(std::ceil(q * static_cast<double>(n)));
  return std::clamp<int64_t>(rank, 1, n);
}

// Bucket of a value >= 0: values below kSubBuckets have their own; a value
// in [2^e, 2^(e+1)) with e >= kSubBucketBits falls in one of kSubBuckets
// buckets of width 2^(e - kSubBucketBits).
std::size_t bucket_of(int64_t value) {
  if (value < kSubBuckets) return static_cast<std::size_t>(value);
  const int exponent = std::bit_width(static_cast<uint64_t>(value)) - 1;
  const int shift = exponent - StreamingPercentiles::kSubBucketBits;
  return static_cast<std::size_t>((shift + 1) * kSubBuckets + ((value >> shift) - kSubBuckets));
}

// Midpoint of a bucket (its value when it is one wide).
double bucket_midpoint(std::size_t bucket) {
  const auto index = static_cast<int64_t>(bucket);
  if (index < kSubBuckets) return static_cast<double>(index);
  const int64_t shift = index / kSubBuckets - 1;
  const int64_t lowest = (kSubBuckets + index % kSubBuckets) << shift;
  const int64_t width = int64_t{1} << shift;
  return static_cast<double>(lowest) + 0.5 * static_cast<double>(width - 1);
}

// Buckets for every int64 value: up to exponent 62.
constexpr std::size_t kBucketCount =
    static_cast<std::size_t>((63 - StreamingPercentiles::kSubBucketBits + 1) * kSubBuckets);

}  // namespace

Percentiles percentiles_of(std::vector<int64_t> values) {
  Percentiles p;
  p.count = static_cast<int64_t>(values.size());
  if (values.empty()) return p;
  std::sort(values.begin(), values.end());
  auto rank = [&](double q) {
    return static_cast<double>(values[static_cast<std::size_t>(nearest_rank(q, p.count) - 1)]);
  };
  p.p50 = rank(0.5);
  p.p90 = rank(0.9);
  p.p99 = rank(0.99);
  p.p999 = rank(0.999);
  p.max = static_cast<double>(values.back());
  return p;
}

void StreamingPercentiles::add(int64_t value) {
  value = std::max<int64_t>(value, 0);
  ++count_;
  max_ = std::max(max_, value);
  if (!bins_.empty()) {
    add_to_histogram(value);
    return;
  }
  if (values_.size() < exact_capacity_) {
    values_.push_back(value);
    return;
  }
  move_to_histogram();
  add_to_histogram(value);
}

void StreamingPercentiles::move_to_histogram() {
  bins_.assign(kBucketCount, 0);
  for (int64_t value : values_) add_to_histogram(value);
  std::vector<int64_t>().swap(values_);
}

void StreamingPercentiles::add_to_histogram(int64_t value) { ++bins_[bucket_of(value)]; }

Percentiles StreamingPercentiles::result() const {
  if (bins_.empty()) return percentiles_of(values_);
  Percentiles p;
  p.count = count_;
  p.max = static_cast<double>(max_);
  // One walk through the buckets for the four ranks, in increasing order.
  const double quantiles[] = {0.5, 0.9, 0.99, 0.999};
  double* outputs[] = {&p.p50, &p.p90, &p.p99, &p.p999};
  std::size_t next = 0;
  int64_t seen = 0;
  for (std::size_t bucket = 0; bucket < bins_.size() && next < 4; ++bucket) {
    seen += bins_[bucket];
    while (next < 4 && seen >= nearest_rank(quantiles[next], count_)) {
      *outputs[next] = std::min(bucket_midpoint(bucket), p.max);
      ++next;
    }
  }
  return p;
}

}  // namespace hb
