#include "harness/compare/mann_whitney.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace hb {

std::vector<double> average_ranks(std::span<const double> values) {
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&values](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  std::vector<double> ranks(values.size());
  for (std::size_t first = 0; first < order.size();) {
    std::size_t last = first + 1;
    while (last < order.size() && values[order[last]] == values[order[first]]) ++last;
    // Positions first..last-1 hold ranks first+1..last; their mean:
    const double rank = 0.5 * static_cast<double>(first + 1 + last);
    for (std::size_t i = first; i < last; ++i) ranks[order[i]] = rank;
    first = last;
  }
  return ranks;
}

MannWhitneyResult mann_whitney_greater(std::span<const double> baseline,
                                       std::span<const double> candidate) {
  if (baseline.empty() || candidate.empty())
    throw std::invalid_argument("Mann-Whitney test needs two non-empty samples");
  std::vector<double> pooled(baseline.begin(), baseline.end());
  pooled.insert(pooled.end(), candidate.begin(), candidate.end());
  for (double value : pooled)
    if (!std::isfinite(value))
      throw std::invalid_argument("Mann-Whitney test needs finite sample values");

  MannWhitneyResult result;
  result.n_baseline = baseline.size();
  result.n_candidate = candidate.size();
  const double nb = static_cast<double>(baseline.size());
  const double nc = static_cast<double>(candidate.size());
  const double n = nb + nc;

  const std::vector<double> ranks = average_ranks(pooled);
  const double candidate_rank_sum = std::accumulate(
      ranks.begin() + static_cast<std::ptrdiff_t>(baseline.size()), ranks.end(), 0.0);
  result.u_candidate = candidate_rank_sum - nc * (nc + 1) / 2;
  result.u_baseline = nb * nc - result.u_candidate;
  result.u_mean = nb * nc / 2;

  // Tie correction: sum of t^3 - t over groups of equal values.
  std::sort(pooled.begin(), pooled.end());
  double tie_term = 0;
  for (std::size_t first = 0; first < pooled.size();) {
    std::size_t last = first + 1;
    while (last < pooled.size() && pooled[last] == pooled[first]) ++last;
    const double t = static_cast<double>(last - first);
    tie_term += t * t * t - t;
    first = last;
  }
  const double variance = nb * nc / 12 * ((n + 1) - tie_term / (n * (n - 1)));
  result.u_sd = variance > 0 ? std::sqrt(variance) : 0;
  if (result.u_sd == 0) return result;  // every value equal: p = 1

  // Upper tail of a discrete statistic: P(U >= u) ~= P(Z >= (u - 1/2 - mean) / sd).
  result.z = (result.u_candidate - result.u_mean - 0.5) / result.u_sd;
  result.p_value = std::clamp(0.5 * std::erfc(result.z / std::sqrt(2.0)), 0.0, 1.0);
  return result;
}

}  // namespace hb
