// The mesh force reference against what is known without it: the closed
// forms of the analytic reference on every analytic scenario given as
// meshes (the trust chain), a thin wall it must not pass, a hook turned
// about its tip that must not sink (the Embree oracle at every tick), two
// ridges crossing between their samples, a
// start inside, and the convergence residual it reports.
#include "harness/reference/rigid_proxy_reference.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "hapticbench/closest_points.h"
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
    // With the scene's friction: the closed form's stick and slip.
    const std::optional<AnalyticScene> analytic = make_analytic_scene(scenario.context);
    REQUIRE(analytic);
    FrictionalContactReference closed_form(*analytic);
    const bool sphere = tool.shape->type == ShapeType::kSphere;
    const Tessellation tessellation =
        sphere ? inscribed_error(tool.mesh, tool.shape->radius) : Tessellation{};
    const double tool_radius = tool.mesh.radius_about(Vec3::Zero());
    RigidProxySettings settings;
    RigidProxyReference reference(scenario.context.scene, tool.mesh, scenario.context.coupling,
                                  settings);
    std::vector<IdealRendering> closed_forms, meshes;
    double peak_force = 0, peak_torque = 0, peak_friction = 0;
    int sticking = 0;
    for (int64_t tick = 0; tick < scenario.trajectory.ticks(); tick += 5) {
      const Pose device = scenario.trajectory.at(tick).pose;
      const std::optional<IdealRendering> mesh = reference.update(device);
      REQUIRE(mesh);
      CHECK(reference.last_stats().converged);
      CHECK(reference.last_stats().kkt_residual < 1e-4);
      meshes.push_back(*mesh);
      closed_forms.push_back(closed_form.update(device));
      if (getenv("HB_DEBUG") && scenario.name == getenv("HB_DEBUG") &&
          (tick % 50 == 0 || (tick > 1550 && tick < 1650)))
        printf(
            "it %d conv %d kkt %.2g %ld dev %.4f %.4f | mesh F %.3f %.3f %.3f T %.4f %.4f %.4f "
            "stick %d lim %.3f | cf F %.3f %.3f %.3f T %.4f %.4f %.4f stick %d\n",
            reference.last_stats().iterations, (int)reference.last_stats().converged,
            reference.last_stats().kkt_residual, (long)tick, device.p.x(), device.p.z(),
            mesh->display.force.x(), mesh->display.force.y(), mesh->display.force.z(),
            mesh->display.torque.x(), mesh->display.torque.y(), mesh->display.torque.z(),
            (int)reference.last_stats().sticking, reference.last_stats().friction_limit_n,
            closed_forms.back().display.force.x(), closed_forms.back().display.force.y(),
            closed_forms.back().display.force.z(), closed_forms.back().display.torque.x(),
            closed_forms.back().display.torque.y(), closed_forms.back().display.torque.z(),
            (int)closed_form.sticking());
      sticking += closed_form.sticking();
      const Vec3 force = closed_forms.back().display.force;
      peak_friction = std::max(peak_friction, (force - force.z() * Vec3::UnitZ()).norm());
      peak_force = std::max(peak_force, force.norm());
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
    if (analytic->friction > 0) {
      // Both phases are there to compare: sticking, and sliding with the
      // full μ F_n along the face.
      CHECK(sticking > 0);
      CHECK(peak_friction > 0.5 * analytic->friction * peak_force);
    }
    CHECK(worst_force <= force_tolerance);
    CHECK(worst_torque <= torque_tolerance);
    ++scenarios;
  }
  CHECK(scenarios >= 7);
}

// A sphere pressed into a right-angled V groove along x and dragged along
// it: sliding, each face pushes with λ = F/√2 for a vertical push F, so the
// friction is μ Σλ = √2 μ F, more than on one face (the wedge). Sticking,
// the sphere rolls about the line through its two contacts, r/√2 below its
// centre: the rotational coupling in series with the translational one.
// (How a sticking sphere's load splits between normal and friction forces
// on the two faces is statically indeterminate, so the limit is checked
// sliding only.)
TEST_CASE("the mesh reference holds a sphere in a groove with the wedge's friction") {
  const double mu = 0.3, r = 0.01;
  std::vector<SceneObject> scene;
  for (double side : {-1.0, 1.0}) {
    // A slab whose top face passes through the groove's axis (the x axis)
    // at 45° to the vertical.
    const Quat tilt(Eigen::AngleAxisd(side * M_PI / 4, Vec3::UnitX()));
    scene.push_back(
        test::box_object(Vec3(0.2, 0.1, 0.02), Pose{tilt * Vec3(0, side * 0.05, -0.01), tilt}));
    scene.back().mesh = shape_mesh(*scene.back().shape);
    scene.back().friction = mu;
  }
  Tool tool = test::sphere_tool(r);
  tool.shape->subdivisions = 5;
  const CouplingGains gains = test::example_gains();
  RigidProxyReference reference(scene, shape_mesh(*tool.shape), gains);
  const double rest_z = r * std::sqrt(2.0);  // the sphere touching both faces
  const double press = 0.003;                // m, below the rest height
  // Clear above, then down, then along x by 1 mm (within the friction's
  // reach: F = k_t press, holds to √2 μ F / k_t = 1.27 mm), then 2 cm.
  std::vector<Pose> path;
  for (int k = 0; k <= 20; ++k)
    path.push_back({Vec3(0, 0, rest_z + 0.005 - 0.0004 * k), Quat::Identity()});
  const double reach = std::sqrt(2.0) * mu * press;
  for (int k = 1; k <= 10; ++k)
    path.push_back({Vec3(0.0001 * k, 0, rest_z - press), Quat::Identity()});
  std::optional<IdealRendering> held;
  for (const Pose& device : path) {
    held = reference.update(device);
    REQUIRE(held);
  }
  INFO("held: force " << held->display.force.transpose() << ", limit "
                      << reference.last_stats().friction_limit_n);
  CHECK(reference.last_stats().sticking);
  const double lever = r / std::sqrt(2.0);
  const double k_stick = 1 / (1 / gains.k_t + lever * lever / gains.k_r);
  CHECK(held->display.force.x() == Approx(-k_stick * 0.001).epsilon(0.01));
  const double push = held->display.force.z();
  CHECK(push == Approx(gains.k_t * press).epsilon(0.02));
  std::optional<IdealRendering> sliding;
  for (int k = 1; k <= 40; ++k) {
    sliding = reference.update(Pose{Vec3(0.001 + 0.0005 * k, 0, rest_z - press), Quat::Identity()});
    REQUIRE(sliding);
  }
  CHECK_FALSE(reference.last_stats().sticking);
  CHECK(-sliding->display.force.x() ==
        Approx(std::sqrt(2.0) * mu * sliding->display.force.z()).epsilon(0.02));
  CHECK(reference.last_stats().friction_limit_n ==
        Approx(std::sqrt(2.0) * mu * sliding->display.force.z()).epsilon(0.02));
  CHECK(-sliding->display.force.x() > gains.k_t * reach * 0.95);
  CHECK(std::abs(sliding->display.force.y()) < 0.01 * push);
}

// A slab whose top face passes through the origin with outward normal
// rotation * ẑ, of friction μ (meshed).
std::vector<SceneObject> tilted_slab(const Quat& rotation, double mu) {
  std::vector<SceneObject> scene = {
      test::box_object(Vec3(0.3, 0.3, 0.02), Pose{rotation * Vec3(0, 0, -0.01), rotation})};
  scene[0].mesh = shape_mesh(*scene[0].shape);
  scene[0].friction = mu;
  return scene;
}

TEST_CASE("the mesh reference's box dragged on a slab: k_t x while sticking, mu F_n sliding") {
  // A 4 cm cube pressed 3 mm (F_n = 6 N) at μ = 0.5: sticks for 1.5 mm
  // (no rolling: a face cannot), then slides with F_t = μ F_n = 3 N. The
  // friction's tipping moment F_t h moves the load within the face (1 cm
  // of its 2 cm half-width), so the proxy does not turn: no torque.
  const double mu = 0.5;
  RigidProxySettings settings;
  RigidProxyReference reference(tilted_slab(Quat::Identity(), mu),
                                test::meshed_box_tool(Vec3::Constant(0.04)).mesh,
                                test::example_gains(), settings);
  const double k_t = test::example_gains().k_t, z = 0.02 - 0.003;
  for (int k = 0; k <= 10; ++k)
    REQUIRE(reference.update({Vec3(0, 0, 0.025 - 0.0008 * k), Quat::Identity()}));
  const auto at = [&](double x) {
    const std::optional<IdealRendering> ideal = reference.update({Vec3(x, 0, z), Quat::Identity()});
    REQUIRE(ideal);
    CHECK(reference.last_stats().converged);
    CHECK(ideal->display.force.z() == Approx(k_t * 0.003).epsilon(0.01));
    CHECK(ideal->display.torque.norm() < 1e-5);  // of the 0.06 N·m tipping moment
    return ideal->display.force.x();
  };
  for (int k = 1; k <= 10; ++k) at(0.0001 * k);
  CHECK(at(0.001) == Approx(-k_t * 0.001).epsilon(0.01));
  CHECK(reference.last_stats().sticking);
  for (int k = 1; k <= 20; ++k) at(0.001 + 0.0005 * k);
  CHECK(at(0.0115) == Approx(-mu * k_t * 0.003).epsilon(0.01));
  CHECK_FALSE(reference.last_stats().sticking);
  CHECK(reference.last_stats().friction_limit_n == Approx(mu * k_t * 0.003).epsilon(0.01));
}

TEST_CASE("the mesh reference's box on a slope sticks below tan(theta) = mu and slides above") {
  // A 4 cm cube lying flat on a slope of angle θ, pressed 3 mm straight
  // down: the push has F_t / F_n = tan θ. At μ = 0.5 it holds on 20°
  // (tan θ = 0.36: the proxy stays where it touched) and slides on 35°
  // (0.70: down the slope, until F_t = μ F_n).
  const double mu = 0.5;
  for (const double degrees : {20.0, 35.0}) {
    const double theta = degrees * M_PI / 180;
    const Quat slope(Eigen::AngleAxisd(theta, Vec3::UnitY()));
    const Vec3 normal = slope * Vec3::UnitZ();
    TriangleMesh tool = test::meshed_box_tool(Vec3::Constant(0.04)).mesh;
    for (Vec3& v : tool.vertices) v = slope * v;  // its bottom face along the slope
    RigidProxyReference reference(tilted_slab(slope, mu), tool, test::example_gains());
    const Vec3 touch = 0.02 * normal;
    for (int k = 0; k <= 10; ++k)
      REQUIRE(reference.update({touch + 0.0005 * (10 - k) * normal, Quat::Identity()}));
    std::optional<IdealRendering> ideal;
    for (int k = 1; k <= 30; ++k) {
      ideal = reference.update({touch - 0.0001 * k * Vec3::UnitZ(), Quat::Identity()});
      REQUIRE(ideal);
    }
    const Vec3 force = ideal->display.force;
    const double normal_force = force.dot(normal);
    const double tangential = (force - normal_force * normal).norm();
    const double moved = (ideal->proxy.p - touch).norm();
    INFO(degrees << " degrees: F_t / F_n " << tangential / normal_force << ", proxy moved " << moved
                 << " m");
    CHECK(normal_force > 3.0);
    if (std::tan(theta) < mu) {
      CHECK(reference.last_stats().sticking);
      CHECK(tangential / normal_force == Approx(std::tan(theta)).epsilon(0.01));
      CHECK(moved < 2e-6);  // the clearance, not a slide
    } else {
      CHECK_FALSE(reference.last_stats().sticking);
      CHECK(tangential / normal_force == Approx(mu).epsilon(0.01));
      CHECK((ideal->proxy.p - touch).dot(slope * Vec3::UnitX()) > 2e-4);  // down the slope
    }
  }
}

TEST_CASE("the mesh reference's tripod twisted on a slab resists with the pivot torque") {
  // Three 3 mm spherical feet 2 cm from the tool's axis, pressed with
  // F_n = 6 N (each foot F_n / 3: three points carry a centred load in one
  // way only) and twisted about the axis at μ = 0.5: the friction holds
  // until k_r ψ = μ F_n ρ = 0.06 N·m (ψ = 12 mrad), then the feet slide
  // and the torque stays there.
  const double mu = 0.5, rho = 0.02, foot = 0.003;
  Shape sphere;
  sphere.type = ShapeType::kSphere;
  sphere.radius = foot;
  const TriangleMesh ball = shape_mesh(sphere);
  TriangleMesh tripod;
  for (int leg = 0; leg < 3; ++leg) {
    const double angle = 2 * M_PI * leg / 3;
    const Vec3 centre(rho * std::cos(angle), rho * std::sin(angle), -0.01);
    const int base = static_cast<int>(tripod.vertices.size());
    for (const Vec3& v : ball.vertices) tripod.vertices.push_back(v + centre);
    for (const auto& [a, b, c] : ball.triangles)
      tripod.triangles.push_back({a + base, b + base, c + base});
  }
  const CouplingGains gains = test::example_gains();
  RigidProxyReference reference(tilted_slab(Quat::Identity(), mu), tripod, gains);
  const double rest = 0.01 + foot, z = rest - 0.003;
  for (int k = 0; k <= 10; ++k)
    REQUIRE(reference.update({Vec3(0, 0, rest + 0.0005 * (10 - k)), Quat::Identity()}));
  const auto twisted = [&](double psi) {
    const std::optional<IdealRendering> ideal =
        reference.update({Vec3(0, 0, z), Quat(Eigen::AngleAxisd(psi, Vec3::UnitZ()))});
    REQUIRE(ideal);
    CHECK(ideal->display.force.z() == Approx(gains.k_t * 0.003).epsilon(0.02));
    return ideal->display.torque.z();
  };
  for (int k = 1; k <= 6; ++k) twisted(0.001 * k);
  CHECK(twisted(0.006) == Approx(-gains.k_r * 0.006).epsilon(0.01));
  CHECK(reference.last_stats().sticking);
  for (int k = 1; k <= 40; ++k) twisted(0.006 + 0.001 * k);
  const double pivot = mu * gains.k_t * 0.003 * rho;  // 0.06 N·m
  CHECK(twisted(0.047) == Approx(-pivot).epsilon(0.02));
  CHECK_FALSE(reference.last_stats().sticking);
}

TEST_CASE("the mesh reference's friction can be left out") {
  std::vector<SceneObject> scene = {
      test::box_object(Vec3(0.2, 0.2, 0.02), Pose{Vec3(0, 0, -0.01), Quat::Identity()})};
  scene[0].mesh = shape_mesh(*scene[0].shape);
  scene[0].friction = 0.5;
  const Tool tool = test::sphere_tool(0.01);
  RigidProxySettings frictionless;
  frictionless.friction = false;
  RigidProxyReference with(scene, shape_mesh(*tool.shape), test::example_gains());
  RigidProxyReference without(scene, shape_mesh(*tool.shape), test::example_gains(), frictionless);
  const std::vector<Pose> path = {{Vec3(0, 0, 0.02), Quat::Identity()},
                                  {Vec3(0, 0, 0.008), Quat::Identity()},
                                  {Vec3(0.002, 0, 0.008), Quat::Identity()}};
  IdealRendering a, b;
  for (const Pose& device : path) {
    a = *with.update(device);
    b = *without.update(device);
  }
  // Pressed 2 mm (F_n = 4 N) and moved 2 mm along the face: the frictional
  // proxy slides 1 mm behind the device (μ F_n = 2 N), the frictionless one
  // follows it.
  CHECK(-a.display.force.x() == Approx(0.5 * a.display.force.z()).epsilon(0.02));
  CHECK(std::abs(b.display.force.x()) < 1e-6);
  CHECK(without.last_stats().friction_limit_n == 0.0);
}

TEST_CASE("the mesh reference keeps a hook turned about its tip out of the slab") {
  for (const char* name : {"hook_turn_2rads", "hook_turn_8rads"}) {
    const Scenario scenario = load_scenario((std::filesystem::path(HAPTICBENCH_SOURCE_DIR) /
                                             "scenarios/stress" / (std::string(name) + ".json"))
                                                .string());
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

TEST_CASE("the mesh reference keeps two 90-degree wedges crossing at right angles apart") {
  // A 10 cm cube turned 45 degrees about x (its top ridge along x) and a
  // 4 cm cube tool turned 45 degrees about y in the tool frame (its lowest
  // ridge along y). Pressed 2 mm past contact and slid diagonally, the
  // ridges cross at a point that runs along both, mostly between the
  // samples of either (spacing ~1.7 mm: up to ~0.9 mm hidden between them).
  const double root_half = std::sqrt(0.5);
  const Quat about_x(Eigen::AngleAxisd(M_PI / 4, Vec3::UnitX()));
  std::vector<SceneObject> scene = {
      test::box_object(Vec3::Constant(0.1), Pose{Vec3::Zero(), about_x})};
  scene[0].mesh = shape_mesh(*scene[0].shape);
  TriangleMesh tool_mesh = test::meshed_box_tool(Vec3::Constant(0.04)).mesh;
  const Quat about_y(Eigen::AngleAxisd(M_PI / 4, Vec3::UnitY()));
  for (Vec3& v : tool_mesh.vertices) v = about_y * v;
  const double scene_ridge_z = 0.05 / root_half, tool_ridge_z = -0.02 / root_half;
  RigidProxySettings settings;
  settings.friction = false;
  RigidProxyReference reference(scene, tool_mesh, test::example_gains(), settings);
  REQUIRE(reference.sample_spacing_m() > 1e-3);

  const Vec3 scene_ridge[2] = {Vec3(-0.05, 0, scene_ridge_z), Vec3(0.05, 0, scene_ridge_z)};
  const Vec3 tool_ridge[2] = {Vec3(0, -0.02, tool_ridge_z), Vec3(0, 0.02, tool_ridge_z)};
  double closest = 1, least_force = 1e9;
  for (int tick = -50; tick <= 400; ++tick) {
    // From 5 mm above down to 2 mm past contact, then both ridges' crossing
    // point moves 3 cm.
    const double s = -0.015 + 0.03 * std::max(tick, 0) / 400.0;
    const double depth = tick < 0 ? -0.005 + 0.007 * (tick + 50) / 50.0 : 0.002;
    const Pose device{Vec3(s, -0.7 * s, scene_ridge_z - tool_ridge_z - depth), Quat::Identity()};
    const std::optional<IdealRendering> ideal = reference.update(device);
    REQUIRE(ideal);
    if (tick < 0) continue;
    const SegmentClosestPoints ridges = closest_points_of_segments(
        ideal->proxy.transform_point(tool_ridge[0]), ideal->proxy.transform_point(tool_ridge[1]),
        scene_ridge[0], scene_ridge[1]);
    // Signed: the tool's ridge above the scene's.
    closest = std::min(closest, (ridges.on_p - ridges.on_q).z());
    least_force = std::min(least_force, ideal->display.force.z());
  }
  INFO("closest ridge approach " << closest << " m, least upward force " << least_force << " N");
  CHECK(least_force > 3.0);  // pressed all the way
  CHECK(closest >= reference.clearance_m() - 1e-9);
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
