// The per-tick force model of Voxmap PointShell (algorithms/voxmap_pointshell/
// pointshell_contacts.cpp): the tangent-plane depth, Hooke's law, the N ≥ 10
// averaging rule, the braking viscosity's sign, the early exits, and the
// Jacobians against central differences. Units m, N, s.
#include "algorithms/voxmap_pointshell/pointshell_contacts.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "algorithms/voxmap_pointshell/voxmap.h"
#include "hapticbench/shapes.h"
#include "tests/support/proxy_fixtures.h"

namespace hb {
namespace {

CacheSettings no_cache() { return CacheSettings{false, {}}; }

// A shell of n copies of one point.
PointShell repeated_point(std::size_t n, const Vec3& r, const Vec3& normal) {
  return make_pointshell(std::vector<Vec3>(n, r), std::vector<Vec3>(n, normal), Vec3::Zero());
}

// A 40 cm slab 2 cm thick whose top face passes through the origin with
// normal tilt·z; untilted, the plane z = 0, on the voxel-centre plane of
// the grid.
SceneVoxmap slab_voxmap(double h, bool signed_distance, const Quat& tilt = Quat::Identity()) {
  SceneObject slab;
  Shape shape;
  shape.type = ShapeType::kBox;
  shape.size = Vec3(0.4, 0.4, 0.02);
  slab.shape = shape;
  slab.mesh = shape_mesh(shape);
  slab.pose.q = tilt;
  slab.pose.p = tilt * Vec3(0, 0, -0.01);
  VoxmapSettings settings;
  settings.voxel_size_m = h;
  settings.proximity_layers = 2;
  settings.signed_distance = signed_distance;
  return build_scene_voxmap({slab},
                            Eigen::AlignedBox3d(Vec3(-0.05, -0.05, -0.03), Vec3(0.05, 0.05, 0.05)),
                            settings, no_cache());
}

PointShell sphere_shell(double radius, double spacing) {
  Shape sphere;
  sphere.type = ShapeType::kSphere;
  sphere.radius = radius;
  sphere.subdivisions = 4;
  const PointShellPoints points = build_pointshell(shape_mesh(sphere), spacing, no_cache());
  return make_pointshell(points.points, points.normals, Vec3::Zero());
}

TEST_CASE("the averaging rule divides the summed wrench by N/10 from N = 10 on",
          "[voxmap_pointshell]") {
  CHECK(averaging_divisor(0) == 1);
  CHECK(averaging_divisor(9) == 1);
  CHECK(averaging_divisor(10) == 1);
  CHECK(averaging_divisor(25) == 2.5);
  PointShellGains gains;
  gains.stiffness = 3000;
  gains.braking_viscosity = 0;
  const double depth = 4e-4;
  for (std::size_t n = 1; n <= 30; ++n) {
    const PointShell shell = repeated_point(n, Vec3(0.003, 0, -0.01), Vec3::UnitZ());
    PointShellHits hits;
    for (std::size_t i = 0; i < n; ++i)
      hits.contacts.push_back({static_cast<int32_t>(i), depth, Vec3::Zero()});
    const ForceEvaluation f = pointshell_wrench(shell, hits, gains, RigidBodyState{}, true);
    // Each point alone: F = K d n, τ = r × F.
    const Vec3 single_force = gains.stiffness * depth * Vec3::UnitZ();
    const Vec3 single_torque = Vec3(0.003, 0, -0.01).cross(single_force);
    const double divisor = n < 10 ? 1.0 : static_cast<double>(n) / 10.0;
    INFO("N = " << n);
    CHECK((f.wrench.force - static_cast<double>(n) / divisor * single_force).norm() < 1e-12);
    CHECK((f.wrench.torque - static_cast<double>(n) / divisor * single_torque).norm() < 1e-12);
    // The Jacobians scale alike: ∂F_z/∂z = −K N/divisor.
    CHECK(f.stiffness(2, 2) ==
          Approx(-gains.stiffness * static_cast<double>(n) / divisor).epsilon(1e-12));
  }
}

TEST_CASE("a point on a flat spot of φ counts for the averaging and adds nothing else",
          "[voxmap_pointshell]") {
  // A point deep in a uniform block reads φ with no gradient: in contact
  // (N counts it) but without a direction, so no force, torque or stiffness.
  PointShellGains gains;
  gains.stiffness = 3000;
  gains.braking_viscosity = 0;
  const double depth = 4e-4;
  const Vec3 r(0.003, 0, -0.01);
  for (std::size_t flat = 0; flat <= 30; flat += 5) {
    const std::size_t pressing = 20;
    const PointShell shell = repeated_point(pressing + flat, r, Vec3::UnitZ());
    PointShellHits hits;
    for (std::size_t i = 0; i < pressing + flat; ++i)
      hits.contacts.push_back(
          {static_cast<int32_t>(i), i < pressing ? depth : 0.003, Vec3::Zero(), i >= pressing});
    const ForceEvaluation f = pointshell_wrench(shell, hits, gains, RigidBodyState{}, true);
    const double divisor = static_cast<double>(pressing + flat) / 10.0;
    const Vec3 force =
        gains.stiffness * depth * static_cast<double>(pressing) / divisor * Vec3::UnitZ();
    INFO(flat << " flat points");
    CHECK((f.wrench.force - force).norm() < 1e-12);
    CHECK((f.wrench.torque - r.cross(force)).norm() < 1e-12);
    CHECK(f.stiffness(2, 2) ==
          Approx(-gains.stiffness * static_cast<double>(pressing) / divisor).epsilon(1e-12));
    CHECK(f.stiffness(0, 0) == 0);
  }
}

TEST_CASE("the tangent-plane depth is measured from the voxel centre along the point's normal",
          "[voxmap_pointshell]") {
  const double h = 0.002;
  const SceneVoxmap voxmap = slab_voxmap(h, false);
  PointShellGains gains;
  gains.braking_viscosity = 0;
  const Vec3 normal = Vec3(0.3, -0.2, 1).normalized();
  const PointShell shell = repeated_point(1, Vec3::Zero(), normal);
  int in_contact = 0;
  for (double x = -0.0031; x < 0.003; x += 0.00037) {
    for (double z = -0.00117; z <= 0.0012; z += 0.0001) {
      RigidBodyState state;
      state.x = Vec3(x, 0.0007, z);
      PointShellHits hits;
      WorkCounters work;
      find_pointshell_hits(shell, voxmap.lookup, gains, state, hits, work);
      // The surface layer is |z_centre| ≤ h/2: only the voxels centred on z = 0.
      const Vec3 centre = h * (state.x / h).array().round().matrix();
      const double expected = std::abs(centre.z()) < 1e-12 ? normal.dot(centre - state.x) : 0.0;
      INFO("point " << state.x.transpose());
      if (expected > 1e-12) {
        REQUIRE(hits.contacts.size() == 1);
        CHECK(hits.contacts[0].depth == Approx(expected).margin(1e-15));
        const ForceEvaluation f = pointshell_wrench(shell, hits, gains, state, false);
        CHECK((f.wrench.force - gains.stiffness * expected * normal).norm() < 1e-9);
        ++in_contact;
      } else if (expected < -1e-12 || std::abs(centre.z()) > 1e-12) {
        CHECK(hits.contacts.empty());
      }
    }
  }
  CHECK(in_contact > 20);
}

TEST_CASE("past the surface layer a voxmap point takes its depth and direction from φ",
          "[voxmap_pointshell]") {
  // McNeely's interior voxels exert nothing, so a proxy pushed through the
  // one-voxel surface layer stayed trapped; with φ kept, a point in an
  // interior voxel acts as in the signed-distance variant: d = −φ(P),
  // F = K d ∇φ (the slab's φ is −z below its top face z = 0).
  const double h = 0.002;
  const SceneVoxmap voxmap = slab_voxmap(h, true);
  PointShellGains gains;  // the voxmap variant
  gains.braking_viscosity = 0;
  const Vec3 normal = Vec3(0.3, -0.2, 1).normalized();
  const PointShell shell = repeated_point(1, Vec3::Zero(), normal);
  int interior = 0, surface = 0;
  for (double z = -0.0057; z <= -0.0003; z += 0.0001) {
    RigidBodyState state;
    state.x = Vec3(0.0011, 0.0007, z);
    PointShellHits hits;
    WorkCounters work;
    find_pointshell_hits(shell, voxmap.lookup, gains, state, hits, work);
    INFO("z " << z);
    REQUIRE(hits.contacts.size() == 1);
    const PointHit& hit = hits.contacts[0];
    const ForceEvaluation f = pointshell_wrench(shell, hits, gains, state, false);
    if (z < -0.5 * h - 1e-9) {  // an interior voxel
      ++interior;
      CHECK(hit.field);
      CHECK(hit.depth == Approx(-z).margin(1e-6));
      CHECK((f.wrench.force - gains.stiffness * (-z) * Vec3::UnitZ()).norm() <=
            gains.stiffness * 1e-6);
    } else if (z > -0.5 * h + 1e-9) {  // the surface layer: the tangent plane
      ++surface;
      CHECK_FALSE(hit.field);
      CHECK(hit.depth == Approx(normal.dot(Vec3(0.002, 0, 0) - state.x)).margin(1e-12));
    }
  }
  CHECK(interior > 20);
  CHECK(surface > 5);
}

TEST_CASE("the signed-distance force gives back on every closed loop what it took",
          "[voxmap_pointshell]") {
  // A conservative force does no net work around a closed loop. A slab
  // tilted 0.3 rad (its surface crosses voxels at every height, so some
  // points sit below it in proximity voxels, whose centre is above it) and
  // a 2 cm sphere's shell (about 300 points: more than ten touch at once)
  // driven along random closed loops of position and orientation that dip
  // up to 2 mm into the slab or only graze it; the work of the wrench,
  // summed by the trapezoid rule over 4,000 steps per loop, is within 1 µJ
  // of zero (a few nJ here). McNeely's averaging (its divisor follows the
  // number of points in contact) fails it by up to 16 mJ, a force read only
  // in surface and interior voxels by up to 26 µJ; the voxmap variant
  // (McNeely's tangent plane and averaging, as published) fails it too.
  const double h = 0.002;
  const Quat tilt = quat_from_rotation_vector(Vec3(0.3, 0, 0));
  const Vec3 up = tilt * Vec3::UnitZ();  // the top face's normal
  const SceneVoxmap voxmap = slab_voxmap(h, true, tilt);
  const PointShell shell = sphere_shell(0.01, h);
  PointShellGains gains;
  gains.stiffness = 10000;
  gains.braking_viscosity = 0;
  const bool signed_distance = GENERATE(true, false);
  gains.signed_distance = signed_distance;
  double mcneely_largest = 0;  // the voxmap variant's largest |work| per loop, J
  const auto wrench_at = [&](const RigidBodyState& state, std::size_t& touching) {
    PointShellHits hits;
    find_pointshell_hits_flat(shell, voxmap.lookup, gains, state, hits);
    touching = std::max(touching, hits.contacts.size());
    return pointshell_wrench(shell, hits, gains, state, false).wrench;
  };
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (int loop = 0; loop < 6; ++loop) {
    const double dip = loop % 3 == 0 ? 0.0007 : 0.0025;  // grazing, or pressed
    const auto in_plane = [&](const Vec3& v) { return Vec3(v - v.dot(up) * up); };
    const Vec3 along = in_plane(0.004 * Vec3(unit(random), unit(random), unit(random)));
    const Vec3 across = in_plane(0.004 * Vec3(unit(random), unit(random), unit(random)));
    const Vec3 turn_a = 0.3 * Vec3(unit(random), unit(random), unit(random));
    const Vec3 turn_b = 0.3 * Vec3(unit(random), unit(random), unit(random));
    const auto pose_at = [&](double s) {
      const double c = std::cos(2 * std::numbers::pi * s), d = std::sin(2 * std::numbers::pi * s);
      RigidBodyState state;
      // The centre 1 cm above the surface less the dip at mid-loop.
      state.x = (0.01 + 0.0005 - dip * 0.5 * (1 - c)) * up + d * along + (1 - c) * across;
      state.q = quat_from_rotation_vector(d * turn_a + (1 - c) * turn_b);
      return state;
    };
    constexpr int kSteps = 4000;
    double work = 0, work_magnitude = 0;
    std::size_t touching = 0;
    RigidBodyState previous = pose_at(0);
    Wrench previous_wrench = wrench_at(previous, touching);
    for (int k = 1; k <= kSteps; ++k) {
      const RigidBodyState state = pose_at(static_cast<double>(k) / kSteps);
      const Wrench wrench = wrench_at(state, touching);
      const Vec3 moved = state.x - previous.x;
      const Vec3 turned = rotation_vector(state.q * previous.q.conjugate());
      const double step_work = 0.5 * (wrench.force + previous_wrench.force).dot(moved) +
                               0.5 * (wrench.torque + previous_wrench.torque).dot(turned);
      work += step_work;
      work_magnitude += std::abs(step_work);
      previous = state;
      previous_wrench = wrench;
    }
    INFO("loop " << loop << ": dip " << dip << " m, up to " << touching << " points touching, work "
                 << work << " J of " << work_magnitude << " J moved through");
    CHECK(touching > 0);
    if (dip > 0.001) CHECK(touching >= 10);
    CHECK(work_magnitude > 1e-5);  // the loop goes through contact
    if (signed_distance) CHECK(std::abs(work) <= 1e-6);
    mcneely_largest = std::max(mcneely_largest, std::abs(work));
  }
  // McNeely's tangent-plane force with its averaging, as published, is not
  // the gradient of a potential: the same loops gain or lose energy.
  if (!signed_distance) {
    WARN("voxmap variant: largest |work| over a loop " << mcneely_largest << " J");
    CHECK(mcneely_largest > 1e-4);
  }
}

TEST_CASE("braking viscosity opposes motion towards the scene and is zero moving away",
          "[voxmap_pointshell]") {
  PointShellGains gains;
  gains.braking_viscosity = 7;
  // A point on the +x side of a tool, inward normal −x; the scene lies at +x.
  const Vec3 r(0.01, 0, 0);
  const Vec3 n(-1, 0, 0);
  const PointShell shell = repeated_point(1, r, n);
  PointShellHits hits;
  hits.braking.push_back(0);
  RigidBodyState state;

  state.v = Vec3(0.2, 0.05, 0);  // towards the scene: n·v = −0.2 < 0
  ForceEvaluation f = pointshell_wrench(shell, hits, gains, state, false);
  // F = −b v (−n·v)
  CHECK((f.wrench.force - (-gains.braking_viscosity * state.v * (-n.dot(state.v)))).norm() < 1e-12);
  CHECK(f.wrench.force.dot(state.v) < 0);
  CHECK((f.wrench.torque - r.cross(f.wrench.force)).norm() < 1e-15);

  state.v = Vec3(-0.2, 0.05, 0);  // away from the scene
  f = pointshell_wrench(shell, hits, gains, state, true);
  CHECK(f.wrench.force.norm() == 0);
  CHECK(f.damping.norm() == 0);
  state.v = Vec3(0, 0.3, 0.1);  // sliding along it: n·v = 0
  CHECK(pointshell_wrench(shell, hits, gains, state, false).wrench.force.norm() == 0);

  // Turning into the scene: u = ω × r.
  state.v = Vec3::Zero();
  state.w = Vec3(0, 0, -5);  // ω × r = (0, −0.05, 0): tangential, no braking
  CHECK(pointshell_wrench(shell, hits, gains, state, false).wrench.force.norm() == 0);
  state.x = Vec3::Zero();
  const PointShell tilted = repeated_point(1, r, Vec3(-1, 1, 0).normalized());
  state.w = Vec3(0, 0, -5);  // u = (0, −0.05, 0), n·u < 0
  f = pointshell_wrench(tilted, hits, gains, state, false);
  const Vec3 u = state.w.cross(r);
  CHECK(f.wrench.force.dot(u) < 0);

  // The averaging rule holds for braking points apart: 20 points brake
  // like 10.
  const PointShell twenty = repeated_point(20, r, n);
  PointShellHits all;
  for (int32_t i = 0; i < 20; ++i) all.braking.push_back(i);
  state = RigidBodyState{};
  state.v = Vec3(0.2, 0, 0);
  const ForceEvaluation one = pointshell_wrench(shell, hits, gains, state, false);
  const ForceEvaluation many = pointshell_wrench(twenty, all, gains, state, false);
  CHECK((many.wrench.force - 10 * one.wrench.force).norm() < 1e-12);
}

TEST_CASE("a braking point that acts is reported with the scene's normal and its distance",
          "[voxmap_pointshell]") {
  // Over the slab (top face z = 0), a point 1.73 mm above it in a proximity
  // voxel; φ is linear there, so its interpolation is exact.
  const double h = 0.001;
  const SceneVoxmap voxmap = slab_voxmap(h, true);
  const PointShell shell = repeated_point(1, Vec3::Zero(), Vec3(0.3, 0, 1).normalized());
  PointShellGains gains;
  gains.braking_viscosity = 5;
  RigidBodyState state;
  state.x = Vec3(0.0021, -0.0013, 0.00173);
  PointShellHits hits;
  WorkCounters work;
  find_pointshell_hits(shell, voxmap.lookup, gains, state, hits, work);
  REQUIRE(hits.contacts.empty());
  REQUIRE(hits.braking.size() == 1);
  std::vector<Contact> contacts;
  state.v = Vec3(0.01, 0, -0.1);  // towards the slab
  report_contacts(shell, hits, voxmap.lookup, gains, state, contacts);
  REQUIRE(contacts.size() == 1);
  CHECK((contacts[0].point - state.x).norm() < 1e-15);
  CHECK((contacts[0].normal - Vec3::UnitZ()).norm() < 1e-6);
  CHECK(contacts[0].depth == Approx(-0.00173).margin(1e-6));
  // Moving away, or without braking: no force, nothing reported.
  contacts.clear();
  state.v = Vec3(0.01, 0, 0.1);
  report_contacts(shell, hits, voxmap.lookup, gains, state, contacts);
  CHECK(contacts.empty());
  state.v = Vec3(0.01, 0, -0.1);
  gains.braking_viscosity = 0;
  report_contacts(shell, hits, voxmap.lookup, gains, state, contacts);
  CHECK(contacts.empty());
}

TEST_CASE("braking points report what a fresh reading of φ gives, in both variants",
          "[voxmap_pointshell]") {
  // A 2 cm sphere sinking into the slab, tilted and turning: contacts below,
  // a ring of braking points above them. The signed-distance search keeps
  // φ at its braking points for the report; the voxmap one does not, and
  // the report reads it. Either way the report is what reading φ afresh
  // at each acting braking point gives.
  const double h = 0.001;
  const PointShell shell = sphere_shell(0.02, h);
  const SceneVoxmap voxmap = slab_voxmap(h, true);  // with φ, as the renderer keeps it
  for (const bool signed_distance : {false, true}) {
    PointShellGains gains;
    gains.signed_distance = signed_distance;
    gains.braking_viscosity = 5;
    RigidBodyState state;
    state.x = Vec3(0.0003, -0.0007, 0.0195);
    state.q = Quat(Eigen::AngleAxisd(0.3, Vec3(1, 2, 0).normalized()));
    state.v = Vec3(0.02, 0, -0.1);
    state.w = Vec3(1, -2, 3);
    PointShellHits hits;
    WorkCounters work;
    find_pointshell_hits(shell, voxmap.lookup, gains, state, hits, work);
    INFO((signed_distance ? "signed distance" : "voxmap")
         << ": " << hits.braking.size() << " braking points");
    REQUIRE(hits.braking.size() > 20);
    CHECK(hits.braking_fields.size() == (signed_distance ? hits.braking.size() : 0));
    std::vector<Contact> reported;
    report_contacts(shell, hits, voxmap.lookup, gains, state, reported);
    // The braking points reported follow the contacts; each against φ read now.
    const std::size_t first_braking = hits.contacts.size();
    REQUIRE(reported.size() > first_braking + 10);
    const Mat3 rotation = state.q.toRotationMatrix();
    std::size_t k = first_braking;
    for (const int32_t i : hits.braking) {
      const Vec3 s = rotation * shell.points[i];
      if (!(braking_speed(rotation * shell.normals[i], s, state) < -1e-9)) continue;
      while (k < reported.size() && (reported[k].point - (state.x + s)).norm() > 1e-15) ++k;
      REQUIRE(k < reported.size());
      Vec3 gradient;
      const double phi = voxmap.lookup.interpolated_distance(state.x + s, gradient);
      CHECK(reported[k].depth == -phi);
      CHECK((reported[k].normal - gradient.normalized()).norm() < 1e-15);
    }
  }
}

TEST_CASE("a tool clear of the scene costs one bounding test", "[voxmap_pointshell]") {
  const SceneVoxmap voxmap = slab_voxmap(0.001, false);
  const PointShell shell = sphere_shell(0.02, 0.001);
  PointShellGains gains;
  RigidBodyState state;
  state.x = Vec3(0, 0, 0.04);  // 2 cm above the slab, beyond the proximity layers
  PointShellHits hits;
  WorkCounters work;
  find_pointshell_hits(shell, voxmap.lookup, gains, state, hits, work);
  CHECK(hits.contacts.empty());
  CHECK(hits.braking.empty());
  CHECK(work.get("points_looked_up") == 0);
  CHECK(work.get("sphere_tests") == 1);
  // Close to the slab only the leaves near it are looked up.
  state.x = Vec3(0, 0, 0.0205);
  work = WorkCounters{};
  find_pointshell_hits(shell, voxmap.lookup, gains, state, hits, work);
  INFO(work.get("points_looked_up") << " of " << shell.points.size() << " points looked up");
  CHECK(work.get("points_looked_up") > 0);
  CHECK(work.get("points_looked_up") < static_cast<int64_t>(shell.points.size()) / 3);
  CHECK_FALSE(hits.braking.empty());
}

bool same_hits(const PointShellHits& a, const PointShellHits& b) {
  if (a.braking != b.braking || a.contacts.size() != b.contacts.size()) return false;
  for (std::size_t k = 0; k < a.contacts.size(); ++k) {
    const PointHit& x = a.contacts[k];
    const PointHit& y = b.contacts[k];
    if (x.point != y.point || x.depth != y.depth || x.reference != y.reference ||
        x.field != y.field)
      return false;
  }
  return true;
}

// A box with a through-hole (edges, corners, a tunnel) and a sphere, at
// 1 mm voxels, both variants' data.
SceneVoxmap holed_box_and_ball() {
  Shape holed;
  holed.type = ShapeType::kBoxWithHole;
  holed.size = Vec3(0.06, 0.06, 0.02);
  holed.hole_size = Vec3(0.02, 0.02, 0);
  Shape ball;
  ball.type = ShapeType::kSphere;
  ball.radius = 0.015;
  std::vector<SceneObject> scene(2);
  scene[0].shape = holed;
  scene[0].mesh = shape_mesh(holed);
  scene[1].shape = ball;
  scene[1].mesh = shape_mesh(ball);
  scene[1].pose.p = Vec3(0.05, 0, 0.02);
  VoxmapSettings settings;
  settings.voxel_size_m = 0.001;
  settings.signed_distance = true;
  return build_scene_voxmap(scene,
                            Eigen::AlignedBox3d(Vec3(-0.06, -0.06, -0.04), Vec3(0.1, 0.06, 0.06)),
                            settings, no_cache());
}

// A capsule tool (4 mm radius, 2 cm long) at 1 mm spacing.
PointShell capsule_shell() {
  Shape capsule;
  capsule.type = ShapeType::kCapsule;
  capsule.radius = 0.004;
  capsule.length = 0.02;
  const PointShellPoints points = build_pointshell(shape_mesh(capsule), 0.001, no_cache());
  return make_pointshell(points.points, points.normals, Vec3(0, 0, 0.001));
}

bool same_wrench(const PointShell& shell, const PointShellHits& a, const PointShellHits& b,
                 const PointShellGains& gains, const RigidBodyState& state) {
  const ForceEvaluation x = pointshell_wrench(shell, a, gains, state, true);
  const ForceEvaluation y = pointshell_wrench(shell, b, gains, state, true);
  return x.wrench.force == y.wrench.force && x.wrench.torque == y.wrench.torque &&
         x.stiffness == y.stiffness && x.damping == y.damping;
}

TEST_CASE("the tree finds exactly what the flat scan of every point finds", "[voxmap_pointshell]") {
  const SceneVoxmap voxmap = holed_box_and_ball();
  const PointShell shell = capsule_shell();
  for (const bool signed_distance : {false, true}) {
    PointShellGains gains;
    gains.signed_distance = signed_distance;
    std::mt19937 random(11);
    std::uniform_real_distribution<double> unit(-1, 1);
    int contact_poses = 0, braking_poses = 0;
    int64_t tree_points = 0;
    for (int n = 0; n < 400; ++n) {
      RigidBodyState state;
      // Near the holed box's top face, in its hole, or near the sphere.
      const Vec3 anchors[] = {Vec3(0.02, 0.01, 0.014), Vec3(0.0, 0.009, 0.0), Vec3(0.05, 0, 0.039)};
      state.x = anchors[n % 3] + 0.006 * Vec3(unit(random), unit(random), unit(random));
      state.q = quat_from_rotation_vector(3.0 * Vec3(unit(random), unit(random), unit(random)));
      state.v = Vec3(unit(random), unit(random), unit(random));
      state.w = 5 * Vec3(unit(random), unit(random), unit(random));
      PointShellHits tree, flat;
      WorkCounters work;
      find_pointshell_hits(shell, voxmap.lookup, gains, state, tree, work);
      find_pointshell_hits_flat(shell, voxmap.lookup, gains, state, flat);
      tree_points += work.get("points_looked_up");
      INFO("pose " << n << " at " << state.x.transpose());
      REQUIRE(same_hits(tree, flat));
      CHECK(same_wrench(shell, tree, flat, gains, state));
      if (!flat.contacts.empty()) ++contact_poses;
      if (!flat.braking.empty()) ++braking_poses;
    }
    INFO("signed distance " << signed_distance);
    CHECK(contact_poses > 100);
    CHECK(braking_poses > 100);
    // And the tree skips a part of the points, though every pose is near the scene.
    CHECK(tree_points < 400 * static_cast<int64_t>(shell.points.size()) * 7 / 10);
  }
}

TEST_CASE("the search from the last front finds exactly what the flat scan finds, for less",
          "[voxmap_pointshell]") {
  // Random walks at haptic-rate steps (up to 0.4 mm and 0.02 rad a tick)
  // in and out of contact, with jumps of a few centimetres now and then.
  const SceneVoxmap voxmap = holed_box_and_ball();
  const PointShell shell = capsule_shell();
  for (const bool signed_distance : {false, true}) {
    PointShellGains gains;
    gains.signed_distance = signed_distance;
    std::mt19937 random(23);
    std::uniform_real_distribution<double> unit(-1, 1);
    PointShellFront front;
    RigidBodyState state;
    state.x = Vec3(0.02, 0.01, 0.02);
    int contact_ticks = 0, jumps = 0;
    WorkCounters coherent_work, full_work;
    for (int n = 0; n < 3000; ++n) {
      if (n % 500 == 250) {
        state.x = Vec3(0.1 * unit(random), 0.06 * unit(random), 0.03 + 0.02 * unit(random));
        ++jumps;
      } else {
        state.x += 0.0004 * Vec3(unit(random), unit(random), unit(random));
        // Drawn back towards the scene's middle so that the walk stays near it.
        state.x += 0.002 * (Vec3(0.02, 0.0, 0.015) - state.x);
      }
      state.q = quat_from_rotation_vector(0.02 * Vec3(unit(random), unit(random), unit(random))) *
                state.q;
      state.v = Vec3(unit(random), unit(random), unit(random));
      PointShellHits coherent, full, flat;
      find_pointshell_hits_coherent(shell, voxmap.lookup, gains, state, 0, front, coherent,
                                    coherent_work);
      find_pointshell_hits(shell, voxmap.lookup, gains, state, full, full_work);
      find_pointshell_hits_flat(shell, voxmap.lookup, gains, state, flat);
      INFO("tick " << n << " at " << state.x.transpose());
      REQUIRE(same_hits(coherent, flat));
      REQUIRE(same_hits(full, flat));
      CHECK(same_wrench(shell, coherent, flat, gains, state));
      if (!flat.contacts.empty()) ++contact_ticks;
    }
    INFO("signed distance " << signed_distance << ": spheres tested "
                            << coherent_work.get("sphere_tests") << " from the front, "
                            << full_work.get("sphere_tests") << " from the root");
    CHECK(contact_ticks > 300);
    CHECK(jumps == 6);
    CHECK(coherent_work.get("sphere_tests") < full_work.get("sphere_tests") / 2);
    // About the same points: a leaf looked up stays in the front until its
    // own sphere is clear, which the voxel-quantised bound may say later
    // than its parent's.
    CHECK(coherent_work.get("points_looked_up") <= full_work.get("points_looked_up") * 21 / 20);
  }
}

TEST_CASE("the point budget's stride rises at once and falls with a fifth to spare",
          "[voxmap_pointshell]") {
  CHECK(point_budget_stride(5000, 0, 1) == 1);  // no budget
  CHECK(point_budget_stride(5000, -1, 3) == 1);
  CHECK(point_budget_stride(512, 512, 1) == 1);
  CHECK(point_budget_stride(513, 512, 1) == 2);
  CHECK(point_budget_stride(3100, 512, 1) == 7);  // ⌈3100 / 512⌉
  // Lowered from 7 only to a stride whose budget has a fifth to spare:
  // 2,500 ≤ 0.8 · 512 · k first holds at k = 7 (2,867), not at k = 6 (2,458).
  CHECK(point_budget_stride(2500, 512, 7) == 7);
  CHECK(point_budget_stride(2400, 512, 7) == 6);
  CHECK(point_budget_stride(300, 512, 7) == 1);
  CHECK(point_budget_stride(450, 512, 2) == 2);  // 450 > 0.8 · 512
}

// A 6 cm × 6 cm × 1 cm box tool at 1 mm spacing, about 9,000 points.
PointShell plate_shell() {
  Shape plate;
  plate.type = ShapeType::kBox;
  plate.size = Vec3(0.06, 0.06, 0.01);
  const PointShellPoints points = build_pointshell(shape_mesh(plate), 0.001, no_cache());
  return make_pointshell(points.points, points.normals, Vec3::Zero());
}

TEST_CASE("within a point budget a face pressed flat looks up a sample and keeps its wrench",
          "[voxmap_pointshell]") {
  // The plate's bottom face (3,600 points) 0.4 mm into the slab, tilted
  // a little so that the depths vary across the face, sliding slowly: the
  // crowded contact of a box on a floor.
  const PointShell shell = plate_shell();
  const int64_t budget = 400;
  for (const bool signed_distance : {false, true}) {
    const SceneVoxmap voxmap = slab_voxmap(0.001, signed_distance);
    PointShellGains gains;
    gains.signed_distance = signed_distance;
    PointShellFront exact_front, budget_front;
    WorkCounters exact_work, budget_work;
    double force_error_max = 0, torque_error_max = 0, force_min = 1e9;
    int64_t looked_up_max = 0;
    for (int tick = 0; tick < 200; ++tick) {
      RigidBodyState state;
      state.x = Vec3(2e-5 * tick, 1e-5 * tick, 0.005 - 0.0004);
      state.q = quat_from_rotation_vector(Vec3(0.004, -0.003, 0.0005 * tick));
      state.v = Vec3(0.02, 0.01, -0.005);
      PointShellHits exact, sampled;
      find_pointshell_hits_coherent(shell, voxmap.lookup, gains, state, 0, exact_front, exact,
                                    exact_work);
      const int64_t before = budget_work.get("points_looked_up");
      find_pointshell_hits_coherent(shell, voxmap.lookup, gains, state, budget, budget_front,
                                    sampled, budget_work);
      const ForceEvaluation a = pointshell_wrench(shell, exact, gains, state, true);
      const ForceEvaluation b = pointshell_wrench(shell, sampled, gains, state, true);
      if (tick == 0) {
        // The first search has no count to go by: every point, exactly.
        CHECK(sampled.weight == 1);
        CHECK(same_hits(exact, sampled));
        continue;
      }
      INFO("signed distance " << signed_distance << ", tick " << tick);
      REQUIRE(sampled.weight == budget_front.stride());
      REQUIRE(budget_front.stride() > 4);
      looked_up_max = std::max(looked_up_max, budget_work.get("points_looked_up") - before);
      const double force = a.wrench.force.norm();
      force_min = std::min(force_min, force);
      force_error_max = std::max(force_error_max, (b.wrench.force - a.wrench.force).norm() / force);
      // Torque about the centre of mass relative to the force's moment arm
      // over the face (3 cm).
      torque_error_max =
          std::max(torque_error_max, (b.wrench.torque - a.wrench.torque).norm() / (0.03 * force));
      // The Jacobians are scaled with the wrench.
      CHECK(b.stiffness(2, 2) == Approx(a.stiffness(2, 2)).epsilon(0.1));
    }
    INFO("signed distance " << signed_distance << ": force within " << force_error_max
                            << ", torque within " << torque_error_max << ", at most "
                            << looked_up_max << " points a search");
    CHECK(force_min > 1);  // a real press
    CHECK(force_error_max < 0.05);
    CHECK(torque_error_max < 0.05);
    // About the budget a search (a stride rounds per leaf), where the
    // exact search looks up every point of the face.
    CHECK(looked_up_max <= budget * 5 / 4);
    CHECK(exact_work.get("points_looked_up") > 200 * 3000);
    CHECK(budget_work.get("searches_over_budget") == 199);
    CHECK(budget_work.get("points_over_budget") > 199 * 2500);
    CHECK(exact_work.get("points_over_budget") == 0);
  }
}

TEST_CASE("a budget the contact fits in changes nothing, and a lifted tool gets every point back",
          "[voxmap_pointshell]") {
  const PointShell shell = plate_shell();
  const SceneVoxmap voxmap = slab_voxmap(0.001, false);
  PointShellGains gains;
  PointShellFront exact_front, budget_front;
  WorkCounters exact_work, budget_work;
  // Pressed (over budget), lifted clear, then tilted onto one corner
  // (within budget): from the touch on, the hits are the exact ones.
  for (int tick = 0; tick < 120; ++tick) {
    RigidBodyState state;
    state.x = tick < 40 ? Vec3(0, 0, 0.0046) : tick < 80 ? Vec3(0, 0, 0.02) : Vec3(0, 0, 0.009);
    state.q = tick < 80 ? Quat::Identity() : quat_from_rotation_vector(Vec3(0.1, -0.1, 0));
    PointShellHits exact, sampled;
    find_pointshell_hits_coherent(shell, voxmap.lookup, gains, state, 0, exact_front, exact,
                                  exact_work);
    find_pointshell_hits_coherent(shell, voxmap.lookup, gains, state, 2500, budget_front, sampled,
                                  budget_work);
    INFO("tick " << tick << " exact looked up " << exact_work.get("points_looked_up"));
    if (tick >= 1 && tick < 40) CHECK(budget_front.stride() > 1);
    if (tick >= 82) {
      CHECK(!exact.contacts.empty());
      CHECK(budget_front.stride() == 1);
      CHECK(same_hits(exact, sampled));
      CHECK(same_wrench(shell, exact, sampled, gains, state));
    }
  }
}

TEST_CASE("the contact Jacobians match central differences", "[voxmap_pointshell]") {
  for (const bool signed_distance : {false, true}) {
    const double h = 0.002;
    const SceneVoxmap voxmap = slab_voxmap(h, signed_distance);
    const PointShell shell = sphere_shell(0.02, h);
    PointShellGains gains;
    gains.stiffness = 5000;
    gains.braking_viscosity = 40;
    gains.signed_distance = signed_distance;
    RigidBodyState state;
    state.x = Vec3(0.00031, -0.00047, 0.02 - 0.0013);
    state.q = quat_from_rotation_vector(Vec3(0.11, 0.23, -0.31));
    state.v = Vec3(0.02, -0.01, -0.05);
    state.w = Vec3(0.3, -0.2, 0.5);

    const auto hits_at = [&](const RigidBodyState& s) {
      PointShellHits hits;
      WorkCounters work;
      find_pointshell_hits(shell, voxmap.lookup, gains, s, hits, work);
      return hits;
    };
    const PointShellHits hits = hits_at(state);
    INFO((signed_distance ? "signed distance" : "voxmap")
         << ": " << hits.contacts.size() << " contacts, " << hits.braking.size() << " braking");
    REQUIRE(hits.contacts.size() >= 10);  // the averaging rule is in play
    REQUIRE_FALSE(hits.braking.empty());

    // The same points act at every perturbed state, so the force is smooth there.
    const double step = 1e-7;
    for (int c = 0; c < 12; ++c) {
      for (const double sign : {-1.0, 1.0}) {
        const PointShellHits moved = hits_at(test::perturbed(state, c, sign * step));
        REQUIRE(moved.contacts.size() == hits.contacts.size());
        for (std::size_t i = 0; i < hits.contacts.size(); ++i)
          REQUIRE(moved.contacts[i].point == hits.contacts[i].point);
        REQUIRE(moved.braking == hits.braking);
      }
    }
    const auto wrench = [&](const RigidBodyState& s) {
      return pointshell_wrench(shell, hits_at(s), gains, s, false).wrench;
    };
    const Eigen::Matrix<double, 6, 12> numeric = test::numeric_jacobian(wrench, state, step);
    const Eigen::Matrix<double, 6, 12> analytic =
        test::analytic_jacobian(pointshell_wrench(shell, hits, gains, state, true));
    INFO("analytic\n" << analytic << "\nnumeric\n" << numeric);
    CHECK((analytic - numeric).cwiseAbs().maxCoeff() <= 1e-5 * analytic.cwiseAbs().maxCoeff());
    CHECK(analytic.block<6, 6>(0, 6).norm() > 0);  // braking damping present
  }
}

}  // namespace
}  // namespace hb
