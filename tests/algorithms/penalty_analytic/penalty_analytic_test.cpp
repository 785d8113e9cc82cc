#include "algorithms/penalty_analytic/penalty_analytic.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "hapticbench/input_error.h"
#include "tests/support/proxy_fixtures.h"

namespace hb {
namespace {

constexpr double kToolRadius = 0.02;
constexpr double kCouplingStiffness = 2000;
constexpr double kContactStiffness = 3000;

// A 0.4 × 0.4 × 0.02 m slab whose top face is the plane z = 0.
RenderContext press_context(const Tool& tool) {
  RenderContext context;
  context.scene.push_back(
      test::box_object(Vec3(0.4, 0.4, 0.02), Pose{Vec3(0, 0, -0.01), Quat::Identity()}));
  context.tool = tool;
  context.coupling = test::example_gains();
  return context;
}

ParamSet make_params(std::vector<std::pair<std::string, ParamValue>> values) {
  ParamSet params("/algorithms/0/params");
  for (auto& [key, value] : values) params.set(key, value);
  return params;
}

// Device approaching from `start` to `hold` along a line in 500 ticks, then held.
DeviceSample press_sample(int64_t tick, const Vec3& start, const Vec3& hold) {
  DeviceSample sample;
  sample.tick = tick;
  sample.t_ns = tick * 1'000'000;
  const double s = std::min(1.0, static_cast<double>(tick) / 500.0);
  sample.pose.p = start + s * (hold - start);
  if (tick < 500) sample.twist.v = (hold - start) / 0.5;
  return sample;
}

TickResult run_press(Renderer& renderer, const Vec3& start, const Vec3& hold, int64_t ticks) {
  renderer.reset(Pose{start, Quat::Identity()});
  TickResult result;
  for (int64_t k = 0; k < ticks; ++k) result = renderer.step(press_sample(k, start, hold));
  return result;
}

TEST_CASE("sphere pressed into a box face displays the series spring force", "[penalty_analytic]") {
  const RenderContext context = press_context(test::sphere_tool(kToolRadius));
  const double device_penetration = 0.005;
  const Vec3 start(0.01, -0.02, 0.03);
  const Vec3 hold(0.01, -0.02, kToolRadius - device_penetration);
  const double series =
      kCouplingStiffness * kContactStiffness / (kCouplingStiffness + kContactStiffness);
  const double expected_force = series * device_penetration;  // 6 N
  // Proxy centre where k_T (z_p − z_h) = k_c (r − z_p).
  const double proxy_z = (kContactStiffness * kToolRadius + kCouplingStiffness * hold.z()) /
                         (kCouplingStiffness + kContactStiffness);

  // Explicit Euler is stable here: k Δt = (2000 + 3000)·1e-3 = 5 < b = 5 + 2 N·s/m.
  for (const auto& values : std::vector<std::vector<std::pair<std::string, ParamValue>>>{
           {{"integrator", std::string("implicit_euler")}},
           {{"integrator", std::string("explicit_euler")}},
           {{"proxy", std::string("quasi_static")}}}) {
    auto renderer = create_penalty_analytic(context, make_params(values));
    const TickResult result = run_press(*renderer, start, hold, 2000);
    INFO(std::get<std::string>(values.front().second));
    CHECK(result.display.force.z() == Approx(expected_force).epsilon(1e-3));
    CHECK(std::hypot(result.display.force.x(), result.display.force.y()) < 1e-3 * expected_force);
    CHECK(result.display.torque.norm() < 1e-9);
    CHECK(result.proxy.p.z() == Approx(proxy_z).epsilon(1e-4));
    REQUIRE(result.contacts.size() == 1);
    const Contact& contact = result.contacts[0];
    CHECK((contact.normal - Vec3::UnitZ()).norm() < 1e-9);
    CHECK(contact.depth == Approx(kToolRadius - proxy_z).epsilon(1e-3));
    // The reported point is the sphere's lowest point.
    CHECK((contact.point - (result.proxy.p - kToolRadius * Vec3::UnitZ())).norm() < 1e-9);
    CHECK(result.work.get("tool_points_tested") >= 1);
    CHECK(result.flags == 0);
  }
}

TEST_CASE("box tool pressed flat: four corner springs in series with the coupling",
          "[penalty_analytic]") {
  const double half = 0.01;
  const RenderContext context = press_context(test::box_tool(Vec3(2 * half, 2 * half, 2 * half)));
  const double device_penetration = 0.005;
  const Vec3 start(0, 0, 0.03);
  const Vec3 hold(0, 0, half - device_penetration);
  const double corners = 4 * kContactStiffness;
  const double expected_force =
      kCouplingStiffness * corners / (kCouplingStiffness + corners) * device_penetration;
  for (const char* proxy : {"dynamic", "quasi_static"}) {
    auto renderer = create_penalty_analytic(context, make_params({{"proxy", std::string(proxy)}}));
    const TickResult result = run_press(*renderer, start, hold, 2000);
    INFO(proxy);
    CHECK(result.display.force.z() == Approx(expected_force).epsilon(1e-3));
    CHECK(result.display.torque.norm() < 1e-6);
    CHECK(result.contacts.size() == 4);
    for (const Contact& contact : result.contacts) {
      CHECK(contact.point.z() == Approx(result.proxy.p.z() - half).epsilon(1e-9));
      CHECK(contact.depth == Approx(half - result.proxy.p.z()).epsilon(1e-6));
    }
    CHECK(result.work.get("tool_points_tested") >= 8);
  }
}

TEST_CASE("sphere on a sphere: the force is radial and in series", "[penalty_analytic]") {
  RenderContext context;
  const double obstacle_radius = 0.05;
  context.scene.push_back(test::sphere_object(obstacle_radius, Pose{}));
  context.tool = test::sphere_tool(kToolRadius);
  context.coupling = test::example_gains();
  const Vec3 direction = Vec3(1, 2, 2) / 3;
  const double touching = obstacle_radius + kToolRadius;
  const double device_penetration = 0.004;
  const Vec3 start = (touching + 0.01) * direction;
  const Vec3 hold = (touching - device_penetration) * direction;
  const double expected_force = kCouplingStiffness * kContactStiffness /
                                (kCouplingStiffness + kContactStiffness) * device_penetration;
  for (const char* proxy : {"dynamic", "quasi_static"}) {
    auto renderer = create_penalty_analytic(context, make_params({{"proxy", std::string(proxy)}}));
    const TickResult result = run_press(*renderer, start, hold, 2000);
    INFO(proxy);
    CHECK((result.display.force - expected_force * direction).norm() < 1e-3 * expected_force);
    REQUIRE(result.contacts.size() == 1);
    CHECK((result.contacts[0].normal - direction).norm() < 1e-6);
  }
}

TEST_CASE("slow contact loop: the haptic step sees contacts only once installed",
          "[penalty_analytic]") {
  const RenderContext context = press_context(test::sphere_tool(kToolRadius));
  auto haptic = create_penalty_analytic(context, make_params({}));
  CHECK(haptic->slow_loop() == nullptr);

  auto renderer =
      create_penalty_analytic(context, make_params({{"contact_loop", std::string("slow")}}));
  SlowLoop* slow = renderer->slow_loop();
  REQUIRE(slow != nullptr);
  // Start (and hold the device) with the sphere 3 mm into the box.
  const Pose pressed{Vec3(0, 0, kToolRadius - 0.003), Quat::Identity()};
  renderer->reset(pressed);
  DeviceSample sample;
  sample.pose = pressed;
  TickResult before = renderer->step(sample);
  CHECK(before.contacts.empty());
  CHECK(before.display.force.norm() < 1e-12);
  CHECK((before.flags & kFlagSlowResultInstalled) == 0);

  std::unique_ptr<SlowLoop::Result> update = slow->run_slow_update();
  sample.tick = 1;
  before = renderer->step(sample);  // finished but not installed yet
  CHECK(before.contacts.empty());
  slow->install_slow_result(std::move(update));

  sample.tick = 2;
  const TickResult after = renderer->step(sample);
  CHECK((after.flags & kFlagSlowResultInstalled) != 0);
  REQUIRE(after.contacts.size() == 1);
  CHECK(after.contacts[0].depth > 0);
  CHECK(after.contacts[0].depth <= 0.003);
  CHECK(after.display.force.z() > 0);  // the proxy is pushed out; the device feels it
  // The installed plane keeps acting on later ticks without another update.
  TickResult later = after;
  for (int64_t k = 3; k < 1500; ++k) {
    sample.tick = k;
    later = renderer->step(sample);
  }
  CHECK((later.flags & kFlagSlowResultInstalled) == 0);
  CHECK(later.display.force.z() == Approx(6.0 * 0.003 / 0.005).epsilon(1e-3));

  // reset() forgets installed planes.
  renderer->reset(pressed);
  CHECK(renderer->step(sample).contacts.empty());
}

TEST_CASE("non-finite device input never reaches the display", "[penalty_analytic]") {
  const RenderContext context = press_context(test::sphere_tool(kToolRadius));
  for (const char* proxy : {"dynamic", "quasi_static"}) {
    auto renderer = create_penalty_analytic(context, make_params({{"proxy", std::string(proxy)}}));
    renderer->reset(Pose{Vec3(0, 0, 0.019), Quat::Identity()});
    DeviceSample sample;
    sample.pose.p = Vec3(0, 0, 0.019);
    renderer->step(sample);
    sample.pose.q = Quat(std::numeric_limits<double>::quiet_NaN(), 0, 0, 0);
    const TickResult bad = renderer->step(sample);
    INFO(proxy);
    CHECK(is_finite(bad.display));
    CHECK((bad.flags & kFlagNonFiniteZeroed) != 0);
    CHECK(is_finite(bad.proxy));
  }
}

TEST_CASE("an unstable explicit contact never produces a non-finite display",
          "[penalty_analytic]") {
  RenderContext context = press_context(test::sphere_tool(kToolRadius));
  context.device = DeviceLimits{20, 1};
  // k Δt = 1e6 · 1e-3 ≫ b: explicit Euler explodes on contact.
  auto renderer =
      create_penalty_analytic(context, make_params({{"integrator", std::string("explicit_euler")},
                                                    {"contact_stiffness", 1e6},
                                                    {"contact_damping", 0.0}}));
  uint32_t seen = 0;
  renderer->reset(Pose{Vec3(0, 0, 0.03), Quat::Identity()});
  for (int64_t k = 0; k < 3000; ++k) {
    const TickResult result = renderer->step(press_sample(k, Vec3(0, 0, 0.03), Vec3(0, 0, 0.015)));
    REQUIRE(is_finite(result.display));
    REQUIRE(is_finite(result.proxy));
    REQUIRE(result.display.force.norm() <= 20 * (1 + 1e-12));
    seen |= result.flags;
  }
  CHECK((seen & kFlagForceSaturated) != 0);
}

TEST_CASE("in free space the broad phase skips every tool vertex", "[penalty_analytic]") {
  const RenderContext context = press_context(test::box_tool(Vec3(0.02, 0.02, 0.02)));
  auto renderer = create_penalty_analytic(context, make_params({}));
  const Pose above{Vec3(0, 0, 0.05), Quat::Identity()};
  renderer->reset(above);
  DeviceSample sample;
  sample.pose = above;
  const TickResult result = renderer->step(sample);
  CHECK(result.work.get("obstacle_bound_tests") == 1);
  CHECK(result.work.get("tool_points_tested") == 0);
  CHECK(result.contacts.empty());
  CHECK(result.display.force.norm() < 1e-12);
}

std::string error_of(const RenderContext& context, const ParamSet& params) {
  try {
    create_penalty_analytic(context, params);
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST_CASE("penalty_analytic rejects bad parameters naming the field", "[penalty_analytic]") {
  const RenderContext context = press_context(test::sphere_tool(kToolRadius));
  CHECK_THAT(error_of(context, make_params({{"contact_stiffness", -1.0}})),
             Catch::Contains("/algorithms/0/params/contact_stiffness"));
  CHECK_THAT(error_of(context, make_params({{"contact_damping", -0.5}})),
             Catch::Contains("contact_damping"));
  CHECK_THAT(error_of(context, make_params({{"integrator", std::string("verlet")}})),
             Catch::Contains("integrator"));
  CHECK_THAT(error_of(context, make_params({{"proxy_mass_kg", 0.0}})),
             Catch::Contains("proxy_mass_kg"));
  CHECK_THAT(error_of(context, make_params({{"proxy", std::string("god_object")}})),
             Catch::Contains("proxy"));
  CHECK_THAT(error_of(context, make_params({{"contact_loop", std::string("fast")}})),
             Catch::Contains("contact_loop"));
  CHECK_THAT(error_of(context, make_params({{"proxy", std::string("quasi_static")},
                                            {"contact_stiffness", -3.0}})),
             Catch::Contains("contact_stiffness"));
  // The massless proxy has no integrator: the parameter stays unread and is reported.
  const ParamSet quasi_static = make_params(
      {{"proxy", std::string("quasi_static")}, {"integrator", std::string("implicit_euler")}});
  create_penalty_analytic(context, quasi_static);
  CHECK_THROWS_WITH(quasi_static.reject_unknown(), Catch::Contains("integrator"));
}

TEST_CASE("penalty_analytic names the scene object that is a mesh", "[penalty_analytic]") {
  RenderContext context = press_context(test::sphere_tool(kToolRadius));
  SceneObject mesh_object;
  mesh_object.name = "bunny.off";
  mesh_object.mesh = test::box_tool(Vec3(0.1, 0.1, 0.1)).mesh;
  context.scene.push_back(mesh_object);
  try {
    create_penalty_analytic(context, make_params({}));
    FAIL("expected an InputError");
  } catch (const InputError& error) {
    CHECK(error.location() == "/scene/1");
    CHECK_THAT(std::string(error.what()), Catch::Contains("scene[1] is a mesh"));
  }
}

}  // namespace
}  // namespace hb
