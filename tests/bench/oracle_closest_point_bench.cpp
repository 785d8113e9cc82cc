// Cost of one closest-point query of the ground-truth oracles on a real
// model: bunny00 scaled to about 0.2 m, 10,000 points within 3 mm of its
// surface (where a tool's samples are when it touches). One benchmark per
// backend, sharing the fixture. Reports time per query (time_per_query,
// seconds) and queries per second (items_per_second).
// Run: build/tests/bench/oracle_closest_point_bench
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "harness/mesh_io/mesh_io.h"
#include "harness/reference/oracle.h"

namespace hb {
namespace {

constexpr double kScale = 0.2;         // m per file unit
constexpr double kMaxOffsetM = 0.003;  // points lie within this of the surface
constexpr int kQueryCount = 10000;
constexpr uint64_t kSeed = 20240607;

// The scene (bunny00 as one object) and the query points, loaded once for
// every benchmark of this file.
struct BunnyQueries {
  bool loaded = false;
  std::string error;
  std::vector<SceneObject> scene;
  std::vector<Vec3> points;  // m, world frame
};

// Random surface points (a random triangle, a uniform random point in it)
// moved along the triangle's normal by a uniform offset in ±3 mm.
std::vector<Vec3> points_near_surface(const TriangleMesh& mesh) {
  std::mt19937_64 random(kSeed);
  std::uniform_int_distribution<std::size_t> triangle(0, mesh.triangles.size() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> offset(-kMaxOffsetM, kMaxOffsetM);
  std::vector<Vec3> points;
  points.reserve(kQueryCount);
  for (int i = 0; i < kQueryCount; ++i) {
    const std::size_t t = triangle(random);
    double u = unit(random);
    double v = unit(random);
    if (u + v > 1) {  // fold the square onto the triangle: uniform in it
      u = 1 - u;
      v = 1 - v;
    }
    const auto& [a, b, c] = mesh.triangles[t];
    const Vec3 on_surface = mesh.vertices[a] + u * (mesh.vertices[b] - mesh.vertices[a]) +
                            v * (mesh.vertices[c] - mesh.vertices[a]);
    points.push_back(on_surface + offset(random) * mesh.face_normal(t));
  }
  return points;
}

const BunnyQueries& bunny_queries() {
  static const BunnyQueries queries = [] {
    BunnyQueries q;
    const std::string path = HAPTICBENCH_SOURCE_DIR "/models/bunny00.off";
    if (!std::filesystem::exists(path)) {
      q.error = path + " is missing";
      return q;
    }
    SceneObject bunny;
    bunny.name = "bunny00.off";
    bunny.mesh = read_mesh_file(path, kScale);
    q.points = points_near_surface(bunny.mesh);
    q.scene.push_back(std::move(bunny));
    q.loaded = true;
    return q;
  }();
  return queries;
}

// Shared fixture: the bunny scene and its query points.
class BunnyClosestPoint : public benchmark::Fixture {
 public:
  void SetUp(benchmark::State& state) override {
    queries_ = &bunny_queries();
    if (!queries_->loaded) state.SkipWithError(queries_->error.c_str());
  }

 protected:
  // Times closest-point queries of all points per iteration (only closest
  // points asked for, as the penetration measure asks for them).
  void run_queries(benchmark::State& state, const Oracle& oracle) {
    PointQueryRequest request;
    request.points = queries_->points;
    request.want_inside = false;
    request.want_closest = true;
    PointQueryResult result;
    for (auto _ : state) {
      oracle.query_points(request, result);
      benchmark::DoNotOptimize(result.distance.data());
      benchmark::ClobberMemory();
    }
    const auto count = static_cast<int64_t>(queries_->points.size());
    state.SetItemsProcessed(state.iterations() * count);
    state.counters["time_per_query"] = benchmark::Counter(
        static_cast<double>(count),
        benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  }

  const BunnyQueries* queries_ = nullptr;
};

BENCHMARK_DEFINE_F(BunnyClosestPoint, Embree)(benchmark::State& state) {
  if (!queries_->loaded) return;
  const auto oracle = make_embree_oracle(queries_->scene);
  run_queries(state, *oracle);
}
BENCHMARK_REGISTER_F(BunnyClosestPoint, Embree)->Unit(benchmark::kMillisecond);

BENCHMARK_DEFINE_F(BunnyClosestPoint, Cgal)(benchmark::State& state) {
  if (!queries_->loaded) return;
  const auto oracle = make_cgal_oracle(queries_->scene);
  run_queries(state, *oracle);
}
BENCHMARK_REGISTER_F(BunnyClosestPoint, Cgal)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hb

BENCHMARK_MAIN();
