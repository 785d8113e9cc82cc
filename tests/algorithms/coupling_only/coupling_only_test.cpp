#include "algorithms/coupling_only/coupling_only.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>

#include "hapticbench/input_error.h"
#include "tests/support/proxy_fixtures.h"

namespace hb {
namespace {

RenderContext sphere_context() {
  RenderContext context;
  context.tool = test::sphere_tool(0.02);
  context.coupling = test::example_gains();
  return context;
}

ParamSet params_with(const std::string& key, ParamValue value) {
  ParamSet params("/algorithms/0/params");
  params.set(key, std::move(value));
  return params;
}

// Device accelerating from rest along `direction` at `acceleration` m/s².
DeviceSample accelerating(int64_t tick, const Vec3& acceleration) {
  const double t = static_cast<double>(tick) * 1e-3;
  DeviceSample sample;
  sample.tick = tick;
  sample.t_ns = tick * 1'000'000;
  sample.pose.p = 0.5 * acceleration * t * t;
  sample.twist.v = acceleration * t;
  return sample;
}

TEST_CASE("in steady acceleration the display is the proxy's inertia, −m a", "[coupling_only]") {
  const RenderContext context = sphere_context();
  const Vec3 acceleration(0.2, -0.1, 0.05);
  for (const char* integrator : {"explicit_euler", "implicit_euler"}) {
    for (double mass : {0.0, 0.1}) {  // 0: the tool's own mass
      ParamSet params = params_with("integrator", std::string(integrator));
      if (mass > 0) params.set("proxy_mass_kg", mass);
      const double m = mass > 0 ? mass : context.tool.mass.mass_kg;
      auto renderer = create_coupling_only(context, params);
      renderer->reset(Pose{});
      TickResult result;
      for (int64_t k = 0; k <= 1000; ++k) result = renderer->step(accelerating(k, acceleration));
      INFO(integrator << " proxy mass " << m);
      CHECK((result.display.force + m * acceleration).norm() < 0.01 * m * acceleration.norm());
      CHECK(result.contacts.empty());
      CHECK(result.flags == 0);
      // The proxy trails the device by m a / k_T, to within one tick of travel
      // (the reported pose is the one after the step).
      const DeviceSample last = accelerating(1000, acceleration);
      const Vec3 lag = last.pose.p - result.proxy.p;
      CHECK((lag - m * acceleration / 2000).norm() < last.twist.v.norm() * 1e-3 * 1.01);
    }
  }
}

TEST_CASE("pushing a proxy held off its centre of mass needs the lever's torque",
          "[coupling_only]") {
  RenderContext context = sphere_context();
  const Vec3 com(0, 0.01, 0.02);
  context.tool.mass.centre_of_mass = com;
  const double m = context.tool.mass.mass_kg;
  const Vec3 acceleration(0.3, 0, 0);
  auto renderer =
      create_coupling_only(context, params_with("integrator", std::string("implicit_euler")));
  renderer->reset(Pose{});
  TickResult result;
  for (int64_t k = 0; k <= 1500; ++k) result = renderer->step(accelerating(k, acceleration));
  // Steady state: no angular acceleration, so about the COM the couple cancels the
  // force's moment: τ_c = (R c) × F with F = m a; the device shows −τ_c.
  const Vec3 expected_torque = -com.cross(m * acceleration);
  CHECK((result.display.force + m * acceleration).norm() < 0.01 * m * acceleration.norm());
  CHECK((result.display.torque - expected_torque).norm() < 0.02 * expected_torque.norm());
}

TEST_CASE("a NaN device pose never reaches the display or the proxy", "[coupling_only]") {
  const RenderContext context = sphere_context();
  for (const char* integrator : {"explicit_euler", "implicit_euler"}) {
    auto renderer =
        create_coupling_only(context, params_with("integrator", std::string(integrator)));
    renderer->reset(Pose{});
    DeviceSample sample;
    sample.pose.p = Vec3(0.001, 0, 0);
    renderer->step(sample);
    sample.pose.p.y() = std::numeric_limits<double>::quiet_NaN();
    const TickResult bad = renderer->step(sample);
    CHECK(is_finite(bad.display));
    CHECK(bad.display.force == Vec3::Zero());
    CHECK((bad.flags & kFlagNonFiniteZeroed) != 0);
    CHECK(is_finite(bad.proxy));
    sample.pose.p = Vec3(0.001, 0, 0);
    const TickResult good = renderer->step(sample);
    CHECK(is_finite(good.display));
    CHECK(good.flags == 0);
  }
}

TEST_CASE("an exploding explicit proxy never produces a non-finite display", "[coupling_only]") {
  RenderContext context = sphere_context();
  context.coupling = CouplingGains{1e6, 0.1, 5, 0.05};  // k_T Δt = 1000 ≫ b_T: diverges
  context.device = DeviceLimits{20, 1};
  auto renderer =
      create_coupling_only(context, params_with("integrator", std::string("explicit_euler")));
  renderer->reset(Pose{});
  DeviceSample sample;
  sample.pose.p = Vec3(0.001, 0.0, 0.0);
  uint32_t seen = 0;
  for (int64_t k = 0; k < 2000; ++k) {
    sample.tick = k;
    const TickResult result = renderer->step(sample);
    REQUIRE(is_finite(result.display));
    REQUIRE(result.display.force.norm() <= 20 * (1 + 1e-12));
    REQUIRE(result.display.torque.norm() <= 1 * (1 + 1e-12));
    REQUIRE(is_finite(result.proxy));
    seen |= result.flags;
  }
  CHECK((seen & kFlagForceSaturated) != 0);
  CHECK((seen & kFlagProxyReset) != 0);
}

TEST_CASE("coupling_only rejects bad parameters naming the field", "[coupling_only]") {
  const RenderContext context = sphere_context();
  auto message = [&](const ParamSet& params) {
    try {
      create_coupling_only(context, params);
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  CHECK_THAT(message(params_with("integrator", std::string("rk4"))),
             Catch::Contains("/algorithms/0/params/integrator"));
  CHECK_THAT(message(params_with("proxy_mass_kg", 0.0)), Catch::Contains("proxy_mass_kg"));
  CHECK_THAT(message(params_with("proxy_mass_kg", -1.0)), Catch::Contains("proxy_mass_kg"));
  CHECK_THAT(message(params_with("proxy_mass_kg", std::string("heavy"))),
             Catch::Contains("proxy_mass_kg"));
  // Contact parameters mean nothing here: left unread, so the registry reports them.
  ParamSet contact = params_with("contact_stiffness", 3000.0);
  create_coupling_only(context, contact);
  CHECK_THROWS_AS(contact.reject_unknown(), InputError);
}

}  // namespace
}  // namespace hb
