// Cost of one Gauss least-constraint solve (the god-object's per-update QP)
// for K = 4, 16, 64 contacts of a tool pressed against a surface, cold and
// warm-started from the active set of the previous solve.
// Run: build/tests/bench/gauss_least_constraint_bench
//        --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "algorithms/contact/gauss_least_constraint.h"

namespace hb {
namespace {

struct Problem {
  Mat6 mass;
  Vec6 unconstrained;
  std::vector<GaussConstraint> constraints;
  std::vector<int> previous_active;
};

Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  return Vec3(normal(rng), normal(rng), normal(rng)).normalized();
}

// A 4 cm, 0.5 kg tool whose lower half touches a bumpy floor: normals within
// 60° of +z, pushed down and sideways and twisted by the coupling.
Problem random_problem(std::mt19937_64& rng, int contacts) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Problem problem;
  const Mat3 rotation = Eigen::AngleAxisd(3 * unit(rng), random_unit(rng)).toRotationMatrix();
  const Mat3 inertia = rotation * Vec3(1.2e-4, 1.4e-4, 1.7e-4).asDiagonal() * rotation.transpose();
  problem.mass = rigid_body_mass_matrix(0.5, 0.5 * (inertia + inertia.transpose()));
  problem.unconstrained << unit(rng), unit(rng), -1.0 + 0.3 * unit(rng), 20 * unit(rng),
      20 * unit(rng), 20 * unit(rng);
  while (static_cast<int>(problem.constraints.size()) < contacts) {
    GaussConstraint c;
    c.normal = random_unit(rng);
    if (c.normal.z() < 0.5) continue;
    c.lever = Vec3(0.02 * unit(rng), 0.02 * unit(rng), -0.02 + 0.005 * unit(rng));
    problem.constraints.push_back(c);
  }
  return problem;
}

std::vector<Problem> problems(int contacts) {
  std::mt19937_64 rng(42 + contacts);
  std::vector<Problem> set;
  GaussLeastConstraintSolver solver;
  for (int i = 0; i < 64; ++i) {
    set.push_back(random_problem(rng, contacts));
    Problem& p = set.back();
    p.previous_active = solver.solve(p.mass, p.unconstrained, p.constraints).active;
  }
  return set;
}

// state.range(0): contacts K.
void BM_gauss_cold(benchmark::State& state) {
  const std::vector<Problem> set = problems(static_cast<int>(state.range(0)));
  GaussLeastConstraintSolver solver;
  size_t next = 0;
  int64_t iterations = 0;
  for (auto _ : state) {
    const Problem& p = set[next];
    next = (next + 1) % set.size();
    const GaussSolution& solution = solver.solve(p.mass, p.unconstrained, p.constraints);
    benchmark::DoNotOptimize(solution.acceleration.data());
    iterations += solution.iterations;
  }
  state.counters["qp_iterations"] =
      benchmark::Counter(static_cast<double>(iterations), benchmark::Counter::kAvgIterations);
}

// Warm start from the active set found for the same contacts: a resting
// contact, where the previous update's active set is usually still right.
void BM_gauss_warm(benchmark::State& state) {
  const std::vector<Problem> set = problems(static_cast<int>(state.range(0)));
  GaussLeastConstraintSolver solver;
  size_t next = 0;
  int64_t iterations = 0;
  for (auto _ : state) {
    const Problem& p = set[next];
    next = (next + 1) % set.size();
    const GaussSolution& solution =
        solver.solve(p.mass, p.unconstrained, p.constraints, p.previous_active);
    benchmark::DoNotOptimize(solution.acceleration.data());
    iterations += solution.iterations;
  }
  state.counters["qp_iterations"] =
      benchmark::Counter(static_cast<double>(iterations), benchmark::Counter::kAvgIterations);
}

BENCHMARK(BM_gauss_cold)->Arg(4)->Arg(16)->Arg(64)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_gauss_warm)->Arg(4)->Arg(16)->Arg(64)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace hb

BENCHMARK_MAIN();
