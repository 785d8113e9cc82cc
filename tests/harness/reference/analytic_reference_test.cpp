// Checks of the analytic ground truth against closed forms and against
// independent computations: coupling energies evaluated here, force and
// torque balance (KKT) solved here, and a brute-force hull of the boxes'
// Minkowski difference. Quaternions (qw,qx,qy,qz); units m, N, N·m, rad, J.
#include "harness/reference/analytic_reference.h"

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "tests/support/shape_fixtures.h"
#include "tests/support/tunnelling_paths.h"

namespace hb {
namespace {

using test::box_shape;

constexpr double kStiffness = 2000;     // k_T, N/m
constexpr double kRotStiffness = 5;     // k_R, N·m/rad
constexpr double kPlateTop = 0.0;       // z of the plate's top face, m
const Vec3 kPlateSize(0.4, 0.4, 0.02);  // full extents, m
const Vec3 kPlateCentre(0, 0, -0.01);   // m

Shape sphere_shape(double radius) {
  Shape shape;
  shape.type = ShapeType::kSphere;
  shape.radius = radius;
  return shape;
}

Shape capsule_shape() {
  Shape shape;
  shape.type = ShapeType::kCapsule;
  shape.radius = 0.01;
  shape.length = 0.05;
  return shape;
}

SceneObject box_object(const Vec3& size, const Pose& pose) {
  SceneObject object;
  object.name = "scene[0]";
  object.pose = pose;
  object.shape = box_shape(size);
  return object;
}

RenderContext context_with(const Shape& tool_shape, const Vec3& box_size = kPlateSize,
                           const Pose& box_pose = Pose{kPlateCentre, Quat::Identity()}) {
  RenderContext context;
  context.scene.push_back(box_object(box_size, box_pose));
  context.tool.shape = tool_shape;
  context.tool.mass.centre_of_mass = Vec3(0.001, -0.002, 0.003);
  context.coupling.k_t = kStiffness;
  context.coupling.k_r = kRotStiffness;
  return context;
}

AnalyticScene scene_for(const RenderContext& context) {
  std::string reason;
  const std::optional<AnalyticScene> scene = make_analytic_scene(context, &reason);
  INFO(reason);
  REQUIRE(scene.has_value());
  return *scene;
}

Quat rotation(const Vec3& axis, double angle) {
  return Quat(Eigen::AngleAxisd(angle, axis.normalized()));
}

Quat random_rotation(std::mt19937& random) {
  std::normal_distribution<double> normal;
  Quat q(normal(random), normal(random), normal(random), normal(random));
  return q.normalized();
}

// Coupling spring energy ½ k_T |x_h − x_p|² + ½ k_R |θ(q_h q_p⁻¹)|², J.
double coupling_energy(const Pose& device, const Pose& proxy) {
  const Vec3 theta = rotation_vector(device.q * proxy.q.conjugate());
  return 0.5 * kStiffness * (device.p - proxy.p).squaredNorm() +
         0.5 * kRotStiffness * theta.squaredNorm();
}

std::array<Vec3, 8> box_vertices(const Vec3& half, const Pose& pose) {
  std::array<Vec3, 8> vertices;
  for (int k = 0; k < 8; ++k) {
    const Vec3 corner((k & 1) ? half.x() : -half.x(), (k & 2) ? half.y() : -half.y(),
                      (k & 4) ? half.z() : -half.z());
    vertices[k] = pose.transform_point(corner);
  }
  return vertices;
}

// Height (m) of the lowest tool vertex above the plane n·x = offset.
double lowest_vertex_height(const Vec3& tool_half, const Pose& pose, const Vec3& normal,
                            double offset) {
  double lowest = 1e300;
  for (const Vec3& v : box_vertices(tool_half, pose))
    lowest = std::min(lowest, normal.dot(v) - offset);
  return lowest;
}

// Tool box pose with the given orientation whose lowest vertex is `depth`
// below the plate's top face, its origin above (x, y).
Pose pressed_box_pose(const Vec3& tool_half, const Quat& q, double x, double y, double depth) {
  Pose pose{Vec3(x, y, 0), q};
  const double lowest = lowest_vertex_height(tool_half, pose, Vec3::UnitZ(), kPlateTop);
  pose.p.z() += -lowest - depth;
  return pose;
}

// KKT of the frictionless half-space problem at the returned proxy: no vertex
// below the plane, the display wrench is −(coupling spring), and it is
// balanced by non-negative normal forces at the touching vertices (torques
// about the tool origin); no feasible pose nearby, nor any lifted random
// orientation, has a lower coupling energy.
void require_kkt_on_plane(const AnalyticScene& scene, const Pose& device,
                          const IdealRendering& rendering, const Vec3& normal, double offset,
                          unsigned seed) {
  const Vec3 tool_half = 0.5 * scene.tool_shape.size;
  const Pose& proxy = rendering.proxy;
  REQUIRE(rendering.in_contact);
  REQUIRE((rendering.contact_normal - normal).norm() < 1e-12);
  REQUIRE(std::abs(proxy.q.norm() - 1) < 1e-12);

  // Display = −(spring part of the coupling) at the proxy.
  const Vec3 theta = rotation_vector(device.q * proxy.q.conjugate());
  CHECK((rendering.display.force - kStiffness * (proxy.p - device.p)).norm() < 1e-12);
  CHECK((rendering.display.torque + kRotStiffness * theta).norm() < 1e-12);

  // Feasible: no vertex below the plane beyond 1e-9 m; at least one touches.
  const std::array<Vec3, 8> vertices = box_vertices(tool_half, proxy);
  std::vector<int> active;
  double lowest = 1e300;
  for (int k = 0; k < 8; ++k) {
    const double height = normal.dot(vertices[k]) - offset;
    lowest = std::min(lowest, height);
    if (height <= 1e-9) active.push_back(k);
  }
  CHECK(lowest >= -1e-9);
  REQUIRE(!active.empty());

  // Frictionless: the displayed force is along the normal, pushing out.
  const Vec3 force = rendering.display.force;
  CHECK((force - force.dot(normal) * normal).norm() < 1e-9);
  CHECK(force.dot(normal) > 0);

  // Balance: display wrench = Σ λ_k (n, r_k × n), λ_k ≥ 0, over some subset
  // of the touching vertices (the touching set may be degenerate, e.g. a face).
  Vec6 wrench;
  wrench << rendering.display.force, rendering.display.torque;
  bool balanced = false;
  const int count = static_cast<int>(active.size());
  for (int subset = 1; subset < (1 << count) && !balanced; ++subset) {
    std::vector<int> members;
    for (int m = 0; m < count; ++m) {
      if (subset & (1 << m)) members.push_back(active[m]);
    }
    Eigen::MatrixXd columns(6, members.size());
    for (std::size_t m = 0; m < members.size(); ++m) {
      const Vec3 lever = vertices[members[m]] - proxy.p;
      columns.col(m) << normal, lever.cross(normal);
    }
    const Eigen::VectorXd lambda = columns.colPivHouseholderQr().solve(wrench);
    const double residual = (columns * lambda - wrench).norm();
    if (lambda.minCoeff() >= -1e-9 && residual <= 1e-9) balanced = true;
  }
  CHECK(balanced);

  // Local optimality: small random perturbations, lifted back to feasibility.
  const double optimum = coupling_energy(device, proxy);
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> shift(-1e-4, 1e-4);
  std::uniform_real_distribution<double> turn(-1e-3, 1e-3);
  double lowest_nearby = 1e300;
  for (int trial = 0; trial < 2000; ++trial) {
    Pose nearby = proxy;
    nearby.p += Vec3(shift(random), shift(random), shift(random));
    nearby.q = (quat_from_rotation_vector(Vec3(turn(random), turn(random), turn(random))) * proxy.q)
                   .normalized();
    const double height = lowest_vertex_height(tool_half, nearby, normal, offset);
    if (height < 0) nearby.p -= height * normal;
    lowest_nearby = std::min(lowest_nearby, coupling_energy(device, nearby));
  }
  CHECK(lowest_nearby >= optimum - 1e-12);

  // Global optimality over the half-space problem: any orientation, with the
  // translation nearest the device that keeps it above the plane.
  double lowest_anywhere = 1e300;
  for (int trial = 0; trial < 20000; ++trial) {
    Pose candidate{device.p, trial % 2 == 0
                                 ? random_rotation(random)
                                 : (quat_from_rotation_vector(Vec3(
                                        10 * turn(random), 10 * turn(random), 10 * turn(random))) *
                                    device.q)
                                       .normalized()};
    const double height = lowest_vertex_height(tool_half, candidate, normal, offset);
    if (height < 0) candidate.p -= height * normal;
    lowest_anywhere = std::min(lowest_anywhere, coupling_energy(device, candidate));
  }
  CHECK(lowest_anywhere >= optimum - 1e-12);
}

// Brute-force penetration depth of two boxes: the distance from the origin to
// the boundary of the Minkowski difference, whose facet planes are found as
// the planes through three of the 64 vertex differences with all others on
// one side.
double brute_force_box_depth(const Vec3& a_half, const Pose& a_pose, const Vec3& b_half,
                             const Pose& b_pose) {
  std::vector<Vec3> points;
  for (const Vec3& a : box_vertices(a_half, a_pose)) {
    for (const Vec3& b : box_vertices(b_half, b_pose)) points.push_back(b - a);
  }
  const int count = static_cast<int>(points.size());
  double depth = 1e300;
  for (int i = 0; i < count; ++i) {
    for (int j = i + 1; j < count; ++j) {
      for (int k = j + 1; k < count; ++k) {
        Vec3 normal = (points[j] - points[i]).cross(points[k] - points[i]);
        if (normal.norm() < 1e-10) continue;
        normal.normalize();
        double above = -1e300;
        double below = 1e300;
        for (const Vec3& p : points) {
          const double h = normal.dot(p - points[i]);
          above = std::max(above, h);
          below = std::min(below, h);
        }
        if (above <= 1e-12) {
          depth = std::min(depth, normal.dot(points[i]));
        } else if (below >= -1e-12) {
          depth = std::min(depth, -normal.dot(points[i]));
        }
      }
    }
  }
  return std::max(depth, 0.0);
}

// ---------------------------------------------------------------------------

TEST_CASE("make_analytic_scene accepts one box with a sphere or box tool", "[analytic]") {
  const AnalyticScene scene = scene_for(context_with(sphere_shape(0.02)));
  CHECK(scene.box_half_extents.isApprox(Vec3(0.2, 0.2, 0.01)));
  CHECK(scene.box_pose.p.isApprox(kPlateCentre));
  CHECK(scene.tool_shape.type == ShapeType::kSphere);
  CHECK(scene.tool_centre_of_mass.isApprox(Vec3(0.001, -0.002, 0.003)));
  CHECK(scene.coupling.k_t == kStiffness);
  CHECK(scene.coupling.k_r == kRotStiffness);
  CHECK(make_analytic_scene(context_with(box_shape(Vec3(0.04, 0.06, 0.02)))).has_value());
}

TEST_CASE("make_analytic_scene says why a scene is not covered", "[analytic]") {
  std::string reason;

  RenderContext two_objects = context_with(sphere_shape(0.02));
  two_objects.scene.push_back(box_object(Vec3(0.1, 0.1, 0.1), Pose{}));
  CHECK_FALSE(make_analytic_scene(two_objects, &reason).has_value());
  CHECK_THAT(reason, Catch::Contains("2 objects"));

  RenderContext mesh_tool = context_with(sphere_shape(0.02));
  mesh_tool.tool.shape.reset();
  CHECK_FALSE(make_analytic_scene(mesh_tool, &reason).has_value());
  CHECK_THAT(reason, Catch::Contains("tool is a mesh"));

  CHECK_FALSE(make_analytic_scene(context_with(capsule_shape()), &reason).has_value());
  CHECK_THAT(reason, Catch::Contains("capsule"));

  RenderContext mesh_scene = context_with(sphere_shape(0.02));
  mesh_scene.scene.front().shape.reset();
  CHECK_FALSE(make_analytic_scene(mesh_scene, &reason).has_value());
  CHECK_THAT(reason, Catch::Contains("mesh"));

  RenderContext sphere_scene = context_with(sphere_shape(0.02));
  sphere_scene.scene.front().shape = sphere_shape(0.1);
  CHECK_FALSE(make_analytic_scene(sphere_scene, &reason).has_value());
  CHECK_THAT(reason, Catch::Contains("sphere"));

  RenderContext with_gravity = context_with(sphere_shape(0.02));
  with_gravity.gravity = Vec3(0, 0, -9.81);
  CHECK_FALSE(make_analytic_scene(with_gravity, &reason).has_value());
  CHECK_THAT(reason, Catch::Contains("gravity"));

  CHECK_FALSE(make_analytic_scene(RenderContext{}).has_value());  // no reason asked for
}

TEST_CASE("sphere above the box: proxy = device, no force", "[analytic][sphere]") {
  const AnalyticScene scene = scene_for(context_with(sphere_shape(0.02)));
  const Pose device{Vec3(0.01, -0.02, 0.05), rotation(Vec3(1, 2, 3), 0.7)};
  const IdealRendering rendering = ideal_rigid_contact(scene, device);
  CHECK_FALSE(rendering.in_contact);
  CHECK(rendering.proxy.p == device.p);
  CHECK(rendering.proxy.q.coeffs() == device.q.coeffs());
  CHECK(rendering.display.force == Vec3::Zero());
  CHECK(rendering.display.torque == Vec3::Zero());
  CHECK(rendering.contact_normal == Vec3::Zero());
  CHECK(rendering.device_penetration_m == 0);

  // Just clear of the surface is not contact either.
  const Pose touching{Vec3(0.01, -0.02, kPlateTop + 0.02 + 1e-12), Quat::Identity()};
  CHECK_FALSE(ideal_rigid_contact(scene, touching).in_contact);
}

TEST_CASE("sphere pressed straight down: proxy on the surface, force k_T D up",
          "[analytic][sphere]") {
  const double radius = 0.02;
  const AnalyticScene scene = scene_for(context_with(sphere_shape(radius)));
  for (const double depth : {1e-4, 0.004, 0.015}) {
    const Pose device{Vec3(0.05, 0.03, kPlateTop + radius - depth), rotation(Vec3(0, 1, 1), 0.4)};
    const IdealRendering rendering = ideal_rigid_contact(scene, device);
    REQUIRE(rendering.in_contact);
    CHECK(rendering.proxy.p.isApprox(Vec3(0.05, 0.03, kPlateTop + radius), 1e-14));
    CHECK(rendering.proxy.q.coeffs() == device.q.coeffs());
    CHECK((rendering.display.force - Vec3(0, 0, kStiffness * depth)).norm() < 1e-10);
    CHECK(rendering.display.torque == Vec3::Zero());
    CHECK((rendering.contact_normal - Vec3::UnitZ()).norm() < 1e-15);
    CHECK(rendering.device_penetration_m == Approx(depth).margin(1e-15));
  }
}

TEST_CASE("sphere centre inside the box leaves through the nearest face", "[analytic][sphere]") {
  const double radius = 0.02;
  const AnalyticScene scene = scene_for(context_with(sphere_shape(radius)));

  // 8 mm under the top face, 12 mm above the bottom one: out through the top.
  const Pose deep{Vec3(0.1, 0.1, -0.008), Quat::Identity()};
  const IdealRendering up = ideal_rigid_contact(scene, deep);
  CHECK(up.proxy.p.isApprox(Vec3(0.1, 0.1, radius), 1e-14));
  CHECK((up.display.force - Vec3(0, 0, kStiffness * 0.028)).norm() < 1e-10);
  CHECK(up.device_penetration_m == Approx(0.028).margin(1e-15));

  // 1 mm inside the +x side face, 5 mm from top and bottom: out through +x.
  const Pose side{Vec3(0.199, 0.0, -0.005), Quat::Identity()};
  const IdealRendering out = ideal_rigid_contact(scene, side);
  CHECK(out.proxy.p.isApprox(Vec3(0.2 + radius, 0.0, -0.005), 1e-14));
  CHECK((out.display.force - Vec3(kStiffness * 0.021, 0, 0)).norm() < 1e-10);
  CHECK((out.contact_normal - Vec3::UnitX()).norm() < 1e-15);
}

TEST_CASE("sphere pushed into an edge or corner rests on the rounded box", "[analytic][sphere]") {
  const double radius = 0.02;
  const AnalyticScene scene = scene_for(context_with(sphere_shape(radius)));

  // The plate's top edge along y at x = 0.2, z = 0; centre 12 mm from it.
  const Vec3 edge_point(0.2, 0.1, kPlateTop);
  for (const double angle : {0.2, 0.6, 1.3}) {
    const Vec3 direction(std::cos(angle), 0, std::sin(angle));  // edge normal in the xz plane
    const double distance = 0.012;
    const Pose device{edge_point + distance * direction, Quat::Identity()};
    const IdealRendering rendering = ideal_rigid_contact(scene, device);
    REQUIRE(rendering.in_contact);
    CHECK((rendering.proxy.p - (edge_point + radius * direction)).norm() < 1e-15);
    CHECK((rendering.display.force - kStiffness * (radius - distance) * direction).norm() < 1e-10);
    CHECK((rendering.contact_normal - direction).norm() < 1e-12);
    CHECK(rendering.device_penetration_m == Approx(radius - distance).margin(1e-15));
  }

  // Corner (0.2, 0.2, 0): the proxy is at distance r from it along the same ray.
  const Vec3 corner(0.2, 0.2, kPlateTop);
  const Vec3 direction = Vec3(1, 2, 2).normalized();
  const Pose device{corner + 0.005 * direction, Quat::Identity()};
  const IdealRendering rendering = ideal_rigid_contact(scene, device);
  CHECK((rendering.proxy.p - (corner + radius * direction)).norm() < 1e-15);
  CHECK((rendering.display.force - kStiffness * (radius - 0.005) * direction).norm() < 1e-10);
}

TEST_CASE("sphere against a rotated, displaced box", "[analytic][sphere]") {
  const double radius = 0.015;
  const Vec3 size(0.1, 0.08, 0.06);
  const Pose box_pose{Vec3(0.3, -0.2, 0.1), rotation(Vec3(1, -2, 0.5), 0.9)};
  const AnalyticScene scene = scene_for(context_with(sphere_shape(radius), size, box_pose));
  const double depth = 0.006;
  const Pose device{box_pose.transform_point(Vec3(0.01, 0.04 + radius - depth, 0.002)),
                    Quat::Identity()};
  const IdealRendering rendering = ideal_rigid_contact(scene, device);
  const Vec3 face_normal = box_pose.q * Vec3::UnitY();
  CHECK((rendering.proxy.p - box_pose.transform_point(Vec3(0.01, 0.04 + radius, 0.002))).norm() <
        1e-15);
  CHECK((rendering.display.force - kStiffness * depth * face_normal).norm() < 1e-10);
  CHECK((rendering.contact_normal - face_normal).norm() < 1e-12);
}

TEST_CASE("exact_penetration_depth of a sphere at known depths", "[analytic][sphere]") {
  const double radius = 0.02;
  const AnalyticScene scene = scene_for(context_with(sphere_shape(radius)));
  auto depth_at = [&](const Vec3& centre) {
    return exact_penetration_depth(scene, Pose{centre, rotation(Vec3(3, 1, 0), 1.1)});
  };
  CHECK(depth_at(Vec3(0, 0, 0.03)) == 0);                          // 10 mm clear
  CHECK(depth_at(Vec3(0, 0, radius)) == Approx(0).margin(1e-15));  // touching
  CHECK(depth_at(Vec3(0.1, -0.1, 0.019)) == Approx(0.001).margin(1e-15));
  CHECK(depth_at(Vec3(0.1, -0.1, 0.005)) == Approx(0.015).margin(1e-15));
  CHECK(depth_at(Vec3(0.1, -0.1, -0.004)) == Approx(0.024).margin(1e-15));       // centre inside
  CHECK(depth_at(Vec3(0.2 + 0.006, 0.0, 0.008)) == Approx(0.01).margin(1e-15));  // edge, 10 mm
  CHECK(depth_at(Vec3(0.2 + 0.03, 0.0, -0.005)) == 0);  // beside the side face
}

TEST_CASE("box tool face-down pressed D: force k_T D, no torque", "[analytic][box]") {
  const Vec3 size(0.04, 0.06, 0.02);
  const AnalyticScene scene = scene_for(context_with(box_shape(size)));
  for (const double yaw : {0.0, 0.7}) {
    for (const double depth : {2e-4, 0.005}) {
      const Pose device{Vec3(0.03, -0.02, kPlateTop + 0.01 - depth), rotation(Vec3::UnitZ(), yaw)};
      const IdealRendering rendering = ideal_rigid_contact(scene, device);
      REQUIRE(rendering.in_contact);
      CHECK((rendering.proxy.p - Vec3(0.03, -0.02, kPlateTop + 0.01)).norm() < 1e-15);
      CHECK(rendering.proxy.q.angularDistance(device.q) < 1e-15);
      CHECK((rendering.display.force - Vec3(0, 0, kStiffness * depth)).norm() < 1e-10);
      CHECK(rendering.display.torque.norm() < 1e-14);
      CHECK((rendering.contact_normal - Vec3::UnitZ()).norm() < 1e-15);
      CHECK(rendering.device_penetration_m == Approx(depth).margin(1e-15));
    }
  }
}

TEST_CASE("box tool above the plate is free", "[analytic][box]") {
  const AnalyticScene scene = scene_for(context_with(box_shape(Vec3(0.04, 0.06, 0.02))));
  const Pose device{Vec3(0.0, 0.0, 0.05), rotation(Vec3(1, 1, 0), 0.5)};
  const IdealRendering rendering = ideal_rigid_contact(scene, device);
  CHECK_FALSE(rendering.in_contact);
  CHECK(rendering.proxy.p == device.p);
  CHECK(rendering.display.force == Vec3::Zero());
  CHECK(rendering.display.torque == Vec3::Zero());
}

TEST_CASE("tilted box tool pressed into the face satisfies KKT", "[analytic][box]") {
  const Vec3 size(0.04, 0.06, 0.02);
  const Vec3 half = 0.5 * size;
  const AnalyticScene scene = scene_for(context_with(box_shape(size)));

  SECTION("corner down") {
    const Pose device = pressed_box_pose(half, rotation(Vec3(1, 0.4, 0), 0.35), 0.02, 0.01, 0.004);
    const IdealRendering rendering = ideal_rigid_contact(scene, device);
    require_kkt_on_plane(scene, device, rendering, Vec3::UnitZ(), kPlateTop, 1);
    // The tilt is partly undone, so a restoring torque is displayed.
    CHECK(rendering.display.torque.norm() > 1e-4);
    CHECK(rendering.device_penetration_m == Approx(0.004).margin(1e-12));
  }
  SECTION("edge down") {
    const Pose device = pressed_box_pose(half, rotation(Vec3::UnitX(), 0.3), 0.0, 0.0, 0.003);
    require_kkt_on_plane(scene, device, ideal_rigid_contact(scene, device), Vec3::UnitZ(),
                         kPlateTop, 2);
  }
  SECTION("slightly tilted, settles face-down") {
    const Pose device = pressed_box_pose(half, rotation(Vec3(1, -1, 0), 0.01), 0.0, 0.0, 0.006);
    const IdealRendering rendering = ideal_rigid_contact(scene, device);
    require_kkt_on_plane(scene, device, rendering, Vec3::UnitZ(), kPlateTop, 3);
  }
  SECTION("random tilts and depths") {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(-1, 1);
    std::uniform_real_distribution<double> angle(0.0, 0.7);
    std::uniform_real_distribution<double> depth(5e-4, 0.008);
    for (int trial = 0; trial < 12; ++trial) {
      const Quat q = rotation(Vec3::UnitZ(), 3 * unit(random)) *
                     rotation(Vec3(unit(random), unit(random), 0.1 * unit(random)), angle(random));
      const Pose device =
          pressed_box_pose(half, q, 0.1 * unit(random), 0.1 * unit(random), depth(random));
      INFO("trial " << trial);
      require_kkt_on_plane(scene, device, ideal_rigid_contact(scene, device), Vec3::UnitZ(),
                           kPlateTop, 100 + trial);
    }
  }
}

TEST_CASE("box tool against a rotated, displaced scene box satisfies KKT", "[analytic][box]") {
  const Vec3 tool_size(0.03, 0.02, 0.05);
  const Vec3 box_size(0.3, 0.25, 0.2);
  const Pose box_pose{Vec3(0.1, 0.2, -0.1), rotation(Vec3(0.3, 1, -0.2), 0.8)};
  const AnalyticScene scene = scene_for(context_with(box_shape(tool_size), box_size, box_pose));
  // Press into the box's −x face.
  const Vec3 normal = box_pose.q * -Vec3::UnitX();
  const double offset = normal.dot(box_pose.p) + 0.15;
  const Quat q = rotation(Vec3(1, 2, 3), 0.5) * box_pose.q;
  Pose device{box_pose.transform_point(Vec3(-0.15, 0.02, -0.03)), q};
  device.p -= (lowest_vertex_height(0.5 * tool_size, device, normal, offset) + 0.005) * normal;
  const IdealRendering rendering = ideal_rigid_contact(scene, device);
  require_kkt_on_plane(scene, device, rendering, normal, offset, 4);
}

TEST_CASE("exact_penetration_depth of a box tool", "[analytic][box]") {
  const Vec3 size(0.04, 0.06, 0.02);
  const Vec3 half = 0.5 * size;
  const AnalyticScene scene = scene_for(context_with(box_shape(size)));

  CHECK(exact_penetration_depth(scene, Pose{Vec3(0, 0, 0.01 - 0.003), Quat::Identity()}) ==
        Approx(0.003).margin(1e-15));
  CHECK(exact_penetration_depth(scene, Pose{Vec3(0, 0, 0.011), Quat::Identity()}) == 0);
  CHECK(exact_penetration_depth(scene, Pose{Vec3(0.3, 0, -0.01), Quat::Identity()}) == 0);

  // Tilted, entering through the top face near its middle: the deepest vertex's depth.
  const Pose tilted = pressed_box_pose(half, rotation(Vec3(2, 1, 0.3), 0.5), 0.05, -0.04, 0.0035);
  CHECK(exact_penetration_depth(scene, tilted) == Approx(0.0035).margin(1e-14));
}

TEST_CASE("box-box penetration depth matches the brute-force Minkowski hull", "[analytic][box]") {
  const Vec3 tool_size(0.04, 0.06, 0.02);
  const Vec3 box_size(0.1, 0.08, 0.06);
  const Pose box_pose{Vec3(0.01, 0.02, -0.03), rotation(Vec3(1, 1, 1), 0.3)};
  const AnalyticScene scene = scene_for(context_with(box_shape(tool_size), box_size, box_pose));
  std::mt19937 random(11);
  std::uniform_real_distribution<double> offset(-0.08, 0.08);
  int overlapping = 0;
  for (int trial = 0; trial < 24; ++trial) {
    const Pose tool{box_pose.p + Vec3(offset(random), offset(random), offset(random)),
                    random_rotation(random)};
    const double expected = brute_force_box_depth(0.5 * box_size, box_pose, 0.5 * tool_size, tool);
    INFO("trial " << trial);
    CHECK(exact_penetration_depth(scene, tool) == Approx(expected).margin(1e-12));
    if (expected > 0) ++overlapping;
  }
  CHECK(overlapping >= 6);  // the sample exercises real overlaps, not only separations
}

TEST_CASE("friction: the ideal proxy sticks until the tangential force reaches mu F_n, then slides",
          "[analytic]") {
  // A press of `depth` gives F_n = k_T depth (4 N); μ = 0.5 lets the proxy
  // stick while the device moves up to μ depth = 1 mm along the face.
  const double depth = 0.002, mu = 0.5;
  for (const Shape& tool : {sphere_shape(0.01), box_shape(Vec3(0.02, 0.02, 0.02))}) {
    INFO(shape_type_name(tool.type));
    RenderContext context = context_with(tool);
    context.scene.front().friction = mu;
    const AnalyticScene scene = scene_for(context);
    CHECK(scene.friction == mu);
    FrictionalContactReference reference(scene);
    const double z = kPlateTop + 0.01 - depth;  // both tools reach 1 cm below their origin
    // A sticking sphere rolls about its contact point, its rotational
    // coupling in series with the translational one (lever r); a box on
    // its face cannot.
    const double r = tool.type == ShapeType::kSphere ? tool.radius : 0.0;
    const double k_stick = 1 / (1 / kStiffness + r * r / kRotStiffness);  // N/m
    const auto at = [&](double x) {
      const IdealRendering ideal = reference.update(Pose{Vec3(x, 0, z), Quat::Identity()});
      const IdealRendering frictionless =
          ideal_rigid_contact(scene, Pose{Vec3(x, 0, z), Quat::Identity()});
      CHECK(ideal.display.force.z() == Approx(frictionless.display.force.z()));
      CHECK(ideal.display.force.z() == Approx(kStiffness * depth));
      if (tool.type == ShapeType::kSphere) {
        // The friction's moment about the centre, at the contact point r
        // below it: (−r ẑ) × (F_x x̂) = −r F_x ŷ.
        const Vec3 moment(0, -tool.radius * ideal.display.force.x(), 0);
        CHECK((ideal.display.torque - moment).norm() < 1e-9);
      } else {
        CHECK(ideal.display.torque.isApprox(frictionless.display.torque));
      }
      return std::pair(ideal.display.force.x(), reference.sticking());
    };
    const double limit = mu * kStiffness * depth;  // 2 N
    CHECK(at(0.0) == std::pair(0.0, true));        // touching down: no tangential force
    // Dragged 0.5 mm: sticks, the spring pulls back by k_stick × 0.5 mm
    // (1 N for the box, 0.96 N for the sphere).
    auto [f, stuck] = at(0.0005);
    CHECK(f == Approx(-k_stick * 0.0005).epsilon(1e-6));
    CHECK(stuck);
    // Dragged further: slides, the force stays at μ F_n.
    std::tie(f, stuck) = at(0.0015);
    CHECK(f == Approx(-limit));
    CHECK_FALSE(stuck);
    std::tie(f, stuck) = at(0.003);
    CHECK(f == Approx(-limit));
    CHECK_FALSE(stuck);
    // Stopped and moved back 0.5 mm: sticks again, the force relaxes.
    std::tie(f, stuck) = at(0.0025);
    CHECK(f == Approx(-limit + k_stick * 0.0005).epsilon(1e-6));
    CHECK(stuck);
    // Back past the stick range: slides the other way.
    std::tie(f, stuck) = at(0.0);
    CHECK(f == Approx(limit));
    CHECK_FALSE(stuck);
    // Lifted off and pressed again: no memory of the old place.
    reference.update(Pose{Vec3(0.0, 0, kPlateTop + 0.05), Quat::Identity()});
    CHECK(at(0.004) == std::pair(0.0, true));
  }
}

TEST_CASE("friction: a sphere dragged displays the friction's moment about its centre",
          "[analytic]") {
  // A 2 cm sphere pressed with F_n = 6 N and dragged at μ = 0.3: the
  // friction μ F_n = 1.8 N acts at the contact point, 2 cm below the
  // centre: 0.036 N·m, balanced by the proxy's rotational coupling.
  const double radius = 0.02, mu = 0.3, normal_n = 6;
  RenderContext context = context_with(sphere_shape(radius));
  context.scene.front().friction = mu;
  const AnalyticScene scene = scene_for(context);
  FrictionalContactReference reference(scene);
  const double z = kPlateTop + radius - normal_n / kStiffness;
  IdealRendering ideal;
  for (int i = 0; i <= 40; ++i)
    ideal = reference.update(Pose{Vec3(0.0001 * i, 0, z), Quat::Identity()});
  REQUIRE_FALSE(reference.sticking());
  CHECK(ideal.display.force.x() == Approx(-mu * normal_n));
  CHECK(ideal.display.torque.y() == Approx(radius * mu * normal_n));  // 0.036 N·m
  CHECK(ideal.display.torque.y() == Approx(0.036));
  // The proxy turned so that its rotational spring gives that moment.
  CHECK(-kRotStiffness * rotation_vector(Quat::Identity() * ideal.proxy.q.conjugate()).y() ==
        Approx(ideal.display.torque.y()));
}

TEST_CASE("friction: mu = 0 is the frictionless ideal, bit for bit", "[analytic]") {
  const AnalyticScene scene = scene_for(context_with(sphere_shape(0.01)));
  FrictionalContactReference reference(scene);
  for (int k = 0; k < 50; ++k) {
    const Pose device{Vec3(0.001 * k, 0.0005 * k, kPlateTop + 0.008), Quat::Identity()};
    const IdealRendering with = reference.update(device);
    const IdealRendering without = ideal_rigid_contact(scene, device);
    CHECK(with.display.force == without.display.force);
    CHECK(with.proxy.p == without.proxy.p);
  }
}

TEST_CASE("tunnelling: passing through the box counts, going round it or backing out does not",
          "[analytic]") {
  AnalyticScene scene;  // a 2 mm plate: |x|, |y| <= 0.1 m, |z| <= 1 mm, turned and moved
  scene.box_pose = Pose{Vec3(0.3, -0.2, 0.1), quat_from_rotation_vector(Vec3(0.4, 0.1, -0.3))};
  scene.box_half_extents = Vec3(0.1, 0.1, 0.001);
  const auto world = [&](double x, double y, double z) {
    return scene.box_pose.transform_point(Vec3(x, y, z));
  };
  for (const hb::test::TunnellingPath& path : hb::test::plate_tunnelling_paths()) {
    INFO(path.what);
    BoxTunnellingDetector detector(scene);
    int passes = 0;
    for (const Vec3& p : path.points) passes += detector.update(world(p.x(), p.y(), p.z()));
    CHECK(passes == path.passes);
  }
}

}  // namespace
}  // namespace hb
