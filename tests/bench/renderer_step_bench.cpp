// Cost of one haptic tick (Renderer::step) for the baseline renderers, in
// free space and in contact. Run: build/tests/bench/renderer_step_bench
#include <benchmark/benchmark.h>

#include <cmath>

#include "algorithms/registry.h"
#include "hapticbench/mass_properties.h"
#include "hapticbench/shapes.h"

namespace hb {
namespace {

RenderContext box_scene_with(const Shape& tool_shape) {
  RenderContext context;
  SceneObject box;
  box.name = "box";
  box.shape = Shape{ShapeType::kBox, Vec3(0.4, 0.4, 0.02)};
  box.mesh = shape_mesh(*box.shape);
  box.pose.p = Vec3(0, 0, -0.01);
  context.scene.push_back(box);
  context.tool.shape = tool_shape;
  context.tool.mesh = shape_mesh(tool_shape);
  context.tool.mass = mass_properties_from_density(context.tool.mesh, 1000);
  return context;
}

Shape sphere() {
  Shape s;
  s.type = ShapeType::kSphere;
  s.radius = 0.02;
  s.subdivisions = 3;
  return s;
}

Shape cube() {
  Shape s;
  s.type = ShapeType::kBox;
  s.size = Vec3(0.04, 0.04, 0.04);
  return s;
}

// state.range(0): 0 free space (tool 5 cm above the box), 1 pressed 3 mm in.
void run_steps(benchmark::State& state, const std::string& algorithm, const Shape& tool,
               ParamSet params) {
  const RenderContext context = box_scene_with(tool);
  auto renderer = create_renderer(algorithm, context, params, "name");
  const double half_height = tool.type == ShapeType::kSphere ? tool.radius : 0.5 * tool.size.z();
  const double z = state.range(0) == 0 ? 0.05 : half_height - 0.003;
  DeviceSample sample;
  sample.pose.p = Vec3(0, 0, z);
  renderer->reset(sample.pose);
  for (auto _ : state) {
    // A slow circle keeps the device moving so nothing is trivially cached.
    sample.pose.p.x() = 0.001 * std::sin(1e-3 * static_cast<double>(sample.tick));
    TickResult result = renderer->step(sample);
    benchmark::DoNotOptimize(result.display.force);
    ++sample.tick;
    sample.t_ns += 1'000'000;
  }
}

void BM_coupling_only(benchmark::State& state) { run_steps(state, "coupling_only", sphere(), {}); }
void BM_penalty_sphere_implicit(benchmark::State& state) {
  run_steps(state, "penalty_analytic", sphere(), {});
}
void BM_penalty_sphere_explicit(benchmark::State& state) {
  ParamSet params;
  params.set("integrator", std::string("explicit_euler"));
  run_steps(state, "penalty_analytic", sphere(), params);
}
void BM_penalty_sphere_quasi_static(benchmark::State& state) {
  ParamSet params;
  params.set("proxy", std::string("quasi_static"));
  run_steps(state, "penalty_analytic", sphere(), params);
}
void BM_penalty_cube_implicit(benchmark::State& state) {
  run_steps(state, "penalty_analytic", cube(), {});
}

BENCHMARK(BM_coupling_only)->Arg(0);
BENCHMARK(BM_penalty_sphere_implicit)->Arg(0)->Arg(1);
BENCHMARK(BM_penalty_sphere_explicit)->Arg(0)->Arg(1);
BENCHMARK(BM_penalty_sphere_quasi_static)->Arg(0)->Arg(1);
BENCHMARK(BM_penalty_cube_implicit)->Arg(0)->Arg(1);

}  // namespace
}  // namespace hb

BENCHMARK_MAIN();
