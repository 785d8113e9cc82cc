// The sensation-preserving renderer as a whole: hierarchies of tool and
// scene, the contact query on the slow loop, clustering, and the penalty
// proxy integrated with implicit Euler. Checked against closed forms of a
// proxy at rest between the coupling and k per contact plane.
#include "algorithms/sensation_preserving/sensation_preserving.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "hapticbench/input_error.h"
#include "hapticbench/shapes.h"
#include "tests/support/proxy_fixtures.h"
#include "tests/support/render_fixtures.h"
#include "tests/support/scratch_dir.h"

namespace hb {
namespace {

constexpr double kSphereRadius = 0.02;
constexpr double kContactStiffness = 10000;  // N/m per contact plane

SceneObject box_with_mesh(const Vec3& size, const Vec3& centre, const std::string& hash) {
  SceneObject object = test::box_object(size, Pose{centre, Quat::Identity()});
  object.mesh = shape_mesh(*object.shape);
  object.content_hash = hash;
  return object;
}

// A 2 cm icosphere over a slab whose top face is z = 0.
RenderContext sphere_over_slab() { return test::sphere_over_slab(3); }

// A 3 cm box over a floor of 2 × 2 cm tiles (tops at z = 0) whose centre
// lies on a corner shared by four tiles: its bottom face rests on exactly
// four of them, 1.5 cm squares each, and is 5 mm from the others.
RenderContext box_over_tiles() {
  RenderContext context;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      context.scene.push_back(box_with_mesh(
          Vec3(0.02, 0.02, 0.01), Vec3(-0.03 + 0.02 * i, -0.03 + 0.02 * j, -0.005), "tile"));
  context.tool = test::box_tool(Vec3(0.03, 0.03, 0.02), 500);
  context.tool.content_hash = "box";
  context.coupling = test::example_gains();
  return context;
}

// The test's defaults (no disk cache, kContactStiffness) under `values`.
ParamSet params_of(std::initializer_list<std::pair<const char*, ParamValue>> values) {
  ParamSet params = test::params_of({{"cache", false}, {"contact_stiffness", kContactStiffness}});
  for (const auto& [key, value] : values) params.set(key, value);
  return params;
}

// The device lowered at 1 cm/s along z from `start_z` to `end_z`, then held.
std::vector<DeviceSample> press_trace(double start_z, double end_z, int hold_ticks) {
  std::vector<DeviceSample> samples;
  const double speed = 0.01;
  const int descent = static_cast<int>(std::ceil((start_z - end_z) / (speed * 1e-3)));
  for (int k = 0; k < descent + hold_ticks; ++k) {
    DeviceSample s;
    s.tick = k;
    s.t_ns = k * 1'000'000LL;
    s.pose.p = Vec3(0, 0, k < descent ? start_z - speed * 1e-3 * k : end_z);
    if (k < descent) s.twist.v = Vec3(0, 0, -speed);
    samples.push_back(s);
  }
  return samples;
}

// Each tick runs the contact query and installs it before the haptic step
// (the multi-rate emulation with a latency of one query per tick).
TickResult run(Renderer& renderer, const std::vector<DeviceSample>& trace,
               int* largest_contact_count = nullptr) {
  renderer.reset(trace.front().pose);
  SlowLoop* slow = renderer.slow_loop();
  REQUIRE(slow != nullptr);
  TickResult last;
  for (const DeviceSample& s : trace) {
    slow->install_slow_result(slow->run_slow_update());
    last = renderer.step(s);
    if (largest_contact_count)
      *largest_contact_count =
          std::max(*largest_contact_count, static_cast<int>(last.contacts.size()));
  }
  return last;
}

// Lowest z of the mesh's vertices in the tool frame (m, < 0).
double lowest_vertex_z(const TriangleMesh& mesh) {
  double lowest = 0;
  for (const Vec3& v : mesh.vertices) lowest = std::min(lowest, v.z());
  return lowest;
}

TEST_CASE("sphere pressed on a slab: at rest, the coupling and one contact of stiffness k balance",
          "[sensation_preserving]") {
  const RenderContext context = sphere_over_slab();
  const double k_t = context.coupling.k_t;
  // The device's lowest mesh point 4 mm below the slab's top.
  const double depth = 0.004;
  const double device_z = -lowest_vertex_z(context.tool.mesh) - depth;
  auto renderer = create_sensation_preserving(context, params_of({}));
  const TickResult last = run(*renderer, press_trace(device_z + 0.006, device_z, 1500));
  // Springs in series: the proxy sinks p = k_t d / (k + k_t) and the device
  // displays k_t (d − p) upwards.
  const double sink = k_t * depth / (kContactStiffness + k_t);
  const double ideal = k_t * (depth - sink);
  INFO("force " << last.display.force.transpose() << ", ideal " << ideal);
  CHECK(last.display.force.z() == Approx(ideal).epsilon(1e-3));
  CHECK(last.display.force.head<2>().norm() <= 1e-6 * ideal);
  CHECK(last.display.torque.norm() <= 1e-6);
  const double proxy_lowest = last.proxy.p.z() + lowest_vertex_z(context.tool.mesh);
  CHECK(-proxy_lowest == Approx(sink).epsilon(1e-3));
  // It reports its one contact on the slab's top face, pushing up, as deep as the proxy sank.
  REQUIRE(last.contacts.size() == 1);
  CHECK(last.contacts[0].normal.z() == Approx(1).margin(1e-9));
  CHECK(last.contacts[0].depth == Approx(sink).epsilon(1e-3));
}

TEST_CASE("a flat face on four tiles: unclustered stiffness is 4k, one cluster keeps it k",
          "[sensation_preserving]") {
  const RenderContext context = box_over_tiles();
  const double k_t = context.coupling.k_t;
  const double depth = 0.003;            // device face below the tiles' tops, m
  const double device_z = 0.01 - depth;  // box half height 1 cm
  const std::vector<DeviceSample> trace = press_trace(device_z + 0.005, device_z, 1500);
  struct Case {
    int clusters;
    int contacts;  // planes the proxy rests on
  };
  for (const Case c : {Case{0, 4}, Case{1, 1}, Case{4, 4}}) {
    auto renderer = create_sensation_preserving(
        context, params_of({{"clusters", static_cast<double>(c.clusters)}}));
    int most_contacts = 0;
    const TickResult last = run(*renderer, trace, &most_contacts);
    const double k = c.contacts * kContactStiffness;
    const double sink = k_t * depth / (k + k_t);
    INFO("clusters " << c.clusters << ": force " << last.display.force.transpose());
    CHECK(most_contacts == c.contacts);
    CHECK(last.display.force.z() == Approx(k_t * (depth - sink)).epsilon(2e-3));
    CHECK(0.01 - last.proxy.p.z() == Approx(sink).epsilon(2e-3));
    // Symmetric: no sideways force, no torque, the proxy does not tilt.
    CHECK(last.display.force.head<2>().norm() <= 1e-6);
    CHECK(last.display.torque.norm() <= 1e-7);
    CHECK(std::abs(last.proxy.q.w()) == Approx(1).margin(1e-9));
  }
}

TEST_CASE("replays are deterministic, and cached hierarchies render the same as built ones",
          "[sensation_preserving]") {
  test::ScratchDir dir("sensation_preserving_renderer_cache");
  ::setenv("HAPTICBENCH_CACHE_DIR", dir.path().c_str(), 1);
  const RenderContext context = box_over_tiles();
  std::vector<DeviceSample> trace = press_trace(0.012, 0.008, 300);
  // Slide and turn under load so that contacts come and go.
  for (int k = 0; k < 600; ++k) {
    DeviceSample s = trace.back();
    s.tick += 1;
    s.t_ns += 1'000'000LL;
    s.pose.p += Vec3(2e-5, 1e-5, 0);
    s.pose.q = (Quat(Eigen::AngleAxisd(2e-4, Vec3::UnitZ())) * s.pose.q).normalized();
    trace.push_back(s);
  }
  ParamSet cached = params_of({{"clusters", 3.0}});
  cached.set("cache", true);
  auto built = create_sensation_preserving(context, cached);
  auto loaded = create_sensation_preserving(context, cached);
  auto uncached = create_sensation_preserving(context, params_of({{"clusters", 3.0}}));
  CHECK_FALSE(built->build_report().cache_hit);
  CHECK(loaded->build_report().cache_hit);
  CHECK_FALSE(uncached->build_report().cache_hit);
  std::vector<Wrench> first;
  for (Renderer* r : {built.get(), loaded.get(), uncached.get(), built.get()}) {
    r->reset(trace.front().pose);
    std::vector<Wrench> displays;
    for (const DeviceSample& s : trace) {
      r->slow_loop()->install_slow_result(r->slow_loop()->run_slow_update());
      displays.push_back(r->step(s).display);
    }
    if (first.empty()) {
      first = displays;
      continue;
    }
    for (std::size_t i = 0; i < displays.size(); ++i) {
      REQUIRE(displays[i].force == first[i].force);
      REQUIRE(displays[i].torque == first[i].torque);
    }
  }
  ::unsetenv("HAPTICBENCH_CACHE_DIR");
}

TEST_CASE("the build report names the hierarchies' sizes", "[sensation_preserving]") {
  const RenderContext context = box_over_tiles();
  const BuildReport report = create_sensation_preserving(context, params_of({}))->build_report();
  const auto detail = [&](const std::string& name) {
    for (const auto& [key, value] : report.details)
      if (key == name) return value;
    FAIL("no detail " << name);
    return 0.0;
  };
  CHECK(detail("tool_pieces") == 1);    // a box is one convex patch
  CHECK(detail("scene_pieces") == 16);  // one per tile
  CHECK(report.memory_bytes > 0);
}

TEST_CASE("sensation_preserving: bad parameters are named by field", "[sensation_preserving]") {
  const auto location_of = [](const ParamSet& params) -> std::string {
    try {
      create_sensation_preserving(sphere_over_slab(), params);
    } catch (const InputError& error) {
      return error.location();
    }
    return "(no error)";
  };
  const std::string p = "/algorithms/0/params/";
  CHECK(location_of(params_of({{"perceptibility_threshold", -0.1}})) ==
        p + "perceptibility_threshold");
  CHECK(location_of(params_of({{"clusters", -1.0}})) == p + "clusters");
  CHECK(location_of(params_of({{"clusters", 2.5}})) == p + "clusters");
  CHECK(location_of(params_of({{"contact_margin", -0.001}})) == p + "contact_margin");
  CHECK(location_of(params_of({{"max_piece_vertices", 3.0}})) == p + "max_piece_vertices");
  CHECK(location_of(params_of({{"contact_stiffness", -1.0}})) == p + "contact_stiffness");
  CHECK(location_of(params_of({{"integrator", std::string("rk4")}})) == p + "integrator");
  CHECK(location_of(params_of({{"cache", 1.0}})) == p + "cache");
}

}  // namespace
}  // namespace hb
