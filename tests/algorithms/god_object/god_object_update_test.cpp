// The god-object update against closed forms: a cube and a point pressed
// into a slab settle on its face at the standoff, never below it, with the
// coupling force of ideal rigid contact; sliding under load follows the
// device tangentially; random device motions never push a vertex through.
#include "algorithms/god_object/god_object_update.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <random>

#include "algorithms/god_object/god_object.h"
#include "hapticbench/param_set.h"
#include "hapticbench/shapes.h"
#include "tests/support/proxy_fixtures.h"
#include "tests/support/shape_fixtures.h"

namespace hb {
namespace {

using test::at;

constexpr double kCube = 0.04;  // cube tool edge (m)

// A 0.4 × 0.4 × 0.02 m slab whose top face is the plane z = 0, with its mesh.
RenderContext slab_context(const Tool& tool) {
  RenderContext context;
  SceneObject slab =
      test::box_object(Vec3(0.4, 0.4, 0.02), Pose{Vec3(0, 0, -0.01), Quat::Identity()});
  slab.mesh = shape_mesh(*slab.shape);
  context.scene.push_back(slab);
  context.tool = tool;
  context.coupling = test::example_gains();
  return context;
}

Tool cube_tool() { return test::meshed_box_tool(Vec3::Constant(kCube)); }

// Lowest z of the tool's vertices at a tool-frame pose (m).
double lowest_vertex_z(const Tool& tool, const Pose& pose) {
  return test::lowest_vertex_z(tool.mesh, pose);
}

TEST_CASE("a cube pressed into a slab rests on the face within the standoff") {
  const RenderContext context = slab_context(cube_tool());
  GodObjectSettings settings;
  GodObjectSolver solver(context, settings);
  const double above = 0.5 * kCube;  // tool-frame height when resting on z = 0
  solver.reset(at(Vec3(0.01, -0.02, above + 0.01)));

  // The device goes 3 mm below the resting height in one jump.
  const Pose target = at(Vec3(0.01, -0.02, above - 0.003));
  for (int update = 0; update < 20; ++update) solver.update(target);

  const Pose& proxy = solver.proxy_pose();
  const double gap = lowest_vertex_z(context.tool, proxy);
  CHECK(gap >= 0.0);
  CHECK(gap <= settings.standoff_m * 1.0001);
  CHECK(proxy.p.x() == Approx(0.01).margin(1e-9));
  CHECK(proxy.p.y() == Approx(-0.02).margin(1e-9));
  CHECK(proxy.q.angularDistance(Quat::Identity()) < 1e-9);
  // Face on face: at least three corners hold it, each pushing along +z.
  REQUIRE(solver.contacts().size() >= 3);
  for (const KeptContact& contact : solver.contacts()) {
    CHECK(contact.geometry.normal.z() == Approx(1.0).margin(1e-12));
    CHECK(contact.geometry.gap >= 0.0);
  }
  // The coupling spring then holds 3 mm plus the gap: within 1 % of the
  // ideal rigid contact's k_t · 3 mm.
  const double force = context.coupling.k_t * (proxy.p.z() - target.p.z());
  CHECK(force == Approx(context.coupling.k_t * 0.003).epsilon(0.01));
}

TEST_CASE("a cube sliding under load follows the device tangentially on the face") {
  const RenderContext context = slab_context(cube_tool());
  GodObjectSolver solver(context, GodObjectSettings{});
  const double above = 0.5 * kCube;
  solver.reset(at(Vec3(0, 0, above + 0.002)));
  for (int tick = 0; tick <= 400; ++tick) {
    const double x = 0.05 * std::min(1.0, tick / 300.0);
    solver.update(at(Vec3(x, 0.0, above - 0.002)));
    REQUIRE(lowest_vertex_z(context.tool, solver.proxy_pose()) >= 0.0);
  }
  CHECK(solver.proxy_pose().p.x() == Approx(0.05).margin(1e-7));
  CHECK(solver.proxy_pose().p.z() - above <= 1.0001e-5);
}

TEST_CASE("random device motions never carry a cube vertex below the face") {
  const RenderContext context = slab_context(cube_tool());
  GodObjectSolver solver(context, GodObjectSettings{});
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> offset(-0.01, 0.01);
  std::uniform_real_distribution<double> angle(-0.4, 0.4);
  solver.reset(at(Vec3(0, 0, 0.05)));
  Pose target = at(Vec3(0, 0, 0.05));
  int contact_updates = 0;
  for (int step = 0; step < 300; ++step) {
    // A random walk that keeps returning toward (and below) the face.
    target.p += Vec3(offset(rng), offset(rng), offset(rng) - 0.004);
    target.p.z() = std::clamp(target.p.z(), 0.0, 0.06);
    target.p.x() = std::clamp(target.p.x(), -0.1, 0.1);
    target.p.y() = std::clamp(target.p.y(), -0.1, 0.1);
    target.q =
        (quat_from_rotation_vector(Vec3(angle(rng), angle(rng), angle(rng)) * 0.1) * target.q)
            .normalized();
    solver.update(target);
    REQUIRE(lowest_vertex_z(context.tool, solver.proxy_pose()) >= 0.0);
    if (!solver.contacts().empty()) ++contact_updates;
  }
  CHECK(contact_updates > 50);  // the walk did press on the face
}

TEST_CASE("a tilted cube pressed down ends with the coupling force along the face normal") {
  // The device is tilted 0.2 rad about x and 3 mm deep: the contact-free
  // coupling minimum lies below the face, so the proxy ends on the face with
  // the coupling wrench along the contact normals: no tangential force.
  const RenderContext context = slab_context(cube_tool());
  GodObjectSolver solver(context, GodObjectSettings{});
  solver.reset(at(Vec3(0, 0, 0.05)));
  const Pose target =
      at(Vec3(0, 0, 0.5 * kCube - 0.003), quat_from_rotation_vector(Vec3(0.2, 0, 0)));
  for (int update = 0; update < 200; ++update) solver.update(target);
  const Pose& proxy = solver.proxy_pose();
  CHECK(lowest_vertex_z(context.tool, proxy) >= 0.0);
  const Vec3 force = context.coupling.k_t * (target.p - proxy.p);
  CHECK(std::abs(force.x()) < 1e-3 * force.norm());
  CHECK(std::abs(force.y()) < 1e-3 * force.norm());
  CHECK(force.z() < 0.0);  // the device is below the proxy: it is pushed up
}

TEST_CASE("the 3-DOF god-object keeps a point on the face and in the corner of two faces") {
  RenderContext context = slab_context(cube_tool());
  GodObjectSettings settings;
  settings.point_tool = true;
  GodObjectSolver solver(context, settings);

  SECTION("pressed into the top face: projected onto it") {
    solver.reset(at(Vec3(0.05, 0.02, 0.01)));
    const Pose target = at(Vec3(0.07, 0.02, -0.004));
    for (int update = 0; update < 20; ++update) solver.update(target);
    const Vec3 p = solver.proxy_pose().p;
    CHECK(p.z() >= 0.0);
    CHECK(p.z() <= 1.0001e-5);
    CHECK(p.x() == Approx(0.07).margin(1e-9));
    REQUIRE(solver.contacts().size() >= 1);
    CHECK(solver.contacts().front().geometry.normal.z() == Approx(1.0));
  }
  SECTION("pressed into the corner of a wall and the floor: held in the corner") {
    // A wall whose face x = 0.1 stands on the slab (top face z = 0).
    SceneObject wall =
        test::box_object(Vec3(0.02, 0.4, 0.22), Pose{Vec3(0.11, 0, 0.09), Quat::Identity()});
    wall.mesh = shape_mesh(*wall.shape);
    context.scene.push_back(wall);
    GodObjectSolver cornered(context, settings);
    cornered.reset(at(Vec3(0.05, 0.0, 0.05)));
    // The straight path meets the wall first (at z ≈ 6 mm), then slides down.
    const Pose target = at(Vec3(0.11, 0.01, -0.003));
    for (int update = 0; update < 50; ++update) cornered.update(target);
    const Vec3 p = cornered.proxy_pose().p;
    CHECK(p.x() <= 0.1);
    CHECK(p.z() >= 0.0);
    CHECK(p.x() == Approx(0.1).margin(1.1e-5));
    CHECK(p.z() == Approx(0.0).margin(1.1e-5));
    CHECK(p.y() == Approx(0.01).margin(1e-9));
    CHECK(cornered.contacts().size() >= 2);
  }
}

TEST_CASE("the god-object renderer started inside reports the escape and pushes the device out") {
  const RenderContext context = slab_context(cube_tool());
  const std::unique_ptr<Renderer> renderer =
      create_god_object(context, ParamSet("/algorithms/0/params"));
  const double above = 0.5 * kCube;
  DeviceSample device;
  device.pose = at(Vec3(0.0, 0.0, above - 0.002));  // 2 mm deep, held there
  renderer->reset(device.pose);
  for (int tick = 0; tick < 50; ++tick) {
    device.tick = tick;
    const TickResult result = renderer->step(device);
    INFO("tick " << tick);
    CHECK(lowest_vertex_z(context.tool, result.proxy) >= 0.0);
    CHECK(result.work.get("start_escapes") == (tick == 0 ? 1 : 0));
    if (tick == 0) CHECK(result.work.get("start_escape_um") == Approx(2000).margin(12));
    // The coupling pulls the device up toward the proxy on the face:
    // k_t × 2 mm.
    CHECK(result.display.force.z() == Approx(context.coupling.k_t * 0.002).epsilon(0.02));
    if (SlowLoop* slow = renderer->slow_loop()) slow->install_slow_result(slow->run_slow_update());
  }
}

TEST_CASE("a late slow result the haptic proxy jumps to adds no damping spike to the display") {
  // 0.3 mm above the slab, not touching it. The haptic proxy may move
  // within its certificate's reach (the widest band at first). The second
  // update runs with the device at rest since the first, so its band is
  // the narrowest (0.5 mm; the face's pairs within it), anchored where the
  // haptic proxy then stood; while it is late, the device swings back and
  // then ahead a little to the side, and the haptic proxy ends more than
  // the narrow reach from that anchor, behind the slow loop's pose: the
  // update installs by jumping there (offer).
  const RenderContext context = slab_context(cube_tool());
  const std::unique_ptr<Renderer> renderer =
      create_god_object(context, ParamSet("/algorithms/0/params"));
  SlowLoop* slow = renderer->slow_loop();
  REQUIRE(slow != nullptr);
  const double height = 3e-4 + 0.5 * kCube;
  DeviceSample device;
  device.pose = at(Vec3(0, 0, height));
  renderer->reset(device.pose);
  int tick = 0;
  const auto step_to = [&](const Vec3& offset_m) {
    device.tick = tick++;
    device.pose = at(Vec3(0, 0, height) + offset_m);
    return renderer->step(device);
  };
  step_to(Vec3(0.015, 0, 0));  // to the first certificate's edge
  slow->install_slow_result(slow->run_slow_update());
  step_to(Vec3(0.015, 0, 0));  // installs it, moves to its edge
  std::unique_ptr<SlowLoop::Result> late = slow->run_slow_update();
  step_to(Vec3(-0.015, 0, 0));
  const TickResult before = step_to(Vec3(0.015, 0.002, 0));
  slow->install_slow_result(std::move(late));
  const TickResult jumped = step_to(Vec3(0.015, 0.002, 0));
  const double jump_m = (jumped.proxy.p - before.proxy.p).norm();
  INFO("jump " << jump_m << " m, proxy " << jumped.proxy.p.transpose());
  REQUIRE(jump_m > 5e-4);
  // The proxy stands still at the slow loop's pose this tick, and the
  // device too: the display is the coupling spring alone (a velocity from
  // the jump would add b_t × jump / dt, 5 N·s/m × 0.9 m/s here).
  const Vec3 spring = context.coupling.k_t * (jumped.proxy.p - device.pose.p);
  CHECK((jumped.display.force - spring).norm() < 1e-9);
  CHECK(jumped.display.torque.norm() < 1e-9);
}

TEST_CASE("a move's collision check on the pairs that may touch finds what all listed pairs give") {
  // A 10 cm box over 8 × 8 tiles 0.2 mm apart (nearly parallel edges,
  // hundreds of pairs tied when resting), turning up to 0.3 rad about the
  // vertical while it tilts, descends, slides and presses: at each anchor a
  // certificate, then moves from starts away from the anchor (as the
  // update's later moves start), some of them turns in place and some into
  // the tiles. The check on the pairs pairs_within_move keeps must find
  // the same first contact, at the same time, as the check on every pair.
  RenderContext context;
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 8; ++j) {
      const double first = -3.5 * 0.0102;
      SceneObject tile = test::box_object(
          Vec3(0.01, 0.01, 0.01),
          Pose{Vec3(first + 0.0102 * i, first + 0.0102 * j, -0.005), Quat::Identity()});
      tile.mesh = shape_mesh(*tile.shape);
      context.scene.push_back(tile);
    }
  }
  context.coupling = test::example_gains();
  context.tool = test::meshed_box_tool(Vec3(0.1, 0.1, 0.02));
  GodObjectSettings settings;
  GodObjectSolver solver(context, settings);
  const MeshCcd& ccd = solver.geometry().ccd();
  const ProximityCertifier certifier(ccd, settings, context.tool.mass.centre_of_mass);
  ProximityCertifier::QueryWorkspace queries;
  const double radius = ccd.tool_radius();
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::size_t listed = 0, kept = 0;
  int moves = 0, contacts = 0;
  for (int k = 0; k <= 60; ++k) {
    const double t = k / 60.0;
    const Quat turn(Eigen::AngleAxisd(0.3 * t, Vec3::UnitZ()) *
                    Eigen::AngleAxisd(0.003 * std::sin(15 * t), Vec3::UnitX()));
    const Pose tool_anchor =
        at(Vec3(0.008 * t, 0.004 * t, 0.0108 - 0.0008 * std::min(1.0, 2 * t)), turn);
    const ProximityCertificate certificate =
        certifier.certify(queries, tool_anchor, k % 2 ? settings.haptic_band_m : 0.002);
    const double reach = certifier.reach(certificate);
    REQUIRE(reach > 0);
    for (int m = 0; m < 8; ++m) {
      // A start away from the anchor, then a move: a turn about the
      // vertical, a tilt, a push down and aside; to the reach's end, to half
      // of it, or (half the moves, as an update's moves mostly are) a
      // twentieth of it.
      const bool small = m % 2 == 1;
      const double scale = small ? 0.02 : 0.2;
      Vec6 offset;
      offset << scale * reach * Vec3(unit(random), unit(random), unit(random)),
          scale * reach / radius * Vec3(unit(random), unit(random), unit(random));
      const Pose start = displaced(certificate.anchor, offset);
      Vec6 move;
      move << Vec3(unit(random), unit(random), -std::abs(unit(random))),
          Vec3(0.1 * unit(random), 0.1 * unit(random), unit(random));
      const double length = point_reach(move, radius);
      move *= m == 0  ? fraction_within_reach(certificate.anchor, start, move, radius, reach)
              : small ? 0.05 * reach / length
                      : 0.5 * reach / length;
      const ScrewMotion motion(start, displaced(start, move));
      const std::span<const ContactFeatures> near =
          pairs_within_move(certificate, start, move, radius);
      const MeshCcdResult all = ccd.first_contact_among(motion, certificate.pairs, settings.ccd);
      const MeshCcdResult some = ccd.first_contact_among(motion, near, settings.ccd);
      INFO("anchor " << k << ", move " << m << ": " << near.size() << " of "
                     << certificate.pairs.size() << " pairs kept");
      REQUIRE(some.contact == all.contact);
      REQUIRE(some.toi == all.toi);
      REQUIRE(some.contacts.size() == all.contacts.size());
      for (std::size_t c = 0; c < all.contacts.size(); ++c)
        REQUIRE(some.contacts[c].features == all.contacts[c].features);
      // A prefix of the list: what it leaves out starts beyond the reach.
      CHECK(near.data() == certificate.pairs.data());
      if (small) {
        listed += certificate.pairs.size();
        kept += near.size();
      }
      ++moves;
      contacts += all.contact;
    }
  }
  // Hard cases were met (contacts on the move), and the small moves left
  // out over 40 % of the pairs.
  INFO(contacts << " of " << moves << " moves met a pair; on the small moves " << kept << " of "
                << listed << " pairs checked");
  CHECK(contacts * 4 > moves);
  CHECK(kept * 10 < listed * 6);
}

TEST_CASE("god-object settings are read with their field names") {
  ParamSet params("/algorithms/0/params");
  params.set("standoff", 1e-3);
  params.set("contact_distance", 1e-4);
  CHECK_THROWS_WITH(read_god_object_settings(params, false),
                    Catch::Contains("/algorithms/0/params/contact_distance"));
  ParamSet negative("/algorithms/0/params");
  negative.set("max_iterations", 0.0);
  CHECK_THROWS_WITH(read_god_object_settings(negative, false),
                    Catch::Contains("/algorithms/0/params/max_iterations"));
  // max_iterations is checked after the contact distances, before the rest.
  negative.set("haptic_band", 1e-6);
  CHECK_THROWS_WITH(read_god_object_settings(negative, false),
                    Catch::Contains("/algorithms/0/params/max_iterations"));
  negative.set("contact_distance", 1e-6);
  CHECK_THROWS_WITH(read_god_object_settings(negative, false),
                    Catch::Contains("/algorithms/0/params/contact_distance"));
  ParamSet bands("/algorithms/0/params");
  bands.set("haptic_band", 2e-3);
  bands.set("haptic_band_min", 1e-3);
  const GodObjectSettings read = read_god_object_settings(bands, false);
  CHECK(read.haptic_band_m == 2e-3);
  CHECK(read.haptic_band_min_m == 1e-3);
  bands.set("haptic_band_min", 3e-3);  // above haptic_band
  CHECK_THROWS_WITH(read_god_object_settings(bands, false),
                    Catch::Contains("/algorithms/0/params/haptic_band_min"));
}

}  // namespace
}  // namespace hb
