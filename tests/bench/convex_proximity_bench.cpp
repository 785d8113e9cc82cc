// Cost of one convex–convex query of the sensation-preserving contact query,
// ns per call, for pieces of 8, 16 and 32 vertices (points on ellipsoids
// 5 cm across, so every point is a hull vertex): GJK/EPA penetration
// (libccd, then the exact-normal polish and the contact point), the GJK
// rejection of separated pieces, the margin query of separated pieces (own
// GJK distance) and the bare distance. Each iteration takes the next of 64
// prepared pairs. Run:
//   build/tests/bench/convex_proximity_bench --benchmark_repetitions=5
//       --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "algorithms/sensation_preserving/convex_proximity.h"

namespace hb {
namespace {

struct PiecePair {
  std::vector<Vec3> a, b;
  Pose pose_a, pose_b;
  double distance = 0;  // m, 0 when they overlap
};

std::vector<Vec3> ellipsoid_points(std::mt19937& rng, int count) {
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> axis(0.015, 0.025);
  const Vec3 half(axis(rng), axis(rng), axis(rng));
  std::vector<Vec3> points;
  for (int i = 0; i < count; ++i)
    points.push_back(Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized().cwiseProduct(half));
  return points;
}

Quat random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> gauss;
  return Quat(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized();
}

/// 64 pairs of `count`-vertex pieces that overlap (or are apart by 1–5 mm).
std::vector<PiecePair> make_pairs(int count, bool overlapping) {
  std::mt19937 rng(static_cast<unsigned>(count) * 2 + (overlapping ? 1 : 0));
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> gap(0.001, 0.005);
  std::vector<PiecePair> pairs;
  while (pairs.size() < 64) {
    PiecePair p;
    p.a = ellipsoid_points(rng, count);
    p.b = ellipsoid_points(rng, count);
    p.pose_a = Pose{Vec3::Zero(), random_rotation(rng)};
    const Vec3 direction = Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized();
    p.pose_b = Pose{0.08 * direction, random_rotation(rng)};
    // Slide b along the direction until the pieces overlap by a little or
    // are apart by the wanted gap.
    const PlacedConvex a{p.a, p.pose_a};
    const double wanted = overlapping ? 0 : gap(rng);
    for (int step = 0; step < 200; ++step) {
      const double d = convex_distance(a, PlacedConvex{p.b, p.pose_b});
      if (overlapping ? d == 0 : d <= wanted) break;
      p.pose_b.p -= 0.0005 * direction;
    }
    if (overlapping) p.pose_b.p -= 0.002 * direction;
    p.distance = convex_distance(a, PlacedConvex{p.b, p.pose_b});
    if ((p.distance == 0) == overlapping) pairs.push_back(std::move(p));
  }
  return pairs;
}

void BM_Penetration(benchmark::State& state) {
  const std::vector<PiecePair> pairs = make_pairs(static_cast<int>(state.range(0)), true);
  std::size_t i = 0;
  for (auto _ : state) {
    const PiecePair& p = pairs[i++ % pairs.size()];
    benchmark::DoNotOptimize(
        convex_proximity(PlacedConvex{p.a, p.pose_a}, PlacedConvex{p.b, p.pose_b}));
  }
}
BENCHMARK(BM_Penetration)->Arg(8)->Arg(16)->Arg(32);

void BM_SeparatedRejection(benchmark::State& state) {
  const std::vector<PiecePair> pairs = make_pairs(static_cast<int>(state.range(0)), false);
  std::size_t i = 0;
  for (auto _ : state) {
    const PiecePair& p = pairs[i++ % pairs.size()];
    benchmark::DoNotOptimize(
        convex_proximity(PlacedConvex{p.a, p.pose_a}, PlacedConvex{p.b, p.pose_b}));
  }
}
BENCHMARK(BM_SeparatedRejection)->Arg(8)->Arg(16)->Arg(32);

void BM_SeparatedWithinMargin(benchmark::State& state) {
  const std::vector<PiecePair> pairs = make_pairs(static_cast<int>(state.range(0)), false);
  std::size_t i = 0;
  for (auto _ : state) {
    const PiecePair& p = pairs[i++ % pairs.size()];
    benchmark::DoNotOptimize(
        convex_proximity(PlacedConvex{p.a, p.pose_a}, PlacedConvex{p.b, p.pose_b}, 0.01));
  }
}
BENCHMARK(BM_SeparatedWithinMargin)->Arg(8)->Arg(16)->Arg(32);

void BM_Distance(benchmark::State& state) {
  const std::vector<PiecePair> pairs = make_pairs(static_cast<int>(state.range(0)), false);
  std::size_t i = 0;
  for (auto _ : state) {
    const PiecePair& p = pairs[i++ % pairs.size()];
    benchmark::DoNotOptimize(
        convex_distance(PlacedConvex{p.a, p.pose_a}, PlacedConvex{p.b, p.pose_b}));
  }
}
BENCHMARK(BM_Distance)->Arg(8)->Arg(16)->Arg(32);

}  // namespace
}  // namespace hb

BENCHMARK_MAIN();
