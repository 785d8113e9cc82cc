// The voxmap_pointshell renderer (algorithms/voxmap_pointshell/
// voxmap_pointshell.cpp) end to end on a sphere pressed onto a slab: the
// displayed force against the closed form of ideal rigid contact, the
// contacts it reports, determinism with and without the on-disk cache, the
// reach box, free-space ticks, and parameter errors. Units m, N, s.
#include "algorithms/voxmap_pointshell/voxmap_pointshell.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <numbers>
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

// A 2 cm sphere over a slab whose top face is z = top_z; the reach box is
// the region the presses below use.
RenderContext sphere_over_slab(double top_z = 0) {
  RenderContext context = test::sphere_over_slab(4, top_z);
  context.reach = Eigen::AlignedBox3d(Vec3(-0.03, -0.03, -0.01), Vec3(0.03, 0.03, 0.06));
  return context;
}

using test::params_of;

// The device lowered at `speed` (m/s) from 4 mm above contact with a
// surface at z = top_z to `depth` below it, then held (sphere centre on the
// z axis), then moved sideways for slide_ticks, or with `lift` raised back
// at the same speed.
std::vector<DeviceSample> press_trace(double depth, int hold_ticks, int slide_ticks = 0,
                                      double top_z = 0, double speed = 0.01, bool lift = false) {
  std::vector<DeviceSample> samples;
  const double start = top_z + kSphereRadius + 0.004;
  const double end = top_z + kSphereRadius - depth;
  const int descent = static_cast<int>(std::ceil((start - end) / (speed * 1e-3)));
  const int ticks = descent + hold_ticks + slide_ticks + (lift ? descent : 0);
  for (int k = 0; k < ticks; ++k) {
    DeviceSample s;
    s.tick = k;
    s.t_ns = k * 1'000'000LL;
    const double t = (k - descent - hold_ticks) * 1e-3;  // s after the hold
    if (k < descent) {
      s.pose.p = Vec3(0, 0, start - speed * 1e-3 * k);
      s.twist.v = Vec3(0, 0, -speed);
    } else if (k < descent + hold_ticks) {
      s.pose.p = Vec3(0, 0, end);
    } else if (lift) {
      s.pose.p = Vec3(0, 0, std::min(start, end + speed * t));
      s.twist.v = Vec3(0, 0, speed);
    } else {
      s.pose.p = Vec3(0.01 * t, 0.004 * t, end);
      s.twist.v = Vec3(0.01, 0.004, 0);
    }
    samples.push_back(s);
  }
  return samples;
}

double result_centre_z(const TickResult& result) { return result.proxy.p.z(); }

TickResult run(Renderer& renderer, const std::vector<DeviceSample>& trace) {
  renderer.reset(trace.front().pose);
  TickResult last;
  for (const DeviceSample& s : trace) last = renderer.step(s);
  return last;
}

TEST_CASE("sphere pressed on a slab: the display is k_t·d within the voxel-size bound",
          "[voxmap_pointshell]") {
  const double depth = 0.004;  // device below the surface, m
  // The slab's top on a plane of voxel centres, and between them.
  for (const double top_z : {0.0, 0.00073}) {
    const RenderContext context = sphere_over_slab(top_z);
    const double ideal = context.coupling.k_t * depth;
    for (const char* variant : {"voxmap", "signed_distance"}) {
      for (const double h : {0.002, 0.001}) {
        auto renderer = create_voxmap_pointshell(
            context,
            params_of({{"voxel_size", h}, {"variant", std::string(variant)}, {"cache", false}}));
        const TickResult last = run(*renderer, press_trace(depth, 1500, 0, top_z));
        // At rest, the display is the coupling spring k_t (x_p − x_h): its
        // error against k_t·d is k_t times the proxy's penetration, which the
        // voxel size bounds: the surface layer is within h/2 of the surface
        // and each point within √3/2 h of the tool's, so the proxy rests
        // within √3 h (equal spacing) of the surface.
        const double bound = context.coupling.k_t * std::sqrt(3.0) * h;
        const double penetration = top_z + kSphereRadius - result_centre_z(last);
        INFO("top " << top_z << " " << variant << " h = " << h << ": force "
                    << last.display.force.transpose() << ", proxy penetration " << penetration);
        CHECK(std::abs(last.display.force.z() - ideal) <= bound);
        CHECK(last.display.force.head<2>().norm() <= bound);
        CHECK(std::abs(penetration) <= std::sqrt(3.0) * h);
        CHECK(last.display.force.allFinite());
        // The contacts it reports are on the slab's top face, pushing up;
        // braking points (depth < 0) are above it at their distance.
        int pushing = 0;
        for (const Contact& c : last.contacts) {
          CHECK(c.normal.z() > 0.7);
          if (c.depth > 0) {
            ++pushing;
            CHECK(std::abs(c.point.z() - top_z) <= std::sqrt(3.0) * h);
          } else {
            CHECK(c.point.z() - top_z == Approx(-c.depth).margin(1e-6));
          }
        }
        CHECK(pushing > 0);
      }
    }
  }
}

TEST_CASE("the signed-distance variant gives no energy away over a press-and-release loop",
          "[voxmap_pointshell]") {
  // A tilted 3 cm cube pressed 3 mm into the slab and released along
  // another path, turning as it goes: a closed loop in position and
  // orientation. The passivity observer's energy (the work the device port
  // receives, as in the run metrics) must never go below zero: the force
  // is minus the gradient of ½ K Σ φ(P_i)². With each point's own normal as
  // the force's direction it went to −0.37 mJ on armadillo_on_bunny.
  RenderContext context = sphere_over_slab();
  context.tool = test::box_tool(Vec3::Constant(0.03));
  context.tool.content_hash = "cube";
  auto renderer = create_voxmap_pointshell(
      context,
      params_of(
          {{"voxel_size", 0.001}, {"variant", std::string("signed_distance")}, {"cache", false}}));
  constexpr int kTicks = 2000;
  constexpr double kDt = 1e-3;
  const auto pose_at = [&](int k) {
    const double phase = 2 * std::numbers::pi * k / kTicks;
    const Quat q = quat_from_rotation_vector(
        Vec3(0.3 + 0.1 * std::sin(phase), 0.1 * (1 - std::cos(phase)), 0.05 * std::sin(phase)));
    double lowest = 0;  // the cube's lowest corner below its centre
    for (const Vec3& v : context.tool.mesh.vertices) lowest = std::min(lowest, (q * v).z());
    const double press = std::sin(0.5 * phase);
    return Pose{Vec3(0.008 * std::sin(phase), 0.004 * (1 - std::cos(phase)),
                     -lowest + 0.003 - 0.006 * press * press),
                q};
  };
  renderer->reset(pose_at(0));
  double energy = 0, lowest_energy = 0, largest_force = 0;
  for (int k = 0; k < kTicks; ++k) {
    DeviceSample sample;
    sample.tick = k;
    sample.t_ns = k * 1'000'000LL;
    sample.pose = pose_at(k);
    const Pose previous = pose_at(k - 1), next = pose_at(k + 1);
    sample.twist.v = (next.p - previous.p) / (2 * kDt);
    sample.twist.w = rotation_vector(next.q * previous.q.conjugate()) / (2 * kDt);
    const TickResult result = renderer->step(sample);
    energy +=
        (-result.display.force.dot(sample.twist.v) - result.display.torque.dot(sample.twist.w)) *
        kDt;
    lowest_energy = std::min(lowest_energy, energy);
    largest_force = std::max(largest_force, result.display.force.norm());
  }
  INFO("lowest energy " << lowest_energy << " J, final " << energy << " J, largest force "
                        << largest_force << " N");
  CHECK(largest_force > 3.0);  // it was pressed (k_t · 3 mm = 6 N at the deepest)
  CHECK(lowest_energy >= -1e-6);
}

TEST_CASE("a fast press: the proxy stays near the surface, contacts push along the face normal",
          "[voxmap_pointshell]") {
  // The device drops at 2 m/s from 4 mm above the slab to 6 mm into it,
  // holds, and leaves at 2 m/s; soft points (3,000 N/m) at 0.5 mm voxels,
  // so that points cross the one-voxel surface layer within a tick. Ground
  // truth is the plane: the sphere's penetration is top − (centre − R) and
  // the face normal is +z. (With interior voxels exerting nothing, as in
  // McNeely's voxmap, the voxmap variant's proxy sank 5.2 mm here.)
  const RenderContext context = sphere_over_slab();
  const double h = 0.0005, depth = 0.006;
  const std::vector<DeviceSample> trace = press_trace(depth, 300, 0, 0, 2.0, true);
  for (const char* variant : {"voxmap", "signed_distance"}) {
    auto renderer = create_voxmap_pointshell(context, params_of({{"voxel_size", h},
                                                                 {"variant", std::string(variant)},
                                                                 {"cache", false},
                                                                 {"point_stiffness", 3000.0}}));
    renderer->reset(trace.front().pose);
    double device_deepest = 0, proxy_deepest = 0, worst_angle = 0;
    int pushing = 0;
    for (const DeviceSample& sample : trace) {
      const TickResult result = renderer->step(sample);
      device_deepest = std::max(device_deepest, kSphereRadius - sample.pose.p.z());
      proxy_deepest = std::max(proxy_deepest, kSphereRadius - result.proxy.p.z());
      for (const Contact& c : result.contacts) {
        if (!(c.depth > 0)) continue;
        ++pushing;
        worst_angle = std::max(worst_angle, std::acos(std::clamp(c.normal.z(), -1.0, 1.0)));
      }
    }
    INFO(variant << ": device " << device_deepest << " m deep, proxy " << proxy_deepest
                 << " m, worst contact normal " << worst_angle * 180 / std::numbers::pi << " deg");
    CHECK(device_deepest == Approx(depth).margin(1e-9));
    // The proxy follows the device in free space, so it meets the slab at
    // the device's 2 m/s (the signed-distance variant then sinks 2.0 mm; a
    // proxy left at rest at the start lagged the device and sank 1.3 mm).
    CHECK(proxy_deepest <= 0.35 * device_deepest);
    CHECK(pushing > 100);
    if (std::string(variant) == "signed_distance") {
      // ∇φ of a plane is its normal (the corners of the slab are far).
      CHECK(worst_angle <= 2 * std::numbers::pi / 180);
    } else {
      // The tool point's normal: on the sphere, a point within the proxy's
      // depth (plus the surface layer's √3 h) of its lowest point.
      CHECK(std::cos(worst_angle) >= 1 - (proxy_deepest + std::sqrt(3.0) * h) / kSphereRadius);
    }
  }
}

TEST_CASE("explicit Euler presses stably at a stiffness its step allows", "[voxmap_pointshell]") {
  const RenderContext context = sphere_over_slab();
  // Explicit Euler needs (10·K_ff + k_t)·Δt < b_t (at most 10 points count
  // under the averaging rule), so the contact is soft: 2 N must fit in the
  // surface layer (h/2 = 2 mm) at 10·K_ff = 2500 N/m.
  const double h = 0.004;
  const double depth = 0.001;
  auto renderer =
      create_voxmap_pointshell(context, params_of({{"voxel_size", h},
                                                   {"integrator", std::string("explicit_euler")},
                                                   {"proxy_mass_kg", 0.2},
                                                   {"point_stiffness", 250.0},
                                                   {"braking_viscosity", 0.0},
                                                   {"cache", false}}));
  const std::vector<DeviceSample> trace = press_trace(depth, 1500);
  renderer->reset(trace.front().pose);
  TickResult last;
  for (const DeviceSample& s : trace) {
    last = renderer->step(s);
    REQUIRE(last.display.force.allFinite());
    REQUIRE((last.flags & kFlagProxyReset) == 0);
  }
  const double penetration = kSphereRadius - result_centre_z(last);
  INFO("force " << last.display.force.transpose() << ", proxy penetration " << penetration);
  CHECK(std::abs(last.display.force.z() - context.coupling.k_t * depth) <=
        context.coupling.k_t * std::sqrt(3.0) * h);
  CHECK(std::abs(penetration) <= std::sqrt(3.0) * h);
  CHECK_FALSE(last.contacts.empty());
}

TEST_CASE("replays are deterministic, and a cached voxmap renders the same as a built one",
          "[voxmap_pointshell]") {
  test::ScratchDir dir("vps_renderer_cache");
  ::setenv("HAPTICBENCH_CACHE_DIR", dir.path().c_str(), 1);
  const RenderContext context = sphere_over_slab();
  const std::vector<DeviceSample> trace = press_trace(0.003, 300, 400);
  for (const char* variant : {"voxmap", "signed_distance"}) {
    const ParamSet params = params_of({{"voxel_size", 0.002}, {"variant", std::string(variant)}});
    auto built = create_voxmap_pointshell(context, params);
    auto loaded = create_voxmap_pointshell(context, params);
    auto again = create_voxmap_pointshell(context, params);
    INFO(variant);
    // Both variants keep φ, so the second one finds the first one's voxmap
    // (and pointshell) in the cache.
    CHECK(built->build_report().cache_hit == (std::string(variant) == "signed_distance"));
    CHECK(loaded->build_report().cache_hit);
    for (Renderer* r : {built.get(), loaded.get(), again.get()}) r->reset(trace.front().pose);
    for (const DeviceSample& s : trace) {
      const TickResult a = built->step(s);
      const TickResult b = loaded->step(s);
      const TickResult c = again->step(s);
      for (const TickResult* other : {&b, &c}) {
        REQUIRE(a.display.force == other->display.force);
        REQUIRE(a.display.torque == other->display.torque);
        REQUIRE(a.proxy.p == other->proxy.p);
        REQUIRE(a.proxy.q.coeffs() == other->proxy.q.coeffs());
        REQUIRE(a.contacts.size() == other->contacts.size());
      }
    }
    // A reset replays the same ticks.
    built->reset(trace.front().pose);
    again->reset(trace.front().pose);
    for (const DeviceSample& s : trace) {
      const TickResult a = built->step(s);
      const TickResult b = again->step(s);
      REQUIRE(a.display.force == b.display.force);
    }
  }
  ::unsetenv("HAPTICBENCH_CACHE_DIR");
}

TEST_CASE("the build report names the pointshell and voxmap sizes", "[voxmap_pointshell]") {
  const RenderContext context = sphere_over_slab();
  auto renderer =
      create_voxmap_pointshell(context, params_of({{"voxel_size", 0.002}, {"cache", false}}));
  const BuildReport report = renderer->build_report();
  CHECK_FALSE(report.cache_hit);
  CHECK(report.memory_bytes > 0);
  const auto figure = [&](const std::string& name) {
    for (const auto& [key, value] : report.details)
      if (key == name) return value;
    FAIL("no " << name << " in the build report");
    return 0.0;
  };
  // About one point per 4 mm² of the sphere's 50 cm².
  const double area = 4 * M_PI * kSphereRadius * kSphereRadius;
  CHECK(figure("pointshell_points") > 0.9 * area / (0.002 * 0.002));
  CHECK(figure("pointshell_points") < 1.1 * area / (0.002 * 0.002));
  CHECK(figure("voxmap_surface_voxels") > 0);
  CHECK(figure("voxmap_vdb_bytes") > 0);
  CHECK(figure("voxmap_objects") == 1);
}

TEST_CASE("only scene objects within the reach box are voxelised", "[voxmap_pointshell]") {
  RenderContext context = sphere_over_slab();
  SceneObject far_slab = context.scene.front();  // the same slab, 2 m away
  far_slab.pose.p.x() += 2;
  context.scene.push_back(far_slab);
  auto renderer =
      create_voxmap_pointshell(context, params_of({{"voxel_size", 0.002}, {"cache", false}}));
  double objects = -1;
  for (const auto& [key, value] : renderer->build_report().details)
    if (key == "voxmap_objects") objects = value;
  CHECK(objects == 1);
}

TEST_CASE("a free-space tick looks up no points", "[voxmap_pointshell]") {
  const RenderContext context = sphere_over_slab();
  auto renderer =
      create_voxmap_pointshell(context, params_of({{"voxel_size", 0.002}, {"cache", false}}));
  DeviceSample s;
  s.pose.p = Vec3(0, 0, 0.05);
  renderer->reset(s.pose);
  for (int k = 0; k < 10; ++k) {
    s.tick = k;
    const TickResult result = renderer->step(s);
    CHECK(result.work.get("points_looked_up") == 0);
    CHECK(result.contacts.empty());
    CHECK(result.display.force.norm() < 1e-9);
  }
}

TEST_CASE("a 3 cm cube at 2 mm voxels renders its press, in both variants", "[voxmap_pointshell]") {
  // Its faces lie halfway between two layers of voxel centres (7.5 voxels
  // from its centre): the pointshell was empty and the run showed the
  // coupling alone.
  RenderContext context = sphere_over_slab();
  context.tool = test::box_tool(Vec3::Constant(0.03));
  context.tool.mesh = shape_mesh(*context.tool.shape);
  context.tool.content_hash = "cube 3 cm";
  for (const char* variant : {"voxmap", "signed_distance"}) {
    INFO(variant);
    const std::unique_ptr<Renderer> renderer = create_voxmap_pointshell(
        context, params_of({{"voxel_size", 0.002}, {"variant", std::string(variant)}}));
    // The cube's centre from 4 mm above contact (z = 1.5 cm) to 3 mm deep.
    std::vector<DeviceSample> trace;
    for (int k = 0; k < 1200; ++k) {
      DeviceSample s;
      s.tick = k;
      s.t_ns = k * 1'000'000LL;
      s.pose.p = Vec3(0, 0, std::max(0.012, 0.019 - 1e-5 * k));
      trace.push_back(s);
    }
    const TickResult last = run(*renderer, trace);
    CHECK_FALSE(last.contacts.empty());
    CHECK(last.display.force.z() > 2.0);  // about k_t × 3 mm against the face
  }
}

TEST_CASE("a tool within one voxel is refused, naming the spacing", "[voxmap_pointshell]") {
  // A 1.2 mm sphere centred between voxel centres (1 mm from each axis
  // plane at 2 mm voxels): no voxel centre inside, no surface voxel.
  RenderContext context = sphere_over_slab();
  context.tool = test::sphere_tool(0.0006);
  context.tool.shape->subdivisions = 2;
  context.tool.mesh = shape_mesh(*context.tool.shape);
  for (Vec3& vertex : context.tool.mesh.vertices) vertex += Vec3::Constant(0.001);
  context.tool.mass.centre_of_mass = Vec3::Constant(0.001);
  context.tool.content_hash = "sphere 0.6 mm between voxel centres";
  try {
    create_voxmap_pointshell(context, params_of({{"voxel_size", 0.002}}));
    FAIL("a 1.2 mm sphere at 2 mm voxels was accepted");
  } catch (const InputError& error) {
    CHECK(error.location() == "/algorithms/0/params/voxel_size");
    CHECK(std::string(error.what()).find("no surface voxel") != std::string::npos);
  }
}

TEST_CASE("bad parameters are named by field", "[voxmap_pointshell]") {
  const auto location_of = [](const ParamSet& params,
                              const RenderContext& in = sphere_over_slab()) -> std::string {
    try {
      create_voxmap_pointshell(in, params);
    } catch (const InputError& error) {
      return error.location();
    }
    return "(no error)";
  };
  const std::string p = "/algorithms/0/params/";
  CHECK(location_of(params_of({{"voxel_size", -0.001}})) == p + "voxel_size");
  CHECK(location_of(params_of({{"voxel_size", std::string("fine")}})) == p + "voxel_size");
  CHECK(location_of(params_of({{"pointshell_spacing", 0.0}})) == p + "pointshell_spacing");
  CHECK(location_of(params_of({{"point_stiffness", -5.0}})) == p + "point_stiffness");
  CHECK(location_of(params_of({{"variant", std::string("octree")}})) == p + "variant");
  CHECK(location_of(params_of({{"proximity_layers", 1.5}})) == p + "proximity_layers");
  CHECK(location_of(params_of({{"braking_viscosity", -1.0}})) == p + "braking_viscosity");
  CHECK(location_of(params_of({{"point_budget", -1.0}})) == p + "point_budget");
  CHECK(location_of(params_of({{"point_budget", 100.5}})) == p + "point_budget");
  CHECK(location_of(params_of({{"integrator", std::string("rk4")}})) == p + "integrator");
  CHECK(location_of(params_of({{"cache", 1.0}})) == p + "cache");
  CHECK(location_of(params_of({{"voxel_sise", 0.001}})) == p + "voxel_sise");
  // interior_layers (how deep φ is kept) is read by both variants.
  CHECK(location_of(params_of({{"interior_layers", 2.5}})) == p + "interior_layers");
  CHECK(location_of(params_of({{"variant", std::string("signed_distance")},
                               {"interior_layers", 0.0}})) == p + "interior_layers");
  // Without a proximity layer the signed-distance force is no potential's
  // gradient (a loop generated 51 µJ); the voxmap variant may have none.
  CHECK(location_of(params_of({{"variant", std::string("signed_distance")},
                               {"proximity_layers", 0.0}})) == p + "proximity_layers");
  CHECK(location_of(params_of({{"proximity_layers", 0.0}})) == "(no error)");
  // An open surface has no inside for the signed-distance variant.
  RenderContext open_scene = sphere_over_slab();
  open_scene.scene[0].distance_only = true;
  CHECK(location_of(params_of({{"variant", std::string("signed_distance")}}), open_scene) ==
        p + "variant");
  // Sizes that would need unreasonable memory are refused before any work.
  RenderContext whole_scene = sphere_over_slab();
  whole_scene.reach.reset();
  CHECK(location_of(params_of({{"voxel_size", 2e-5}, {"pointshell_spacing", 0.002}}),
                    whole_scene) == p + "voxel_size");
  CHECK(location_of(params_of({{"voxel_size", 0.002}, {"pointshell_spacing", 1e-5}})) ==
        p + "pointshell_spacing");
}

}  // namespace
}  // namespace hb
