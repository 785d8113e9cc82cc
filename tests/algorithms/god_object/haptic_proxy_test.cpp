// The god-object's haptic-rate solve: in free space the proxy is the
// device's pose at every tick; it never leaves its certificate's reach;
// random device motions with certificates refreshed every few ticks never
// carry a cube vertex below the face; a press ends resting at the standoff.
#include "algorithms/god_object/haptic_proxy.h"

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <utility>

#include "hapticbench/mass_properties.h"
#include "hapticbench/shapes.h"
#include "tests/support/proxy_fixtures.h"
#include "tests/support/shape_fixtures.h"

namespace hb {
namespace {

using test::at;

constexpr double kCubeEdge = 0.04;  // cube tool edge (m)

// A 0.4 × 0.4 m slab `thickness` thick whose top face is the plane z = 0,
// with the example coupling; the tool is the caller's.
RenderContext slab_context(double thickness) {
  RenderContext context;
  SceneObject slab = test::box_object(Vec3(0.4, 0.4, thickness),
                                      Pose{Vec3(0, 0, -thickness / 2), Quat::Identity()});
  slab.mesh = shape_mesh(*slab.shape);
  context.scene.push_back(slab);
  context.coupling = test::example_gains();
  return context;
}

// A haptic proxy over a scene, with the solver that owns the CCD structures
// it uses.
struct ProxyRig {
  RenderContext context;
  GodObjectSettings settings;
  GodObjectSolver solver;
  HapticProxy proxy;
  ProximityCertifier::QueryWorkspace queries;  ///< the slow loop's, as the renderer's

  explicit ProxyRig(RenderContext scene, const GodObjectSettings& chosen = {})
      : context(std::move(scene)),
        settings(chosen),
        solver(context, settings),
        proxy(solver.geometry().ccd(), context.coupling, settings,
              context.tool.mass.centre_of_mass) {}

  /// The proximity query at the tool-frame pose, as the slow loop makes it.
  ProximityCertificate certify(const Pose& tool_pose, double band_m) {
    return proxy.certify(queries, tool_pose, band_m);
  }
  void reset(const Pose& start) { proxy.reset(start, queries); }

  /// m, world: the tool mesh's lowest vertex at the proxy pose.
  double lowest_vertex_z() const {
    double lowest = 1e300;
    for (const Vec3& vertex : context.tool.mesh.vertices)
      lowest = std::min(lowest, proxy.pose().transform_point(vertex).z());
    return lowest;
  }
};

struct CubeOnSlab : ProxyRig {
  CubeOnSlab() : ProxyRig(make_context()) {}

  // A 4 cm cube over a 2 cm slab.
  static RenderContext make_context() {
    RenderContext context = slab_context(0.02);
    context.tool = test::box_tool(Vec3::Constant(kCubeEdge));
    context.tool.mesh = shape_mesh(*context.tool.shape);
    return context;
  }
};

TEST_CASE("in free space the proxy is the device's pose until it would leave the certificate") {
  CubeOnSlab rig;
  // 8 cm above the face: nothing within the band, nor within ten widest
  // bands, how far a search measures the scene in free space.
  rig.reset(at(Vec3(0, 0, 0.1)));
  CHECK(rig.proxy.certificate().pairs.empty());
  CHECK(rig.proxy.certificate().clearance_m == kFreeSpaceReachBands * rig.settings.haptic_band_m);
  // 3 cm above it: the clearance is that distance, the reach all but the
  // standoff of it.
  rig.reset(at(Vec3(0, 0, 0.05)));
  CHECK(rig.proxy.certificate().pairs.empty());
  CHECK(rig.proxy.certificate().clearance_m == Approx(0.03).epsilon(1e-12));
  const double reach = rig.proxy.certificate().clearance_m - rig.settings.standoff_m;
  for (int tick = 1; tick <= 80; ++tick) {
    // 0.5 mm per tick sideways, with a slow turn; no new certificate.
    const Pose target =
        at(Vec3(5e-4 * tick, 0, 0.05), quat_from_rotation_vector(Vec3(0, 0, 1e-3 * tick)));
    const HapticSolveStats stats = rig.proxy.step(target);
    const double moved = point_reach(
        displacement(rig.proxy.certificate().anchor, Pose{rig.proxy.pose().p, rig.proxy.pose().q}),
        rig.solver.geometry().ccd().tool_radius());
    INFO("tick " << tick);
    CHECK(moved <= reach * (1 + 1e-9));
    if (!stats.bounded) {
      CHECK((rig.proxy.pose().p - target.p).norm() < 1e-12);
      CHECK(rig.proxy.pose().q.angularDistance(target.q) < 1e-12);
    }
    if (tick <= 50) CHECK_FALSE(stats.bounded);  // 25 mm + 0.05 rad · 3.5 cm < 30 mm
    if (tick >= 60) CHECK(stats.bounded);
  }
  // A new certificate at the proxy lets it move on at once.
  const Pose target = at(rig.proxy.pose().p + Vec3(0.002, 0, 0), rig.proxy.pose().q);
  CHECK(rig.proxy.offer(rig.certify(rig.proxy.pose(), rig.settings.haptic_band_m), rig.proxy.pose(),
                        target));
  rig.proxy.step(target);
  CHECK((rig.proxy.pose().p - target.p).norm() < 1e-12);
}

TEST_CASE("random device motions at the haptic rate never carry a cube vertex below the face") {
  CubeOnSlab rig;
  rig.reset(at(Vec3(0, 0, 0.05)));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> offset(-0.001, 0.001);
  std::uniform_real_distribution<double> angle(-0.02, 0.02);
  Pose target = at(Vec3(0, 0, 0.05));
  int contact_ticks = 0;
  for (int tick = 0; tick < 3000; ++tick) {
    // A random walk that keeps returning toward (and below) the face.
    target.p += Vec3(offset(rng), offset(rng), offset(rng) - 0.0004);
    target.p.z() = std::clamp(target.p.z(), 0.0, 0.06);
    target.p.x() = std::clamp(target.p.x(), -0.1, 0.1);
    target.p.y() = std::clamp(target.p.y(), -0.1, 0.1);
    target.q = (quat_from_rotation_vector(Vec3(angle(rng), angle(rng), angle(rng))) * target.q)
                   .normalized();
    if (tick % 10 == 0)  // a slow loop at 100 Hz
      rig.proxy.offer(rig.certify(rig.proxy.pose(), rig.settings.haptic_band_m), rig.proxy.pose(),
                      target);
    rig.proxy.step(target);
    INFO("tick " << tick);
    REQUIRE(rig.lowest_vertex_z() >= 0.0);
    if (!rig.proxy.contacts().empty()) ++contact_ticks;
  }
  CHECK(contact_ticks > 500);  // the walk did press on the face
}

// An L-shaped hook (a 1 × 2 × 11 cm stem, a 7 cm arm at its top) whose tool
// frame is the middle of the arm tip's lower edge, over a 40 × 40 × 4 cm
// slab whose top face is z = 0, the stem hanging 2 cm beside it.
struct HookOnSlab : ProxyRig {
  HookOnSlab() : ProxyRig(make_context()) {}

  static RenderContext make_context() {
    RenderContext context = slab_context(0.04);
    context.tool.mesh = test::hook_mesh();
    context.tool.mass = mass_properties_from_density(context.tool.mesh, 1000);
    return context;
  }

  // The lowest tool vertex over the slab (|x|, |y| ≤ 0.2), m above its top.
  double lowest_vertex_over_slab() const {
    double lowest = 1e300;
    for (const Vec3& vertex : context.tool.mesh.vertices) {
      const Vec3 p = proxy.pose().transform_point(vertex);
      if (std::abs(p.x()) <= 0.2 && std::abs(p.y()) <= 0.2) lowest = std::min(lowest, p.z());
    }
    return lowest;
  }
};

TEST_CASE("a hook turned about its tip never sinks below the standoff, at 2, 4 and 8 rad/s") {
  // The tip presses on the top face 5 cm in from the edge; the device then
  // turns about the horizontal axis through the tip, lifting the arm: the
  // proxy pivots on the tip, which lies above the centre of mass (r·n > 0),
  // so each rotating tick's second-order motion carries the tip toward the
  // face. Before the haptic proxy measured the pairs after its step, the tip
  // sank through the face at 4 rad/s.
  for (double rate : {2.0, 4.0, 8.0}) {
    HookOnSlab rig;
    REQUIRE(rig.context.tool.mass.centre_of_mass.z() < -0.01);  // the contact lies above it
    const Vec3 tip(-0.15, 0, 0);
    rig.reset(at(tip + Vec3(0, 0, 0.005)));
    double least_pair = 1e300, least_vertex = 1e300;
    int turning_contact_ticks = 0;
    for (int tick = 0; tick < 1500; ++tick) {
      // Down to 2 mm past the face in 0.2 s, then turning for 1.3 s.
      const double t = 1e-3 * tick;
      Pose target = at(tip + Vec3(0, 0, std::max(-0.002, 0.005 - 0.035 * t)));
      if (t > 0.2) target.q = quat_from_rotation_vector(Vec3(0, rate * (t - 0.2), 0));
      if (tick % 10 == 0)  // a slow loop at 100 Hz
        rig.proxy.offer(rig.certify(rig.proxy.pose(), rig.settings.haptic_band_m), rig.proxy.pose(),
                        target);
      rig.proxy.step(target);
      least_pair = std::min(least_pair, rig.proxy.least_listed_distance());
      least_vertex = std::min(least_vertex, rig.lowest_vertex_over_slab());
      if (t > 0.2 && !rig.proxy.contacts().empty()) ++turning_contact_ticks;
    }
    INFO(rate << " rad/s: least listed pair " << least_pair << " m, least vertex height "
              << least_vertex << " m");
    CHECK(turning_contact_ticks > 200);  // it did pivot on the face
    CHECK(least_pair >= rig.settings.standoff_m - 1e-6);
    CHECK(least_vertex >= rig.settings.standoff_m - 1e-6);
  }
}

TEST_CASE(
    "a cube's edge swept over the slab's edge keeps the standoff as the edges turn parallel") {
  // A 4 cm cube turned 45° about y, so that its lowest edge is a ridge along
  // y, pressed 1 mm (in intent) onto the slab right over the slab's edge
  // x = 0.2 m, then yawed about the vertical through its centre: the ridge
  // sweeps across the slab's edge and lies parallel to it at yaw 0, where
  // an edge pair's closest points slide along the edges by far more than
  // the rotation moves any point. Every point of every cube edge (sampled
  // every 0.1 mm) stays outside the slab by the standoff, at every tick.
  for (double rate : {0.5, 2.0}) {
    CubeOnSlab rig;
    const Vec3 slab_centre(0, 0, -0.01), slab_half(0.2, 0.2, 0.01);
    const double ridge_below_centre = kCubeEdge / std::sqrt(2.0);
    const Quat roll = quat_from_rotation_vector(Vec3(0, M_PI / 4, 0));
    const Vec3 centre(0.2, 0, ridge_below_centre);
    auto pose_at = [&](double yaw, double depth) {
      return at(centre - Vec3(0, 0, depth), quat_from_rotation_vector(Vec3(0, 0, yaw)) * roll);
    };
    rig.reset(pose_at(0.3, -0.003));
    double least = 1e300;
    for (int tick = 0; tick < 1200; ++tick) {
      const double t = 1e-3 * tick;
      const double depth = std::min(0.001, -0.003 + 0.04 * t);
      const double yaw = t < 0.2 ? 0.3 : 0.3 - rate * (t - 0.2);
      const Pose target = pose_at(yaw, depth);
      if (tick % 10 == 0)
        rig.proxy.offer(rig.certify(rig.proxy.pose(), rig.settings.haptic_band_m), rig.proxy.pose(),
                        target);
      rig.proxy.step(target);
      least = std::min(least, test::least_edge_distance_to_box(
                                  rig.context.tool.mesh, rig.proxy.pose(), slab_centre, slab_half));
    }
    INFO(rate << " rad/s: least distance of a cube edge to the slab " << least << " m");
    CHECK(least >= rig.settings.standoff_m - 1e-6);
    CHECK(least < 1e-4);  // it did press on the slab
  }
}

TEST_CASE("a tick starts from the last tick's check: each solved pair is measured once a tick") {
  // A tick evaluates the pairs it solves once, at the end pose it checks,
  // and starts from the last tick's check; only a pair it has not measured
  // (the first tick, a pair a new certificate adds) is also measured at its
  // start. Pairs that cannot matter within the tick are not measured.
  CubeOnSlab rig;
  rig.reset(at(Vec3(0, 0, 0.021)));
  const Pose target = at(Vec3(0.002, 0.001, 0.018));  // 3 mm deep, sideways
  rig.proxy.offer(rig.certify(rig.proxy.pose(), rig.settings.haptic_band_m), rig.proxy.pose(),
                  target);
  const auto pairs = static_cast<int64_t>(rig.proxy.certificate().pairs.size());
  REQUIRE(pairs >= 4);
  const HapticSolveStats first = rig.proxy.step(target);
  if (first.widened == 0)
    CHECK(first.pairs_evaluated == first.pairs_solved * (2 + first.corrections));
  for (int tick = 0; tick < 20; ++tick) {
    const HapticSolveStats next = rig.proxy.step(target);
    INFO("tick " << tick << ", corrections " << next.corrections << ", cut " << next.cut
                 << ", solved " << next.pairs_solved << " of " << pairs);
    if (!next.cut && next.widened == 0)
      CHECK(next.pairs_evaluated == next.pairs_solved * (1 + next.corrections));
  }
  // A certificate found where the proxy is lists the same pairs: all
  // carried. Resting on the face 2.4 mm from the last anchor, every pair
  // could matter; at this one only the bottom's can.
  rig.proxy.offer(rig.certify(rig.proxy.pose(), rig.settings.haptic_band_m), rig.proxy.pose(),
                  target);
  REQUIRE(static_cast<int64_t>(rig.proxy.certificate().pairs.size()) == pairs);
  const HapticSolveStats after_offer = rig.proxy.step(target);
  const int64_t solved = after_offer.pairs_solved;
  CHECK(solved >= 4);
  CHECK(solved < pairs);
  CHECK(after_offer.widened == 0);  // at rest: the step stays within the allowance
  CHECK(after_offer.pairs_evaluated == solved * (1 + after_offer.corrections));
  // A band wider than the cube adds its top features, out of reach of the
  // tick: not measured at all.
  rig.proxy.offer(rig.certify(rig.proxy.pose(), 10 * rig.settings.haptic_band_m), rig.proxy.pose(),
                  target);
  REQUIRE(static_cast<int64_t>(rig.proxy.certificate().pairs.size()) > pairs);
  const HapticSolveStats widened = rig.proxy.step(target);
  CHECK(widened.pairs_solved == solved);
  CHECK(widened.pairs_evaluated == solved * (1 + widened.corrections));
  CHECK(rig.lowest_vertex_z() >= 0.0);  // resting on the face, never below it
}

// A floor of n × n separate 1 cm tiles at `pitch` (m; 1 cm: touching),
// centred on the origin, top faces at z = 0, under a box tool of `tool` (m).
RenderContext tiled_floor_context(int n, double pitch, const Vec3& tool) {
  RenderContext context;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double first = -0.5 * (n - 1) * pitch;
      SceneObject tile = test::box_object(
          Vec3(0.01, 0.01, 0.01),
          Pose{Vec3(first + pitch * i, first + pitch * j, -0.005), Quat::Identity()});
      tile.mesh = shape_mesh(*tile.shape);
      context.scene.push_back(tile);
    }
  }
  context.coupling = test::example_gains();
  context.tool = test::box_tool(tool);
  context.tool.mesh = shape_mesh(*context.tool.shape);
  return context;
}

TEST_CASE("a box face slides over the seams of a tiled floor without catching on them") {
  // With its default pair limit the certificate must not lose its reach on
  // a crowded contact: were the limit's pair (the nearest one left out) at
  // the standoff, the proxy could not move and the coupling would stretch.
  // 6 × 6 tiles 0.2 mm apart under a 3 cm box.
  ProxyRig rig(tiled_floor_context(6, 0.0102, Vec3(0.03, 0.03, 0.02)));
  rig.reset(at(Vec3(-0.005, -0.005, 0.0105)));
  for (int tick = 0; tick <= 600; ++tick) {
    // Pressed 1 mm, then slid 1 cm along x over 500 ms.
    const double x = -0.005 + 0.01 * std::clamp((tick - 100) / 500.0, 0.0, 1.0);
    const Pose target = at(Vec3(x, -0.005, 0.0095));
    rig.proxy.offer(rig.certify(rig.proxy.pose(), rig.settings.haptic_band_m), rig.proxy.pose(),
                    target);
    rig.proxy.step(target);
  }
  INFO("listed pairs " << rig.proxy.certificate().pairs.size() << ", clearance "
                       << rig.proxy.certificate().clearance_m);
  CHECK(rig.proxy.pose().p.x() == Approx(0.005).margin(1e-4));  // followed the device
  CHECK(rig.lowest_vertex_z() >= 0.0);                          // on the floor, never in it
  CHECK(rig.lowest_vertex_z() <= rig.settings.contact_distance_m);
}

TEST_CASE("a 10 cm box face resting on 121 touching tiles slides with the device") {
  // box_rest_144_tiles: up to 1,836 pairs lie within the band; with 256
  // listed the certificate had no reach left and the proxy stayed put
  // while the device slid 5 mm (a 9 N pull on a frictionless floor).
  ProxyRig rig(tiled_floor_context(12, 0.01, Vec3(0.1, 0.1, 0.02)));
  rig.reset(at(Vec3(0, 0, 0.0105)));
  const Vec3 slide = Vec3(1, 0.5, 0).normalized() * 0.005;
  for (int tick = 0; tick <= 250; ++tick) {
    // Pressed 1 mm, then slid 5 mm over 200 ms.
    const double along = std::clamp((tick - 50) / 200.0, 0.0, 1.0);
    const Pose target = at(Vec3(0, 0, 0.0095) + along * slide);
    rig.proxy.offer(rig.certify(rig.proxy.pose(), rig.settings.haptic_band_m), rig.proxy.pose(),
                    target);
    rig.proxy.step(target);
  }
  INFO("listed pairs " << rig.proxy.certificate().pairs.size() << ", clearance "
                       << rig.proxy.certificate().clearance_m);
  CHECK(rig.proxy.certificate().pairs.size() > 256);
  CHECK((rig.proxy.pose().p.head<2>() - slide.head<2>()).norm() <= 1e-4);  // followed the device
  CHECK(rig.lowest_vertex_z() >= 0.0);  // on the floor, never in it
  CHECK(rig.lowest_vertex_z() <= rig.settings.contact_distance_m);
}

TEST_CASE("a tick solving only the pairs that can matter moves as one solving every pair") {
  // A 3 cm box over 6 × 6 tiles 0.2 mm apart (nearly parallel edges, ties
  // at one distance), pressed 1 mm in intent, then slid and turned about
  // the vertical at up to 3 rad/s with a tilt and a jitter, certificates
  // every 4 ticks: the same proxy, tick by tick, as with every listed pair
  // solved and checked, never below the standoff's slack, with a fraction
  // of the pairs measured.
  GodObjectSettings all_pairs;
  all_pairs.haptic_all_pairs = true;
  ProxyRig culled(tiled_floor_context(6, 0.0102, Vec3(0.03, 0.03, 0.02)));
  ProxyRig every(tiled_floor_context(6, 0.0102, Vec3(0.03, 0.03, 0.02)), all_pairs);
  const Pose start = at(Vec3(-0.005, -0.005, 0.0105));
  culled.reset(start);
  every.reset(start);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> jitter(-2e-5, 2e-5);
  int64_t solved = 0, listed = 0;
  int widened = 0, contact_ticks = 0;
  double worst_position = 0, worst_angle = 0, least = 1e300;
  for (int tick = 0; tick <= 700; ++tick) {
    const double t = 1e-3 * tick;
    const double slide = std::clamp((t - 0.1) / 0.5, 0.0, 1.0);
    const double yaw = 3.0 * std::max(0.0, t - 0.1) * std::min(1.0, std::max(0.0, t - 0.1) / 0.2);
    const Pose target{Vec3(-0.005 + 0.01 * slide, -0.005 + 0.006 * slide, 0.0095) +
                          Vec3(jitter(random), jitter(random), jitter(random)),
                      Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ()) *
                           Eigen::AngleAxisd(0.01 * std::sin(20 * t), Vec3::UnitX()))};
    if (tick % 4 == 0) {
      culled.proxy.offer(culled.certify(culled.proxy.pose(), culled.settings.haptic_band_m),
                         culled.proxy.pose(), target);
      every.proxy.offer(every.certify(every.proxy.pose(), every.settings.haptic_band_m),
                        every.proxy.pose(), target);
    }
    const HapticSolveStats stats = culled.proxy.step(target);
    every.proxy.step(target);
    solved += stats.pairs_solved;
    listed += static_cast<int64_t>(culled.proxy.certificate().pairs.size());
    widened += stats.widened;
    contact_ticks += !culled.proxy.contacts().empty();
    worst_position =
        std::max(worst_position, (culled.proxy.pose().p - every.proxy.pose().p).norm());
    worst_angle =
        std::max(worst_angle, culled.proxy.pose().q.angularDistance(every.proxy.pose().q));
    least = std::min(least, culled.proxy.least_listed_distance());
    REQUIRE(culled.proxy.contacts().size() == every.proxy.contacts().size());
  }
  INFO(solved << " of " << listed << " listed pairs solved, " << widened << " ticks widened, "
              << contact_ticks << " in contact; poses apart by " << worst_position << " m, "
              << worst_angle << " rad; least listed distance " << least << " m");
  CHECK(contact_ticks > 500);
  CHECK(worst_position <= 1e-9);
  CHECK(worst_angle <= 1e-9);
  CHECK(least >= culled.settings.standoff_m - HapticProxy::kStandoffSlackM - 1e-9);
  CHECK(solved * 2 < listed);
}

TEST_CASE("a certificate lists the first 256 pairs unless they crowd the standoff") {
  // The 10 cm box over 12 × 12 tiles: hovering 2 mm above them, over 500
  // pairs lie in the 5 mm band, but the 256 nearest leave a reach of 2 mm,
  // more than the third of the band two slow-loop intervals need; resting
  // on them, the 256 nearest leave none, and more are listed. The query
  // after a crowded one lists the most at once, then the first 256 again.
  ProxyRig rig(tiled_floor_context(12, 0.01, Vec3(0.1, 0.1, 0.02)));
  const double band = rig.settings.haptic_band_m;
  const Pose hover = at(Vec3(0, 0, 0.012)), rest = at(Vec3(0, 0, 0.01 + 0.5e-4));
  const ProximityCertificate before = rig.certify(hover, band);
  CHECK(before.pairs.size() == kFirstListedPairs);
  CHECK(before.clearance_m == Approx(0.002).margin(1e-9));
  CHECK(before.clearance_m - rig.settings.standoff_m >= band / 3);
  const ProximityCertificate resting = rig.certify(rest, band);
  CHECK(resting.pairs.size() > kFirstListedPairs);
  CHECK(resting.clearance_m - rig.settings.standoff_m >= band / 3);
  const ProximityCertificate lifted = rig.certify(hover, band);
  CHECK(lifted.pairs.size() > kFirstListedPairs);  // listed at once, still a certificate
  CHECK(lifted.clearance_m >= before.clearance_m);
  // Which 256 of the tied pairs (every tile vertex 2 mm below the face) is
  // the list's choice; how many and the clearance are not.
  const ProximityCertificate again = rig.certify(hover, band);
  CHECK(again.pairs.size() == before.pairs.size());
  CHECK(again.clearance_m == Approx(before.clearance_m).margin(1e-12));
}

TEST_CASE("a certificate answered from the last search's pairs lists what a new search would") {
  // A 10 cm box turning (0.4 rad over the path) and tilting while it
  // descends onto 0.2 mm-apart tiles, slides and presses: a certificate
  // every 0.1 mm and 2 mrad, each compared with a search of its own at the
  // same pose. The box's edges pass nearly parallel over the tiles' edges,
  // and resting, hundreds of pairs tie at one distance.
  ProxyRig rig(tiled_floor_context(8, 0.0102, Vec3(0.1, 0.1, 0.02)));
  const MeshCcd& ccd = rig.solver.geometry().ccd();
  const auto most = static_cast<std::size_t>(rig.settings.haptic_max_pairs);
  int searches = 0, queries = 0;
  for (int k = 0; k <= 200; ++k) {
    const double t = k / 200.0;
    const Quat turn(Eigen::AngleAxisd(0.4 * t, Vec3::UnitZ()) *
                    Eigen::AngleAxisd(0.002 * std::sin(20 * t), Vec3::UnitX()));
    const Pose pose = at(Vec3(0.01 * t, 0.005 * t, 0.0125 - 0.0025 * std::min(1.0, 2 * t)), turn);
    const double band = k % 3 == 0 ? rig.settings.haptic_band_m : 0.002;
    const ProximityCertificate listed = rig.certify(pose, band);
    searches += listed.searches;
    ++queries;
    const std::size_t limit = listed.pairs.size() > kFirstListedPairs ? most : kFirstListedPairs;
    const ProximityResult searched = ccd.proximity(listed.anchor, band, limit);
    INFO("query " << k << ": " << listed.pairs.size() << " pairs listed, searches "
                  << listed.searches);
    REQUIRE(listed.pairs.size() == searched.pairs.size());
    CHECK(listed.clearance_m == Approx(searched.clearance_m).margin(1e-12));
    // The same pairs, but for ties at the clearance, with the same distances.
    std::vector<std::pair<ContactFeatures, double>> searched_nearer;
    for (const ProximityPair& pair : searched.pairs)
      if (pair.distance < searched.clearance_m - 1e-12)
        searched_nearer.emplace_back(pair.features, pair.distance);
    for (const auto& [features, distance] : searched_nearer) {
      const auto found = std::find(listed.pairs.begin(), listed.pairs.end(), features);
      REQUIRE(found != listed.pairs.end());
      CHECK(listed.distances[static_cast<std::size_t>(found - listed.pairs.begin())] ==
            Approx(distance).margin(1e-12));
    }
    for (std::size_t i = 0; i < listed.pairs.size(); ++i)
      CHECK(listed.distances[i] <= listed.clearance_m + 1e-12);
  }
  // Most certificates came from earlier pairs, or this compared searches.
  INFO(searches << " searches for " << queries << " certificates");
  CHECK(searches * 4 < queries);
  // A jump past what the last search looked at takes a new one.
  CHECK(rig.certify(at(Vec3(0.03, 0, 0.02)), rig.settings.haptic_band_m).searches >= 1);
}

TEST_CASE("a cube pressed into the face rests on it at the standoff") {
  CubeOnSlab rig;
  rig.reset(at(Vec3(0, 0, 0.021)));               // 1 mm above the face
  const Pose target = at(Vec3(0.001, 0, 0.016));  // 4 mm deep
  for (int tick = 0; tick < 50; ++tick) {
    if (tick % 5 == 0)
      rig.proxy.offer(rig.certify(rig.proxy.pose(), rig.settings.haptic_band_m), rig.proxy.pose(),
                      target);
    rig.proxy.step(target);
  }
  CHECK(rig.lowest_vertex_z() >= 0.0);
  CHECK(rig.lowest_vertex_z() <= rig.settings.contact_distance_m);
  CHECK(rig.proxy.pose().p.x() == Approx(0.001).margin(1e-9));  // free along the face
  REQUIRE(rig.proxy.contacts().size() >= 3);
  for (const Contact& contact : rig.proxy.contacts()) CHECK(contact.normal.z() > 0.999);
}

TEST_CASE(
    "with friction the proxy sticks until the coupling's pull exceeds mu F_n, then trails "
    "by mu times the depth") {
  const double mu = 0.4, depth = 0.003;
  CubeOnSlab rig;
  HapticProxy proxy(rig.solver.geometry().ccd(), rig.context.coupling, rig.settings,
                    rig.context.tool.mass.centre_of_mass, {mu});
  ProximityCertifier::QueryWorkspace queries;
  proxy.reset(at(Vec3(0, 0, 0.021)), queries);
  auto step_to = [&](const Pose& target, int tick) {
    if (tick % 5 == 0)
      proxy.offer(proxy.certify(queries, proxy.pose(), 0.004), proxy.pose(), target);
    proxy.step(target);
  };
  for (int tick = 0; tick < 50; ++tick) step_to(at(Vec3(0, 0, 0.02 - depth)), tick);
  const double rest_z = proxy.pose().p.z();
  const double pressed = rest_z - (0.02 - depth);  // the coupling's stretch along the normal
  for (int tick = 1; tick <= 400; ++tick) {
    const double x = 5e-5 * tick;  // 20 mm in 400 ticks
    step_to(at(Vec3(x, 0, 0.02 - depth)), tick);
    INFO("tick " << tick);
    if (x < 0.99 * mu * pressed)
      CHECK(proxy.pose().p.x() == Approx(0).margin(1e-8));  // stuck
    else if (x > 1.01 * mu * pressed)
      CHECK(x - proxy.pose().p.x() == Approx(mu * pressed).epsilon(1e-4));  // sliding at mu F_n
    CHECK(proxy.pose().p.z() == Approx(rest_z).margin(1e-9));
  }
}

TEST_CASE("the band follows the device's speed between slow updates, within its limits") {
  CubeOnSlab rig;
  const Pose still = at(Vec3(0, 0, 0.1));
  CHECK(rig.proxy.band_for(still, still) == rig.settings.haptic_band_min_m);
  CHECK(rig.proxy.band_for(still, at(Vec3(2e-4, 0, 0.1))) == Approx(1.2e-3));  // 6 × 0.2 mm
  CHECK(rig.proxy.band_for(still, at(Vec3(0.01, 0, 0.1))) == rig.settings.haptic_band_m);
  // A turn counts by how far it moves the cube's corners: 0.01 rad × 3.46 cm.
  const double corner = std::sqrt(3.0) * kCubeEdge / 2;
  CHECK(
      rig.proxy.band_for(still, at(Vec3(0, 0, 0.1), quat_from_rotation_vector(Vec3(0, 0, 0.01)))) ==
      Approx(6 * 0.01 * corner).epsilon(1e-6));
}

}  // namespace
}  // namespace hb
