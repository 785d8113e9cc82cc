// The mesh force reference against what is known without it: the closed
// forms of the analytic reference on every analytic scenario given as
// meshes (the trust chain), a thin wall it must not pass, a hook turned
// about its tip that must not sink (the Embree oracle at every tick), a
// start inside, and the convergence residual it reports.
#include "harness/reference/rigid_proxy_reference.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "harness/reference/surface_samples.h"
#include "harness/scenario/scenario.h"
#include "tests/support/proxy_fixtures.h"

namespace hb {
namespace {

const std::string kAnalyticDir = std::string(HAPTICBENCH_SOURCE_DIR) + "/scenarios/analytic";

// The known error of an inscribed tessellation of a sphere: how far inside
// the sphere its flattest face lies (m; the depth by which it can rest lower
// on a plane) and the largest angle between a face's normal and the sphere's
// normal at its corners (rad; how far the force's direction can turn on an
// edge, and the lever its contact point can gain).
struct Tessellation {
  double depth_m = 0;
  double angle_rad = 0;
};

Tessellation inscribed_error(const TriangleMesh& mesh, double radius) {
  Tessellation error;
  for (const auto& [a, b, c] : mesh.triangles) {
    const Vec3& p = mesh.vertices[a];
    const Vec3 n = (mesh.vertices[b] - p).cross(mesh.vertices[c] - p).normalized();
    error.depth_m = std::max(error.depth_m, radius - std::abs(n.dot(p)));
    for (int corner : {a, b, c})
      error.angle_rad = std::max(error.angle_rad,
                                 std::acos(std::min(1.0, n.dot(mesh.vertices[corner]) / radius)));
  }
  return error;
}

TEST_CASE("the mesh reference agrees with the closed forms on every analytic scenario") {
  int scenarios = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kAnalyticDir)) {
    if (entry.path().extension() != ".json") continue;
    Scenario scenario = load_scenario(entry.path().string());
    // A finer sphere than the scenarios draw, so that the tessellation's
    // error stays well under the 1 % tolerance; the box is exact as a mesh.
    Tool& tool = scenario.context.tool;
    if (tool.shape && tool.shape->type == ShapeType::kSphere) {
      tool.shape->subdivisions = 5;
      tool.mesh = shape_mesh(*tool.shape);
    }
    RenderContext analytic_context = scenario.context;
    for (SceneObject& object : analytic_context.scene) object.friction = 0;
    const std::optional<AnalyticScene> analytic = make_analytic_scene(analytic_context);
    REQUIRE(analytic);
    const bool sphere = tool.shape->type == ShapeType::kSphere;
    const Tessellation tessellation =
        sphere ? inscribed_error(tool.mesh, tool.shape->radius) : Tessellation{};
    const double tool_radius = tool.mesh.radius_about(Vec3::Zero());
    RigidProxySettings settings;
    RigidProxyReference reference(scenario.context.scene, tool.mesh, scenario.context.coupling,
                                  settings);
    std::vector<IdealRendering> closed_forms, meshes;
    double peak_force = 0, peak_torque = 0;
    for (int64_t tick = 0; tick < scenario.trajectory.ticks(); tick += 5) {
      const Pose device = scenario.trajectory.at(tick).pose;
      const std::optional<IdealRendering> mesh = reference.update(device);
      REQUIRE(mesh);
      CHECK(reference.last_stats().converged);
      CHECK(reference.last_stats().kkt_residual < 1e-4);
      meshes.push_back(*mesh);
      closed_forms.push_back(ideal_rigid_contact(*analytic, device));
      peak_force = std::max(peak_force, closed_forms.back().display.force.norm());
      peak_torque = std::max(peak_torque, closed_forms.back().display.torque.norm());
    }
    const double k_t = scenario.context.coupling.k_t;
    // 1 % of the peak, the tessellation's depth and direction errors, and
    // twice the clearance the reference keeps (its force shifts by k_t ε;
    // a contact ε off the face can lean on a neighbouring triangle's edge).
    const double clearance = 2 * settings.clearance_m;
    const double force_tolerance = 0.01 * peak_force + k_t * (tessellation.depth_m + clearance) +
                                   peak_force * std::sin(tessellation.angle_rad);
    const double torque_tolerance =
        0.01 * peak_torque +
        (peak_force * std::sin(tessellation.angle_rad) + k_t * clearance) * tool_radius;
    double worst_force = 0, worst_torque = 0;
    for (std::size_t k = 0; k < meshes.size(); ++k) {
      worst_force =
          std::max(worst_force, (meshes[k].display.force - closed_forms[k].display.force).norm());
      worst_torque = std::max(worst_torque,
                              (meshes[k].display.torque - closed_forms[k].display.torque).norm());
    }
    INFO(scenario.name << ": peak force " << peak_force << " N, worst force error " << worst_force
                       << " N (tolerance " << force_tolerance << "), peak torque " << peak_torque
                       << " N·m, worst torque error " << worst_torque << " (tolerance "
                       << torque_tolerance << ")");
    CHECK(peak_force > 1.0);
    CHECK(worst_force <= force_tolerance);
    CHECK(worst_torque <= torque_tolerance);
    ++scenarios;
  }
  CHECK(scenarios >= 7);
}

TEST_CASE("the mesh reference keeps a hook turned about its tip out of the slab") {
  for (const char* name : {"hook_turn_2rads", "hook_turn_8rads"}) {
    const Scenario scenario =
        load_scenario(std::string(HAPTICBENCH_SOURCE_DIR) + "/scenarios/stress/" + name + ".json");
    RigidProxyReference reference(scenario.context.scene, scenario.context.tool.mesh,
                                  scenario.context.coupling);
    const std::unique_ptr<Oracle> oracle = make_embree_oracle(scenario.context.scene);
    const std::vector<Vec3> samples = sample_surface(scenario.context.tool.mesh, 5e-4);
    double deepest = 0, peak_force = 0;
    for (int64_t tick = 0; tick < scenario.trajectory.ticks(); tick += 2) {
      const std::optional<IdealRendering> ideal =
          reference.update(scenario.trajectory.at(tick).pose);
      REQUIRE(ideal);
      CHECK(reference.last_stats().converged);
      // The oracle's own, finer samples: no more than the clearance can
      // hide between the reference's points.
      std::vector<Vec3> points = samples;
      for (Vec3& p : points) p = ideal->proxy.transform_point(p);
      deepest = std::max(deepest, oracle->penetration(points).max_depth_m);
      peak_force = std::max(peak_force, ideal->display.force.norm());
    }
    INFO(name << ": deepest fine sample " << deepest << " m, peak force " << peak_force << " N");
    CHECK(deepest == 0.0);
    CHECK(peak_force > 3.0);  // the tip was held 2 mm above where the device took it
  }
}

TEST_CASE("the mesh reference does not pass a 2 mm wall at 4 m/s") {
  std::vector<SceneObject> scene = {
      test::box_object(Vec3(0.2, 0.2, 0.002), Pose{Vec3(0, 0, -0.001), Quat::Identity()})};
  scene[0].mesh = shape_mesh(*scene[0].shape);
  const Tool tool = test::sphere_tool(0.01);
  const TriangleMesh tool_mesh = shape_mesh(*tool.shape);
  const CouplingGains gains = test::example_gains();
  RigidProxyReference reference(scene, tool_mesh, gains);
  double lowest = 1;
  IdealRendering last;
  for (int tick = 0; tick < 40; ++tick) {
    const double z = std::max(0.03 - 0.004 * tick, -0.05);  // 4 mm a tick, then held below
    const std::optional<IdealRendering> ideal =
        reference.update(Pose{Vec3(0, 0, z), Quat::Identity()});
    REQUIRE(ideal);
    lowest = std::min(lowest, ideal->proxy.p.z());
    last = *ideal;
  }
  const double r = tool.shape->radius;
  CHECK(lowest >= r * 0.99);  // on top of the plate, never under it
  CHECK(last.display.force.z() == Approx(gains.k_t * (last.proxy.p.z() + 0.05)));
  CHECK(last.display.force.z() > gains.k_t * 0.059);
}

TEST_CASE("the mesh reference starts at the first device pose outside the scene") {
  std::vector<SceneObject> scene = {
      test::box_object(Vec3(0.2, 0.2, 0.02), Pose{Vec3(0, 0, -0.01), Quat::Identity()})};
  scene[0].mesh = shape_mesh(*scene[0].shape);
  const Tool tool = test::sphere_tool(0.01);
  RigidProxyReference reference(scene, shape_mesh(*tool.shape), test::example_gains());
  CHECK_FALSE(reference.update(Pose{Vec3(0, 0, 0.005), Quat::Identity()}));  // 5 mm in
  const std::optional<IdealRendering> out =
      reference.update(Pose{Vec3(0, 0, 0.02), Quat::Identity()});
  REQUIRE(out);
  CHECK(out->display.force.norm() == 0.0);
  // From there the device goes 3 mm deep: the proxy rests on the face.
  const std::optional<IdealRendering> pressed =
      reference.update(Pose{Vec3(0, 0, 0.007), Quat::Identity()});
  REQUIRE(pressed);
  CHECK(pressed->in_contact);
  CHECK(pressed->proxy.p.z() >= 0.0099);
  CHECK(pressed->display.force.z() == Approx(test::example_gains().k_t * 0.003).epsilon(0.02));
}

}  // namespace
}  // namespace hb
