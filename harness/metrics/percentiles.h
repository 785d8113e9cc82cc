// Nearest-rank percentiles: of a stored sample, and of a stream of
// non-negative integers (times in ns) in bounded memory, exact while the
// stream is short and within a stated relative error once it is long.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hb {

/// Nearest-rank percentiles of a sample, in the sample's unit.
struct Percentiles {
  double p50 = 0, p90 = 0, p99 = 0, p999 = 0, max = 0;
  int64_t count = 0;
};
/// Percentiles of values (sorted copy); count 0 and zeros when empty.
Percentiles percentiles_of(std::vector<int64_t> values);

/// Nearest-rank percentiles of the values added. The first
/// `exact_capacity` values are kept as they are, and the percentiles are
/// exact (as percentiles_of). Past that, every value goes into a log-linear
/// histogram: values below 2^kSubBucketBits (1024) keep their own bucket
/// (exact), larger ones share a bucket 2^-kSubBucketBits of their magnitude
/// wide, and a percentile is reported as its bucket's midpoint, so that
/// |reported - exact| <= 2^-(kSubBucketBits+1) * exact (0.05 %). Count and
/// max stay exact. Memory: 8 bytes per value up to exact_capacity, then a
/// fixed 440 KB.
class StreamingPercentiles {
 public:
  static constexpr int kSubBucketBits = 10;
  /// 2^20 values: about 17 minutes of ticks at 1 kHz, 8 MB.
  static constexpr std::size_t kDefaultExactCapacity = std::size_t{1} << 20;
  /// The largest relative error of a percentile once the histogram is in use.
  static constexpr double kRelativeErrorBound = 1.0 / (2 << kSubBucketBits);

  explicit StreamingPercentiles(std::size_t exact_capacity = kDefaultExactCapacity)
      : exact_capacity_(exact_capacity) {}

  /// Negative values count as 0.
  void add(int64_t value);
  int64_t count() const { return count_; }
  /// Whether the percentiles are exact (the histogram is not in use).
  bool exact() const { return bins_.empty(); }
  Percentiles result() const;

 private:
  void move_to_histogram();
  void add_to_histogram(int64_t value);

  std::size_t exact_capacity_;
  std::vector<int64_t> values_;
  std::vector<int64_t> bins_;  ///< counts per bucket, once in histogram mode
  int64_t count_ = 0;
  int64_t max_ = 0;
};

}  // namespace hb
