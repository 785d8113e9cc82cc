// The one-sided Mann–Whitney U test (Wilcoxon rank-sum test): does the
// candidate sample tend to take larger values than the baseline sample?
// The compare gate uses it on per-tick step times, so that a slower median
// or tail is only called a regression when the shift is unlikely to be
// machine noise.
//
// Method: pool both samples, rank them (tied values share the average of
// the ranks they span), U_c = R_c - n_c (n_c + 1) / 2 where R_c is the rank
// sum of the candidate. Under the null hypothesis (both samples from one
// distribution) U_c has mean n_b n_c / 2 and, with ties, variance
//   n_b n_c / 12 * ((N + 1) - sum(t^3 - t) / (N (N - 1))),   N = n_b + n_c,
// t the size of each group of tied values. The p-value is the normal
// approximation with a continuity correction, P(U >= U_c) ~= 1 - Phi(z),
// z = (U_c - mean - 1/2) / sd. The exact null distribution is not computed:
// with 20 or more values a side the approximation is within 0.003 of it,
// and in the tail below 0.02, where a gate's alpha lies, it is slightly
// larger (conservative). With fewer values the p-value is only indicative;
// with five a side only (near) complete separation reaches p < 0.01.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace hb {

struct MannWhitneyResult {
  std::size_t n_baseline = 0;
  std::size_t n_candidate = 0;
  /// Pairs (b, c) with c > b, plus half the pairs with c == b.
  double u_candidate = 0;
  /// Pairs (b, c) with b > c, plus half the ties; u_baseline + u_candidate = n_b n_c.
  double u_baseline = 0;
  /// Mean of U under the null hypothesis, n_b n_c / 2.
  double u_mean = 0;
  /// Standard deviation of U under the null hypothesis, tie-corrected.
  double u_sd = 0;
  /// Continuity-corrected standard score of u_candidate (0 when u_sd is 0).
  double z = 0;
  /// One-sided p-value of "the candidate is larger": small means it is.
  /// 1 when every value is equal (no evidence at all).
  double p_value = 1;
};

/// Ranks 1..n of `values` in their original order; tied values get the
/// average of the ranks they span (e.g. {5, 7, 5} -> {1.5, 3, 1.5}).
std::vector<double> average_ranks(std::span<const double> values);

/// One-sided test of "candidate tends to be larger than baseline". Throws
/// std::invalid_argument when a sample is empty or holds a non-finite value.
MannWhitneyResult mann_whitney_greater(std::span<const double> baseline,
                                       std::span<const double> candidate);

}  // namespace hb
