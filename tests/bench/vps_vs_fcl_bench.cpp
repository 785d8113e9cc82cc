// One contact query per pose, Voxmap PointShell against FCL 0.7, on the
// same poses: the tool and scene of scenarios/meshes/armadillo_on_bunny.json
// (a 5 cm armadillo, 3.305e-4 m per file unit, against bunny00 scaled to
// 30 cm), posed by that scenario's device trace (human_like, seed 3, 2 s at
// 1 kHz, loaded with the scenario), keeping the ticks whose tool is in
// contact with the bunny or within kNearDistance of it (FCL's distance).
//
// Voxmap PointShell query (what the renderer's tick does at one pose,
// without the proxy integration): the pointshell (0.5 mm spacing) posed by
// the device pose with the device's twist, looked up in the scene voxmap
// (0.5 mm voxels, voxmap variant, default gains), the wrench with the
// Jacobians the default implicit Euler integrator asks for, and the contacts
// reported. Structures are built as the renderer builds them for this
// scenario (same region, same tree; cached on disk) before timing.
//
// FCL query: fcl::collide of BVHModel<OBBRSSd> meshes (built once) with
// enable_contact and up to kFclMaxContacts contacts.
//
// Time: per method, the median and 99th percentile over the poses of the
// per-pose median of a few runs, and the ratio of the medians; besides
// Google Benchmark's mean per pose. Contact agreement: a pose is in contact
// for Voxmap PointShell when a point has depth > 0, for FCL when collide
// reports a contact. Run:
//   build/tests/bench/vps_vs_fcl_bench
#include <benchmark/benchmark.h>
#include <fcl/fcl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/voxmap_pointshell/pointshell_contacts.h"
#include "algorithms/voxmap_pointshell/voxmap.h"
#include "hapticbench/cache_directory.h"
#include "hapticbench/disk_cache.h"
#include "hapticbench/proxy/rigid_body.h"
#include "harness/scenario/scenario.h"
#include "tests/bench/bench_models.h"
#include "tests/bench/fcl_models.h"

namespace hb {
namespace {

constexpr double kVoxelSize = 0.0005;    // m, scene voxels and pointshell spacing
constexpr double kNearDistance = 0.003;  // m, poses kept when this close or in contact
constexpr std::size_t kFclMaxContacts = 100000;
constexpr int kVpsRuns = 5;  // runs per pose, median kept
constexpr int kFclRuns = 3;
constexpr std::size_t kMinimumPoses = 200;
// As the renderer (voxmap_pointshell.cpp): the reach box grows by a tenth
// of the tool's radius besides the band.
constexpr double kReachMarginPerToolRadius = 0.1;

using bench::fcl_model;
using bench::FclModel;

/// A device sample as the proxy state the lookup reads: centre of mass
/// (world, m), orientation, its velocity (m/s) and ω (rad/s).
RigidBodyState state_of(const DeviceSample& sample, const Vec3& centre_of_mass) {
  RigidBodyState state;
  state.q = sample.pose.q.normalized();
  const Vec3 lever = state.q * centre_of_mass;
  state.x = sample.pose.p + lever;
  state.v = sample.twist.v + sample.twist.w.cross(lever);
  state.w = sample.twist.w;
  return state;
}

/// One pose's answers of both methods.
struct PoseResult {
  double fcl_distance = 0;  // m, 0 in contact
  bool vps_contact = false, fcl_contact = false;
  std::size_t vps_contacts = 0, vps_braking = 0, fcl_contacts = 0;
  int64_t vps_points_tested = 0;    // points looked up by one query
  int64_t vps_spheres_tested = 0;   // tree nodes tested by one query
  double vps_depth = 0;             // m, deepest point
  double fcl_depth = 0;             // m, FCL's largest penetration_depth
  double vps_seconds = 0;           // from the root
  double vps_coherent_seconds = 0;  // from the previous pose's front
  double fcl_seconds = 0;
  int64_t vps_coherent_spheres = 0;  // tree nodes tested from the front
};

struct Setup {
  Scenario scenario;
  std::size_t scene_triangles = 0, tool_triangles = 0;
  // Voxmap PointShell
  PointShell shell;
  SceneVoxmap voxmap;
  PointShellGains gains;
  PointShellHits hits;
  PointShellFront front;
  std::vector<Contact> contacts;
  WorkCounters work;
  // FCL
  std::shared_ptr<FclModel> fcl_tool, fcl_scene;
  // The poses kept and what they gave.
  std::vector<DeviceSample> poses;
  std::vector<PoseResult> results;

  /// The Voxmap PointShell query at one pose, searching the tree from the
  /// root or (coherent) from the front the last query left; returns the
  /// net force's norm (N).
  double vps_query(const DeviceSample& sample, bool coherent) {
    const RigidBodyState state = state_of(sample, scenario.context.tool.mass.centre_of_mass);
    if (coherent) {
      find_pointshell_hits_coherent(shell, voxmap.lookup, gains, state, 0, front, hits, work);
    } else {
      find_pointshell_hits(shell, voxmap.lookup, gains, state, hits, work);
    }
    const ForceEvaluation evaluation = pointshell_wrench(shell, hits, gains, state, true);
    contacts.clear();
    report_contacts(shell, hits, voxmap.lookup, gains, state, contacts);
    return evaluation.wrench.force.norm();
  }

  /// The FCL query at one pose.
  void fcl_query(const DeviceSample& sample, fcl::CollisionResultd& result) const {
    fcl::CollisionRequestd request(kFclMaxContacts, true);
    result.clear();
    fcl::collide(fcl_tool.get(), bench::fcl_transform(sample.pose), fcl_scene.get(),
                 fcl::Transform3d::Identity(), request, result);
  }

  double fcl_distance(const DeviceSample& sample) const {
    fcl::DistanceRequestd request;
    fcl::DistanceResultd result;
    return fcl::distance(fcl_tool.get(), bench::fcl_transform(sample.pose), fcl_scene.get(),
                         fcl::Transform3d::Identity(), request, result);
  }
};

// The box the renderer is given (scenario_runner.cpp): the trace's
// positions grown by the tool's radius about its frame origin.
Eigen::AlignedBox3d reach_of(const Scenario& scenario) {
  Eigen::AlignedBox3d reach;
  scenario.trajectory.for_each(
      [&reach](const DeviceSample& sample) { reach.extend(sample.pose.p); });
  const double radius = scenario.context.tool.mesh.radius_about(Vec3::Zero());
  reach.min().array() -= radius;
  reach.max().array() += radius;
  return reach;
}

Setup make_setup() {
  Setup s;
  s.scenario = load_scenario(std::string(HAPTICBENCH_SOURCE_DIR) +
                             "/scenarios/meshes/armadillo_on_bunny.json");
  const RenderContext& context = s.scenario.context;
  if (context.scene.size() != 1) {
    std::fprintf(stderr, "armadillo_on_bunny.json: expected one scene object\n");
    std::exit(1);
  }
  const SceneObject& bunny = context.scene.front();
  s.scene_triangles = bunny.mesh.triangles.size();
  s.tool_triangles = context.tool.mesh.triangles.size();

  // Voxmap PointShell structures, as the renderer builds them.
  CacheSettings cache;
  if (const std::optional<std::filesystem::path> directory = default_cache_directory()) {
    cache.enabled = true;
    cache.directory = *directory;
  } else {
    cache.enabled = false;
  }
  VoxmapSettings settings;
  settings.voxel_size_m = kVoxelSize;
  settings.signed_distance = true;  // the renderer keeps φ for both variants
  Eigen::AlignedBox3d region = reach_of(s.scenario);
  const double margin = exterior_band_m(settings) + kVoxelSize +
                        kReachMarginPerToolRadius * context.tool.mesh.radius_about(Vec3::Zero());
  region.min().array() -= margin;
  region.max().array() += margin;
  s.voxmap = build_scene_voxmap(context.scene, region, settings, cache);
  const PointShellPoints points = build_pointshell(context.tool.mesh, kVoxelSize, cache);
  s.shell = make_pointshell(points.points, points.normals, context.tool.mass.centre_of_mass);
  s.hits.contacts.reserve(s.shell.points.size());
  s.hits.braking.reserve(s.shell.points.size());
  s.hits.braking_fields.reserve(s.shell.points.size());
  s.contacts.reserve(s.shell.points.size());

  // FCL: the tool in its own frame, the bunny placed in the world.
  s.fcl_tool = fcl_model(context.tool.mesh, Pose{});
  s.fcl_scene = fcl_model(bunny.mesh, bunny.pose);

  for (const DeviceSample& sample : s.scenario.trajectory.all()) {
    fcl::CollisionResultd collision;
    s.fcl_query(sample, collision);
    const double distance = collision.isCollision() ? 0.0 : s.fcl_distance(sample);
    if (distance > kNearDistance) continue;
    s.poses.push_back(sample);
    PoseResult r;
    r.fcl_distance = distance;
    s.results.push_back(r);
  }
  return s;
}

Setup& setup() {
  static Setup s = make_setup();
  return s;
}

double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const std::size_t i = static_cast<std::size_t>(std::ceil(p * static_cast<double>(v.size()))) - 1;
  return v[std::min(i, v.size() - 1)];
}

double median_of_runs(int runs, const std::function<void()>& query) {
  std::vector<double> times;
  for (int r = 0; r < runs; ++r) {
    const auto begin = std::chrono::steady_clock::now();
    query();
    times.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count());
  }
  return median(times);
}

/// Runs both methods on every pose; records times and answers.
void measure_poses() {
  Setup& s = setup();
  fcl::CollisionResultd collision;
  double force_sink = 0;
  for (std::size_t i = 0; i < s.poses.size(); ++i) {
    const DeviceSample& sample = s.poses[i];
    PoseResult& r = s.results[i];
    const int64_t tested_before = s.work.get("points_looked_up");
    const int64_t spheres_before = s.work.get("sphere_tests");
    r.vps_seconds = median_of_runs(kVpsRuns, [&] { force_sink += s.vps_query(sample, false); });
    r.vps_points_tested = (s.work.get("points_looked_up") - tested_before) / kVpsRuns;
    r.vps_spheres_tested = (s.work.get("sphere_tests") - spheres_before) / kVpsRuns;
    r.vps_contacts = s.hits.contacts.size();
    r.vps_braking = s.hits.braking.size();
    r.vps_contact = !s.hits.contacts.empty();
    for (const PointHit& hit : s.hits.contacts) r.vps_depth = std::max(r.vps_depth, hit.depth);
    r.fcl_seconds = median_of_runs(kFclRuns, [&] { s.fcl_query(sample, collision); });
    r.fcl_contacts = collision.numContacts();
    r.fcl_contact = collision.isCollision();
    for (std::size_t c = 0; c < collision.numContacts(); ++c)
      r.fcl_depth = std::max(r.fcl_depth, collision.getContact(c).penetration_depth);
  }
  // From the front: the poses in trace order, each query starting from the
  // previous pose's front (as the renderer's ticks do), a few passes; per
  // pose the median over the passes.
  std::vector<std::vector<double>> coherent(s.poses.size());
  for (int run = 0; run < kVpsRuns; ++run) {
    s.front.clear();
    for (std::size_t i = 0; i < s.poses.size(); ++i) {
      const int64_t spheres_before = s.work.get("sphere_tests");
      const auto begin = std::chrono::steady_clock::now();
      force_sink += s.vps_query(s.poses[i], true);
      coherent[i].push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count());
      if (run == 0) s.results[i].vps_coherent_spheres = s.work.get("sphere_tests") - spheres_before;
    }
  }
  for (std::size_t i = 0; i < s.poses.size(); ++i)
    s.results[i].vps_coherent_seconds = median(coherent[i]);
  benchmark::DoNotOptimize(force_sink);
}

/// What one pass over the poses did.
struct PassTotals {
  int64_t looked_up = 0, spheres = 0, front_entries = 0, contacts = 0, braking = 0;
};

/// The poses in trace order once, each query from the last one's front
/// (kept out of line so that callgrind can count it alone).
[[gnu::noinline]] PassTotals coherent_pass() {
  Setup& s = setup();
  s.front.clear();
  PassTotals totals;
  const int64_t looked_up = s.work.get("points_looked_up");
  const int64_t spheres = s.work.get("sphere_tests");
  const int64_t front_entries = s.work.get("front_entries");
  double force_sink = 0;
  for (const DeviceSample& pose : s.poses) {
    force_sink += s.vps_query(pose, true);
    totals.contacts += static_cast<int64_t>(s.hits.contacts.size());
    totals.braking += static_cast<int64_t>(s.hits.braking.size());
  }
  benchmark::DoNotOptimize(force_sink);
  totals.looked_up = s.work.get("points_looked_up") - looked_up;
  totals.spheres = s.work.get("sphere_tests") - spheres;
  totals.front_entries = s.work.get("front_entries") - front_entries;
  return totals;
}

/// Google Benchmark's view: one pose per iteration, cycling through the
/// poses in order; from the root, or from the last pose's front.
void BM_VoxmapPointShell(benchmark::State& state, bool coherent) {
  Setup& s = setup();
  s.front.clear();
  std::size_t next = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(s.vps_query(s.poses[next], coherent));
    if (++next == s.poses.size()) next = 0;
  }
}

void BM_FclCollide(benchmark::State& state) {
  Setup& s = setup();
  fcl::CollisionResultd collision;
  std::size_t next = 0;
  for (auto _ : state) {
    s.fcl_query(s.poses[next], collision);
    benchmark::DoNotOptimize(collision.numContacts());
    if (++next == s.poses.size()) next = 0;
  }
}

std::vector<double> seconds_of(const std::vector<PoseResult>& results, double PoseResult::*seconds,
                               const std::function<bool(const PoseResult&)>& keep) {
  std::vector<double> out;
  for (const PoseResult& r : results)
    if (keep(r)) out.push_back(r.*seconds);
  return out;
}

void print_summary() {
  const Setup& s = setup();
  const std::vector<PoseResult>& results = s.results;
  std::printf(
      "\narmadillo (5 cm, %zu triangles) vs bunny00 (30 cm, %zu triangles), "
      "armadillo_on_bunny trace: %zu of %zu ticks in contact or within %.1f mm (FCL)\n",
      s.tool_triangles, s.scene_triangles, results.size(), s.scenario.trajectory.ticks(),
      1e3 * kNearDistance);
  std::printf(
      "Voxmap PointShell: %.1f mm voxels, %zu points in a tree of %zu nodes (%d leaves), "
      "lookup %.1f MB; voxmap %s (%.1f s), pointshell built or loaded before timing\n",
      1e3 * kVoxelSize, s.shell.points.size(), s.shell.nodes.size(), s.shell.leaves,
      static_cast<double>(s.voxmap.lookup.memory_bytes()) / 1e6,
      s.voxmap.stats.cache_hit ? "from cache" : "built", s.voxmap.stats.seconds);

  const auto all = [](const PoseResult&) { return true; };
  const auto touching = [](const PoseResult& r) { return r.fcl_contact; };
  const auto apart = [](const PoseResult& r) { return !r.fcl_contact; };
  struct Row {
    const char* name;
    std::function<bool(const PoseResult&)> keep;
  };
  const Row rows[] = {{"all poses", all},
                      {"poses FCL finds in contact", touching},
                      {"poses FCL finds apart", apart}};
  const struct {
    const char* title;
    double PoseResult::*seconds;
  } searches[] = {{"each pose searched from the tree's root", &PoseResult::vps_seconds},
                  {"poses in trace order, each search from the last one's front (as the "
                   "renderer)",
                   &PoseResult::vps_coherent_seconds}};
  for (const auto& search : searches) {
    std::printf("\nVoxmap PointShell: %s\n", search.title);
    std::printf("%-28s %6s | %12s %12s | %12s %12s | %10s\n", "poses", "count", "VPS median_us",
                "VPS p99_us", "FCL median_us", "FCL p99_us", "FCL/VPS");
    for (const Row& row : rows) {
      const std::vector<double> vps = seconds_of(results, search.seconds, row.keep);
      const std::vector<double> fcl = seconds_of(results, &PoseResult::fcl_seconds, row.keep);
      const double vps_median = median(vps), fcl_median = median(fcl);
      std::printf("%-28s %6zu | %12.2f %12.2f | %12.1f %12.1f | %9.1fx\n", row.name, vps.size(),
                  1e6 * vps_median, 1e6 * percentile(vps, 0.99), 1e6 * fcl_median,
                  1e6 * percentile(fcl, 0.99), fcl_median / vps_median);
    }
  }

  int both = 0, vps_only = 0, fcl_only = 0, neither = 0;
  double vps_only_max_distance = 0, fcl_only_max_depth = 0;
  std::vector<double> vps_counts, fcl_counts, tested, spheres, coherent_spheres, vps_depths,
      braking_counts;
  for (const PoseResult& r : results) {
    if (r.vps_contact && r.fcl_contact) ++both;
    if (!r.vps_contact && !r.fcl_contact) ++neither;
    if (r.vps_contact && !r.fcl_contact) {
      ++vps_only;
      vps_only_max_distance = std::max(vps_only_max_distance, r.fcl_distance);
    }
    if (!r.vps_contact && r.fcl_contact) {
      ++fcl_only;
      fcl_only_max_depth = std::max(fcl_only_max_depth, r.fcl_depth);
    }
    tested.push_back(static_cast<double>(r.vps_points_tested));
    spheres.push_back(static_cast<double>(r.vps_spheres_tested));
    coherent_spheres.push_back(static_cast<double>(r.vps_coherent_spheres));
    if (r.vps_contact) {
      vps_counts.push_back(static_cast<double>(r.vps_contacts));
      braking_counts.push_back(static_cast<double>(r.vps_braking));
      vps_depths.push_back(r.vps_depth);
    }
    if (r.fcl_contact) fcl_counts.push_back(static_cast<double>(r.fcl_contacts));
  }
  std::printf(
      "\ncontact: VPS %d poses, FCL %d poses; both %d, neither %d, VPS only %d (FCL distance "
      "up to %.3f mm), FCL only %d (FCL penetration depth up to %.3f mm)\n",
      both + vps_only, both + fcl_only, both, neither, vps_only, 1e3 * vps_only_max_distance,
      fcl_only, 1e3 * fcl_only_max_depth);
  std::printf(
      "median contacts per pose in contact: VPS %.0f points (and %.0f in proximity voxels), FCL "
      "%.0f triangle pairs (max %.0f / %.0f)\n",
      median(vps_counts), median(braking_counts), median(fcl_counts),
      vps_counts.empty() ? 0.0 : *std::max_element(vps_counts.begin(), vps_counts.end()),
      fcl_counts.empty() ? 0.0 : *std::max_element(fcl_counts.begin(), fcl_counts.end()));
  std::printf(
      "VPS deepest point per pose in contact: median %.3f mm, max %.3f mm; points looked up "
      "per query: median %.0f, max %.0f of %zu; tree nodes tested per query: median %.0f, max "
      "%.0f of %zu\n",
      1e3 * median(vps_depths),
      vps_depths.empty() ? 0.0 : 1e3 * *std::max_element(vps_depths.begin(), vps_depths.end()),
      median(tested), *std::max_element(tested.begin(), tested.end()), s.shell.points.size(),
      median(spheres), *std::max_element(spheres.begin(), spheres.end()), s.shell.nodes.size());
  std::printf("tree nodes tested per query from the last front: median %.0f, max %.0f\n",
              median(coherent_spheres),
              *std::max_element(coherent_spheres.begin(), coherent_spheres.end()));
}

}  // namespace
}  // namespace hb

int main(int argc, char** argv) {
  using namespace hb;
  // --once: the Voxmap PointShell queries once over the poses in trace
  // order, each from the last one's front, and their totals, nothing else
  // (for counting their instructions: valgrind --tool=callgrind
  // --toggle-collect='*coherent_pass*' vps_vs_fcl_bench --once).
  const bool once = bench::take_leading_flag(argc, argv, "--once");
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  if (!bench::models_present({"armadillo.off", "bunny00.off"})) return 1;
  Setup& s = setup();
  if (s.poses.size() < kMinimumPoses) {
    std::fprintf(stderr, "only %zu poses in contact or within %.1f mm (need %zu)\n", s.poses.size(),
                 1e3 * kNearDistance, kMinimumPoses);
    return 1;
  }
  if (once) {
    const auto begin = std::chrono::steady_clock::now();
    const PassTotals totals = coherent_pass();
    const double pass_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    std::printf(
        "%zu poses once from the last front: %lld points looked up, %lld spheres tested, %lld "
        "front entries kept, %lld contacts, %lld braking points; %.2f ms\n",
        s.poses.size(), static_cast<long long>(totals.looked_up),
        static_cast<long long>(totals.spheres), static_cast<long long>(totals.front_entries),
        static_cast<long long>(totals.contacts), static_cast<long long>(totals.braking),
        1e3 * pass_s);
    return 0;
  }
  measure_poses();
  benchmark::RegisterBenchmark("BM_VoxmapPointShell/from_root", BM_VoxmapPointShell, false)
      ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("BM_VoxmapPointShell/from_last_front", BM_VoxmapPointShell, true)
      ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("BM_FclCollide", BM_FclCollide)->Unit(benchmark::kMicrosecond);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  print_summary();
  return 0;
}
