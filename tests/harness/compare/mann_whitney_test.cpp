// The Mann–Whitney U test against hand-computed values and the exact null
// distribution of U.
#include "harness/compare/mann_whitney.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace hb {
namespace {

double upper_normal_tail(double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); }

TEST_CASE("tied values share the average of the ranks they span") {
  const std::vector<double> values = {5, 7, 5};
  CHECK(average_ranks(values) == std::vector<double>{1.5, 3, 1.5});
  // Sorted: 1, 2, 2, 2, 3, 4, 4 -> ranks 1, (2+3+4)/3 = 3, 5, (6+7)/2 = 6.5.
  const std::vector<double> more = {4, 2, 1, 2, 3, 4, 2};
  CHECK(average_ranks(more) == std::vector<double>{6.5, 3, 1, 3, 5, 6.5, 3});
}

TEST_CASE("a small sample without ties: U and p by hand") {
  // Baseline 12 15 19 22, candidate 14 20 25 27 30. Pairs with the candidate
  // larger: 14 beats 12 (1), 20 beats 12 15 19 (3), 25, 27 and 30 beat all
  // four (12): U_c = 16, U_b = 4 * 5 - 16 = 4.
  // Under H0: mean 4 * 5 / 2 = 10, variance 4 * 5 * (9 + 1) / 12 = 16.6667,
  // sd = 4.082483; z = (16 - 10 - 0.5) / 4.082483 = 1.347219,
  // p = 1 - Phi(1.347219) = 0.088955.
  const std::vector<double> baseline = {12, 15, 19, 22};
  const std::vector<double> candidate = {14, 20, 25, 27, 30};
  const MannWhitneyResult r = mann_whitney_greater(baseline, candidate);
  CHECK(r.n_baseline == 4);
  CHECK(r.n_candidate == 5);
  CHECK(r.u_candidate == 16);
  CHECK(r.u_baseline == 4);
  CHECK(r.u_mean == 10);
  CHECK(r.u_sd == Approx(4.082483).epsilon(1e-6));
  CHECK(r.z == Approx(1.347219).epsilon(1e-6));
  CHECK(r.p_value == Approx(0.088955).epsilon(1e-4));

  // The other direction: U_c = 4, z = (4 - 10 - 0.5) / 4.082483 = -1.592168.
  const MannWhitneyResult reverse = mann_whitney_greater(candidate, baseline);
  CHECK(reverse.u_candidate == 4);
  CHECK(reverse.p_value == Approx(upper_normal_tail(-1.592168)).epsilon(1e-6));
  CHECK(reverse.p_value > 0.9);
}

TEST_CASE("ties: average ranks and the tie-corrected variance by hand") {
  // Baseline 1 2 2 3, candidate 2 3 3 4. Pooled and sorted: 1 2 2 2 3 3 3 4,
  // ranks 1, 3 3 3, 6 6 6, 8. Candidate rank sum 3 + 6 + 6 + 8 = 23,
  // U_c = 23 - 4 * 5 / 2 = 13 (pair count: 2 -> 1 + 2 halves = 2,
  // each 3 -> 3 + 1 half = 3.5, 4 -> 4; 2 + 7 + 4 = 13).
  // Two groups of three ties: sum(t^3 - t) = 2 * 24 = 48, N = 8:
  // variance = 16 / 12 * (9 - 48 / 56) = 10.857143, sd = 3.295018,
  // z = (13 - 8 - 0.5) / 3.295018 = 1.365698, p = 0.086017.
  const std::vector<double> baseline = {1, 2, 2, 3};
  const std::vector<double> candidate = {2, 3, 3, 4};
  const MannWhitneyResult r = mann_whitney_greater(baseline, candidate);
  CHECK(r.u_candidate == 13);
  CHECK(r.u_baseline == 3);
  CHECK(r.u_sd * r.u_sd == Approx(10.857143).epsilon(1e-6));
  CHECK(r.z == Approx(1.365698).epsilon(1e-6));
  CHECK(r.p_value == Approx(0.086017).epsilon(1e-4));
}

TEST_CASE("all values equal: no evidence, p = 1") {
  const std::vector<double> same(30, 700.0);
  const MannWhitneyResult r = mann_whitney_greater(same, same);
  CHECK(r.u_candidate == 450);
  CHECK(r.u_sd == 0);
  CHECK(r.p_value == 1);
}

// Number of orderings of n_b baseline and n_c candidate values (no ties)
// with U_c = u: the largest value is either a candidate, which beats all
// n_b baseline values, or a baseline value, which adds nothing.
double orderings_with_u(int nb, int nc, int u,
                        std::vector<std::vector<std::vector<double>>>& memo) {
  if (u < 0) return 0;
  if (nb == 0 || nc == 0) return u == 0 ? 1 : 0;
  double& cached = memo[nb][nc][u];
  if (cached >= 0) return cached;
  cached = orderings_with_u(nb, nc - 1, u - nb, memo) + orderings_with_u(nb - 1, nc, u, memo);
  return cached;
}

TEST_CASE("20 values a side: the normal approximation against the exact distribution") {
  constexpr int n = 20;
  std::vector<std::vector<std::vector<double>>> memo(
      n + 1, std::vector<std::vector<double>>(n + 1, std::vector<double>(n * n + 1, -1)));
  double total = 0;
  for (int u = 0; u <= n * n; ++u) total += orderings_with_u(n, n, u, memo);
  CHECK(total == Approx(137846528820.0));  // C(40, 20)

  std::vector<double> baseline;
  for (int i = 0; i < n; ++i) baseline.push_back(i);
  for (int shift = 0; shift <= 12; ++shift) {
    std::vector<double> candidate;
    for (int i = 0; i < n; ++i) candidate.push_back(i + shift + 0.5);
    // Candidate i + shift + 0.5 beats baseline 0 .. min(i + shift, 19).
    int u = 0;
    for (int i = 0; i < n; ++i) u += std::min(i + shift + 1, n);
    double exact = 0;
    for (int v = u; v <= n * n; ++v) exact += orderings_with_u(n, n, v, memo);
    exact /= total;
    const MannWhitneyResult r = mann_whitney_greater(baseline, candidate);
    INFO("shift " << shift << " U " << u << " exact p " << exact << " approx " << r.p_value);
    CHECK(r.u_candidate == u);
    CHECK(std::abs(r.p_value - exact) < 0.003);
    if (exact < 0.02) CHECK(r.p_value >= exact);  // conservative where alpha lies
  }
}

// Step-time-like values: 800..1199 ns, spread evenly by a multiplicative
// stride (7919 is prime, so i -> 7919 i mod 400 visits every residue).
std::vector<double> sampled_step_times(std::size_t count, double scale) {
  std::vector<double> values;
  for (std::size_t i = 0; i < count; ++i)
    values.push_back(std::round(scale * (800.0 + static_cast<double>((i * 7919) % 400))));
  return values;
}

TEST_CASE("large samples: identical, clearly shifted, shifted the other way") {
  const std::vector<double> baseline = sampled_step_times(1000, 1.0);
  SECTION("identical samples: U at its mean, p just above one half") {
    const MannWhitneyResult r = mann_whitney_greater(baseline, baseline);
    CHECK(r.u_candidate == r.u_mean);
    CHECK(r.p_value == Approx(0.5).margin(1e-3));
    CHECK(r.p_value > 0.5);  // the continuity correction leans towards "no"
  }
  SECTION("1.5 times slower: p far below any alpha") {
    const MannWhitneyResult r = mann_whitney_greater(baseline, sampled_step_times(1000, 1.5));
    CHECK(r.p_value < 1e-6);
    // 1.5 * 800 = 1200 exceeds every baseline value: complete separation.
    CHECK(r.u_candidate == 1000.0 * 1000.0);
  }
  SECTION("faster candidate: p near 1") {
    const MannWhitneyResult r = mann_whitney_greater(baseline, sampled_step_times(1000, 0.7));
    CHECK(r.p_value > 1 - 1e-6);
  }
  SECTION("heavily tied samples (integer ns, few distinct values) stay well defined") {
    std::vector<double> coarse_baseline, coarse_candidate;
    for (int i = 0; i < 1000; ++i) {
      coarse_baseline.push_back(600 + 10 * (i % 3));   // 600, 610, 620
      coarse_candidate.push_back(610 + 10 * (i % 3));  // 610, 620, 630
    }
    const MannWhitneyResult r = mann_whitney_greater(coarse_baseline, coarse_candidate);
    CHECK(std::isfinite(r.z));
    CHECK(r.p_value < 1e-6);
    CHECK(r.u_candidate + r.u_baseline == 1000.0 * 1000.0);
  }
}

TEST_CASE("empty or non-finite samples are rejected") {
  const std::vector<double> some = {1, 2, 3};
  const std::vector<double> none;
  const std::vector<double> nan = {1, std::nan("")};
  CHECK_THROWS_AS(mann_whitney_greater(none, some), std::invalid_argument);
  CHECK_THROWS_AS(mann_whitney_greater(some, none), std::invalid_argument);
  CHECK_THROWS_AS(mann_whitney_greater(some, nan), std::invalid_argument);
}

}  // namespace
}  // namespace hb
