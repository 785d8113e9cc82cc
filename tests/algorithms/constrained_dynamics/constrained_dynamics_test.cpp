// constrained_dynamics: in free space it is the implicit dynamic proxy; a
// cube pressed into a face rests at the standoff with the coupling's force;
// random device motions never carry a vertex below the face; a cube on a
// slope holds when μ exceeds tan(angle) and slides at g (sin − μ cos) below;
// a press-and-drag sticks below μ F_n and slides at μ F_n; runs repeat bit
// for bit; bad parameters are named.
#include "algorithms/constrained_dynamics/constrained_dynamics.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "hapticbench/input_error.h"
#include "hapticbench/mass_properties.h"
#include "hapticbench/proxy/dynamic_proxy.h"
#include "hapticbench/proxy/proxy_settings.h"
#include "hapticbench/shapes.h"
#include "tests/support/proxy_fixtures.h"
#include "tests/support/render_fixtures.h"

namespace hb {
namespace {

constexpr double kCube = 0.04;  // cube tool edge (m)

// A 4 cm cube tool over a 0.4 × 0.4 × 0.02 m slab whose top face is the
// plane through the origin with normal R·z (R = the slab's rotation).
RenderContext cube_over_slab(double friction, const Quat& slab_rotation = Quat::Identity()) {
  RenderContext context;
  SceneObject slab = test::box_object(Vec3(0.4, 0.4, 0.02),
                                      Pose{slab_rotation * Vec3(0, 0, -0.01), slab_rotation});
  slab.mesh = shape_mesh(*slab.shape);
  slab.friction = friction;
  slab.content_hash = "slab";
  context.scene.push_back(slab);
  context.tool = test::box_tool(Vec3::Constant(kCube));
  context.tool.mesh = shape_mesh(*context.tool.shape);
  context.tool.content_hash = "cube";
  context.coupling = test::example_gains();
  return context;
}

DeviceSample sample_at(int64_t tick, const Pose& pose, const Twist& twist = {}) {
  DeviceSample sample;
  sample.tick = tick;
  sample.t_ns = tick * 1'000'000;
  sample.pose = pose;
  sample.twist = twist;
  return sample;
}

Pose at(const Vec3& p, const Quat& q = Quat::Identity()) { return Pose{p, q}; }

// Runs the renderer with its slow loop every `period` ticks (installed at once).
class Rig {
 public:
  Rig(const RenderContext& context, const ParamSet& params = test::params_of({}))
      : context_(context), renderer_(create_constrained_dynamics(context, params)) {}
  void reset(const Pose& start) {
    renderer_->reset(start);
    tick_ = 0;
  }
  TickResult step(const Pose& device, const Twist& twist = {}, int period = 10) {
    if (tick_ % period == 0) {
      SlowLoop* slow = renderer_->slow_loop();
      slow->install_slow_result(slow->run_slow_update());
    }
    return renderer_->step(sample_at(tick_++, device, twist));
  }
  // Signed height of the tool's lowest vertex above the slab's top face (m).
  double lowest_vertex_height(const Pose& proxy) const {
    const Vec3 up = context_.scene[0].pose.q * Vec3::UnitZ();
    double lowest = 1e300;
    for (const Vec3& vertex : context_.tool.mesh.vertices)
      lowest = std::min(lowest, up.dot(proxy.transform_point(vertex)));
    return lowest;
  }

 private:
  RenderContext context_;
  std::unique_ptr<Renderer> renderer_;
  int64_t tick_ = 0;
};

TEST_CASE("in free space constrained dynamics is the implicit dynamic proxy, which is the device",
          "[constrained_dynamics]") {
  // The device starts at 0.15 m/s beside a proxy at rest: both integrate
  // until the proxy has caught up (the pull a jump would take away is no
  // more than one tick of the device's motion puts on the spring), then
  // jump to the device and display nothing from then on.
  const RenderContext context = cube_over_slab(0.5);
  Rig rig(context);
  DynamicProxy reference(proxy_body(context.tool, context.tool.mass.mass_kg, Vec3::Zero()),
                         context.coupling, IntegratorKind::kImplicitEuler, 1e-3);
  reference.follow_device_in_free_space(
      {.tool_radius_m = context.tool.mesh.radius_about(context.tool.mass.centre_of_mass)});
  const Pose start = at(Vec3(0, 0, 0.2));
  rig.reset(start);
  reference.reset(start);
  bool following = false;
  int ticks_at_device = 0;
  for (int tick = 0; tick < 300; ++tick) {
    const double s = 1e-3 * tick;
    const Pose device = at(Vec3(0.05 * std::sin(3 * s), 0.02 * s, 0.2),
                           quat_from_rotation_vector(Vec3(0, 0.3 * s, 0.1 * s)));
    const Twist twist{Vec3(0.15 * std::cos(3 * s), 0.02, 0), Vec3(0, 0.3, 0.1)};
    const TickResult result = rig.step(device, twist);
    uint32_t flags = 0;
    const Wrench expected = reference.advance(sample_at(tick, device, twist), nullptr, flags);
    INFO("tick " << tick);
    CHECK((result.proxy.p - reference.tool_pose().p).norm() < 1e-12);
    CHECK((result.display.force - expected.force).norm() < 1e-9);
    CHECK((result.display.torque - expected.torque).norm() < 1e-9);
    CHECK(result.contacts.empty());
    const bool at_device =
        (result.proxy.p - device.p).norm() < 1e-12 && result.display.force.norm() < 1e-9;
    if (following) CHECK(at_device);
    following = following || at_device;
    if (at_device) ++ticks_at_device;
  }
  CHECK(ticks_at_device > 250);
}

TEST_CASE("a cube pressed into the face rests on it with the coupling's force",
          "[constrained_dynamics]") {
  Rig rig(cube_over_slab(0));
  rig.reset(at(Vec3(0, 0, 0.021)));           // 1 mm above the face
  const Pose device = at(Vec3(0, 0, 0.017));  // 3 mm deep
  TickResult result;
  for (int tick = 0; tick < 1000; ++tick) result = rig.step(device);
  const double height = rig.lowest_vertex_height(result.proxy);
  CHECK(height >= 0);
  CHECK(height <= 2e-5);  // at the 10 µm standoff
  // The device is 3 mm (plus the standoff's gap) below the resting proxy.
  CHECK(result.display.force.z() == Approx(2000 * (0.003 + height)).epsilon(1e-6));
  CHECK(result.display.force.head<2>().norm() < 1e-6);
  CHECK(result.contacts.size() >= 4);
}

TEST_CASE("random device motions never carry a cube vertex below the face",
          "[constrained_dynamics]") {
  Rig rig(cube_over_slab(0.3));
  rig.reset(at(Vec3(0, 0, 0.05)));
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> offset(-0.001, 0.001);
  std::uniform_real_distribution<double> angle(-0.02, 0.02);
  Pose device = at(Vec3(0, 0, 0.05));
  int contact_ticks = 0;
  double lowest = 1e300;
  for (int tick = 0; tick < 3000; ++tick) {
    device.p += Vec3(offset(rng), offset(rng), offset(rng) - 0.0004);
    device.p.z() = std::clamp(device.p.z(), 0.0, 0.06);
    device.p.x() = std::clamp(device.p.x(), -0.1, 0.1);
    device.p.y() = std::clamp(device.p.y(), -0.1, 0.1);
    device.q = (quat_from_rotation_vector(Vec3(angle(rng), angle(rng), angle(rng))) * device.q)
                   .normalized();
    const TickResult result = rig.step(device);
    lowest = std::min(lowest, rig.lowest_vertex_height(result.proxy));
    if (!result.contacts.empty()) ++contact_ticks;
  }
  CHECK(lowest >= -1e-6);  // the goal is 50 µm; the proxy keeps above the face
  CHECK(contact_ticks > 500);
}

// A cube released on a slab tilted by `angle` about y under gravity, the
// coupling switched off: how far its centre moved downhill in `seconds`.
double slide_down_slope(double angle, double friction, double seconds) {
  const Quat tilt = quat_from_rotation_vector(Vec3(0, angle, 0));
  RenderContext context = cube_over_slab(friction, tilt);
  context.coupling = CouplingGains{0, 0, 0, 0};
  context.gravity = Vec3(0, 0, -9.81);
  // The sliding acceleration near the cone's edge is a small difference:
  // solve to 1e-9 m/s (the default 1e-6 m/s leaves it within 3 %).
  Rig rig(context, test::params_of({{"solver_tolerance", 1e-9}}));
  const Pose start = at(tilt * Vec3(0, 0, kCube / 2 + 1e-5), tilt);
  rig.reset(start);
  TickResult result;
  for (int tick = 0; tick < static_cast<int>(seconds / 1e-3); ++tick) result = rig.step(start);
  const Vec3 downhill = tilt * Vec3::UnitX();  // turned about y, +x dips
  return downhill.dot(result.proxy.p - start.p);
}

TEST_CASE("a cube on a slope holds when mu exceeds tan(angle) and slides below",
          "[constrained_dynamics]") {
  const double angle = 20 * std::numbers::pi / 180, g = 9.81, seconds = 0.15;
  CHECK(std::abs(slide_down_slope(angle, 1.05 * std::tan(angle), seconds)) < 1e-6);
  for (double mu : {0.1, 0.95 * std::tan(angle)}) {
    const double expected = 0.5 * g * (std::sin(angle) - mu * std::cos(angle)) * seconds * seconds;
    INFO("mu " << mu);
    CHECK(slide_down_slope(angle, mu, seconds) == Approx(expected).epsilon(0.02));
  }
}

TEST_CASE("a press and drag sticks below mu F_n and slides at mu F_n", "[constrained_dynamics]") {
  const double mu = 0.4;
  Rig rig(cube_over_slab(mu));
  rig.reset(at(Vec3(0, 0, 0.021)));
  // Press 3 mm (F_n ≈ 6 N), then drag the device along x at 2 cm/s.
  TickResult result;
  for (int tick = 0; tick < 500; ++tick) result = rig.step(at(Vec3(0, 0, 0.017)));
  const double normal = result.display.force.z();
  REQUIRE(normal == Approx(6).epsilon(0.01));
  int sticking = 0, sliding = 0;
  for (int tick = 1; tick <= 1500; ++tick) {
    const double x = 2e-5 * tick;
    result = rig.step(at(Vec3(x, 0, 0.017)), Twist{Vec3(0.02, 0, 0), Vec3::Zero()});
    const double tangential = std::abs(result.display.force.x());
    if (2000 * x < 0.9 * mu * normal) {  // the coupling's pull is below the cone: stuck
      ++sticking;
      CHECK(result.proxy.p.x() == Approx(0).margin(1e-7));
    } else if (tick > 1000) {  // well into steady sliding
      ++sliding;
      CHECK(tangential / result.display.force.z() == Approx(mu).epsilon(0.02));
    }
  }
  CHECK(sticking > 50);
  CHECK(sliding > 100);
}

TEST_CASE("a hook turned about its tip and a ridge swept parallel over an edge stay out",
          "[constrained_dynamics]") {
  // Where the linearised constraints are weakest: the hook's tip pivoting
  // on the slab's top face beyond the centre of mass along the normal (a
  // rotation's second-order motion carries it in), and a cube's ridge
  // yawed across the slab's edge until the two lie parallel (an edge pair's
  // closest points slide along the edges). Every point of every tool edge
  // stays outside the slab at every tick: the ridge by the standoff less
  // 1 µm; the hook's tip dips below the standoff by a rotation's curvature
  // before the stabilisation recovers it (a fifth of the gap per tick), to
  // 8.0 µm of the 10 µm at 8 rad/s, and is held to half the standoff.
  const Vec3 slab_centre(0, 0, -0.02), slab_half(0.2, 0.2, 0.02);
  RenderContext hook_context;
  SceneObject slab = test::box_object(2 * slab_half, Pose{slab_centre, Quat::Identity()});
  slab.mesh = shape_mesh(*slab.shape);
  slab.content_hash = "slab_4cm";
  hook_context.scene.push_back(slab);
  hook_context.tool.mesh = test::hook_mesh();
  hook_context.tool.mass = mass_properties_from_density(hook_context.tool.mesh, 1000);
  hook_context.tool.content_hash = "hook";
  hook_context.coupling = test::example_gains();
  const double standoff = 1e-5;
  // Rates about the y axis, and 6 rad/s about skewed axes, none of the
  // hook's principal ones (the linear rows alone let it sink millimetres).
  const Vec3 skewed = Vec3(1, 1, 1).normalized(), tilted = Vec3(0.3, 1, 0.5).normalized();
  for (const Vec3& turn :
       {Vec3(0, 2, 0), Vec3(0, 4, 0), Vec3(0, 8, 0), Vec3(6 * skewed), Vec3(6 * tilted)}) {
    const double rate = turn.norm();
    Rig rig(hook_context);
    const Vec3 tip(-0.15, 0, 0);
    rig.reset(at(tip + Vec3(0, 0, 0.005)));
    double least = 1e300;
    int turning_contact_ticks = 0;
    for (int tick = 0; tick < 1500; ++tick) {
      // Down to 2 mm past the face in 0.2 s, then turning for 1.3 s.
      const double t = 1e-3 * tick;
      Pose target = at(tip + Vec3(0, 0, std::max(-0.002, 0.005 - 0.035 * t)));
      if (t > 0.2) target.q = quat_from_rotation_vector(turn * (t - 0.2));
      const TickResult result = rig.step(target);
      least = std::min(least, test::least_edge_distance_to_box(hook_context.tool.mesh, result.proxy,
                                                               slab_centre, slab_half, 5e-4));
      if (t > 0.2 && !result.contacts.empty()) ++turning_contact_ticks;
    }
    INFO("hook at " << rate << " rad/s about " << turn.transpose() / rate
                    << ": least distance of an edge to the slab " << least << " m");
    CHECK(turning_contact_ticks > 200);  // it did pivot on the face
    CHECK(least >= 0.5 * standoff);
  }

  const Vec3 thin_centre(0, 0, -0.01), thin_half(0.2, 0.2, 0.01);
  const RenderContext cube_context = cube_over_slab(0);
  const Quat roll = quat_from_rotation_vector(Vec3(0, std::numbers::pi / 4, 0));
  const Vec3 centre(0.2, 0, kCube / std::sqrt(2.0));  // the ridge on the slab's edge
  for (double rate : {0.5, 2.0}) {
    Rig rig(cube_context);
    auto pose_at = [&](double yaw, double depth) {
      return at(centre - Vec3(0, 0, depth), quat_from_rotation_vector(Vec3(0, 0, yaw)) * roll);
    };
    rig.reset(pose_at(0.3, -0.003));
    double least = 1e300;
    for (int tick = 0; tick < 1200; ++tick) {
      const double t = 1e-3 * tick;
      const double depth = std::min(0.001, -0.003 + 0.04 * t);
      const double yaw = t < 0.2 ? 0.3 : 0.3 - rate * (t - 0.2);
      const TickResult result = rig.step(pose_at(yaw, depth));
      least = std::min(least, test::least_edge_distance_to_box(cube_context.tool.mesh, result.proxy,
                                                               thin_centre, thin_half));
    }
    INFO("ridge yawed at " << rate << " rad/s: least distance of a cube edge " << least << " m");
    CHECK(least >= standoff - 1e-6);
    CHECK(least < 1e-4);  // it did press on the slab
  }
}

TEST_CASE("constrained dynamics runs repeat bit for bit", "[constrained_dynamics]") {
  auto run = [] {
    Rig rig(cube_over_slab(0.3));
    rig.reset(at(Vec3(0, 0, 0.03)));
    std::vector<double> trace;
    for (int tick = 0; tick < 800; ++tick) {
      const double s = 1e-3 * tick;
      const TickResult r = rig.step(at(Vec3(0.03 * std::sin(4 * s), 0.01 * s, 0.02 - 0.01 * s),
                                       quat_from_rotation_vector(Vec3(0.2 * s, 0, 0.4 * s))));
      trace.insert(trace.end(), {r.display.force.x(), r.display.force.y(), r.display.force.z(),
                                 r.display.torque.x(), r.proxy.p.x(), r.proxy.q.w()});
    }
    return trace;
  };
  CHECK(run() == run());
}

TEST_CASE("constrained dynamics names bad parameters", "[constrained_dynamics]") {
  const RenderContext context = cube_over_slab(0);
  auto fails_at = [&](const char* key, ParamValue value, const char* field) {
    try {
      create_constrained_dynamics(context, test::params_of({{key, value}}));
    } catch (const InputError& error) {
      CHECK(error.location() == field);
      return;
    }
    FAIL("no error for " << key);
  };
  fails_at("stabilisation", 0.0, "/algorithms/0/params/stabilisation");
  fails_at("solver_sweeps", 0.0, "/algorithms/0/params/solver_sweeps");
  fails_at("max_iterations", 3.0, "/algorithms/0/params/max_iterations");
  fails_at("proxy_mass_kg", -1.0, "/algorithms/0/params/proxy_mass_kg");
  fails_at("standoff", 0.0, "/algorithms/0/params/standoff");
}

}  // namespace
}  // namespace hb
