// Cost of one Voxmap PointShell tick (Renderer::step) against voxel size:
// a 2 cm sphere over a slab, far away (the bounding test alone), hovering
// 1 mm above it (tree leaves near the proximity layers looked up) and pressed
// 3 mm in. Run: build/tests/bench/voxmap_pointshell_bench
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "algorithms/voxmap_pointshell/voxmap_pointshell.h"
#include "hapticbench/mass_properties.h"
#include "hapticbench/shapes.h"

namespace hb {
namespace {

RenderContext sphere_over_slab() {
  RenderContext context;
  SceneObject slab;
  slab.name = "slab";
  slab.shape = Shape{ShapeType::kBox, Vec3(0.4, 0.4, 0.02)};
  slab.mesh = shape_mesh(*slab.shape);
  slab.pose.p = Vec3(0, 0, -0.01);
  context.scene.push_back(slab);
  Shape sphere;
  sphere.type = ShapeType::kSphere;
  sphere.radius = 0.02;
  sphere.subdivisions = 4;
  context.tool.shape = sphere;
  context.tool.mesh = shape_mesh(sphere);
  context.tool.mass = mass_properties_from_density(context.tool.mesh, 1000);
  context.reach = Eigen::AlignedBox3d(Vec3(-0.05, -0.05, -0.03), Vec3(0.05, 0.05, 0.1));
  return context;
}

// state.range(0): voxel size in µm; state.range(1): 0 far, 1 hovering, 2 pressed.
void run_steps(benchmark::State& state, const std::string& variant) {
  const RenderContext context = sphere_over_slab();
  ParamSet params;
  params.set("voxel_size", static_cast<double>(state.range(0)) * 1e-6);
  params.set("variant", variant);
  params.set("cache", false);
  auto renderer = create_voxmap_pointshell(context, params);
  const double heights[] = {0.08, 0.021, 0.017};
  // Lowered from clear of the slab (a tool started inside it has no
  // surface voxels to push it out), then left to settle.
  DeviceSample sample;
  const double start = 0.03, target = heights[state.range(1)];
  sample.pose.p = Vec3(0, 0, start);
  renderer->reset(sample.pose);
  for (int k = 0; k < 1000; ++k, ++sample.tick) {
    sample.pose.p.z() = start + (target - start) * std::min(1.0, k / 500.0);
    renderer->step(sample);
  }
  int64_t contacts = 0;
  for (auto _ : state) {
    // A slow circle keeps the device moving.
    sample.pose.p.x() = 0.001 * std::sin(1e-3 * static_cast<double>(sample.tick));
    TickResult result = renderer->step(sample);
    benchmark::DoNotOptimize(result.display.force);
    contacts += static_cast<int64_t>(result.contacts.size());
    ++sample.tick;
    sample.t_ns += 1'000'000;
  }
  state.counters["contacts"] =
      benchmark::Counter(static_cast<double>(contacts), benchmark::Counter::kAvgIterations);
}

void BM_voxmap(benchmark::State& state) { run_steps(state, "voxmap"); }
void BM_signed_distance(benchmark::State& state) { run_steps(state, "signed_distance"); }

void voxel_sizes(benchmark::internal::Benchmark* b) {
  for (const int64_t um : {4000, 2000, 1000, 500})
    for (const int64_t where : {0, 1, 2}) b->Args({um, where});
}

BENCHMARK(BM_voxmap)->Apply(voxel_sizes);
BENCHMARK(BM_signed_distance)->Apply(voxel_sizes);

}  // namespace
}  // namespace hb

BENCHMARK_MAIN();
