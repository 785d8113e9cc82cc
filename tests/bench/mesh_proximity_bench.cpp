// The god-object's contact discovery: MeshCcd::proximity (every feature pair
// within a band, at most 64 of them) at poses where a tool rests on the
// scene, the query each slow update makes for its proximity certificate.
//
// Cases:
//  - sphere_on_box: a 2 cm icosphere (1,280 triangles) 0.1 mm above the
//    top face of a 40 × 40 × 2 cm box (12 triangles), at 20 random
//    orientations, as in scenarios/analytic/sphere_press_stiffness.json;
//  - armadillo_on_bunny: a 5 cm armadillo (52k triangles) 0.1 mm outside
//    the tangent plane of a 30 cm bunny (bunny00, 75k triangles) at 20
//    random surface points and orientations (moved out further where the
//    bunny curves into it), as in
//    scenarios/meshes/armadillo_on_bunny.json;
//  - fandisk_on_armadillo: a crowded contact, a 6 cm fandisk (13k
//    triangles) lowered face down onto a 30 cm armadillo until 0.1 mm
//    above it, at 20 points within 3 mm of the top of
//    scenarios/meshes/fandisk_press_armadillo.json, listing up to 512 pairs
//    (a search that a god-object certificate of 256 pairs keeps: hundreds
//    of pairs lie within a millimetre);
// each with the narrowest and the widest band of the god-object's defaults
// (0.5 mm and 5 mm), at most 64 pairs listed unless said.
//
// Reported per case: median and 99th percentile over the poses of the
// per-pose median time, node-pair tests and feature-pair tests per query,
// pairs listed. Run:
//   build/tests/bench/mesh_proximity_bench
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "algorithms/ccd/mesh_ccd.h"
#include "hapticbench/mass_properties.h"
#include "hapticbench/shapes.h"
#include "harness/mesh_io/mesh_io.h"
#include "tests/bench/bench_models.h"

namespace hb {
namespace {

constexpr int kPoses = 20;
constexpr int kRunsPerPose = 5;
constexpr std::size_t kMaxPairs = 64;
constexpr std::size_t kCrowdedMaxPairs = 512;
constexpr double kGap = 1e-4;  // m between the tool's lowest point and the tangent plane

struct Case {
  std::string name;
  TriangleMesh tool;  // frame at its centre of mass
  std::unique_ptr<MeshCcd> ccd;
  std::vector<Pose> poses;
  std::size_t max_pairs = kMaxPairs;
};

TriangleMesh centred(TriangleMesh mesh) {
  const Vec3 com = mass_properties_from_density(mesh, 1000).centre_of_mass;
  for (Vec3& v : mesh.vertices) v -= com;
  return mesh;
}

Quat random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n;
  return Quat(n(rng), n(rng), n(rng), n(rng)).normalized();
}

/// The tool at `rotation`, moved along `normal` so that its lowest point
/// along it lies kGap above the plane through `surface`.
Pose resting_pose(const TriangleMesh& tool, const Quat& rotation, const Vec3& surface,
                  const Vec3& normal) {
  double reach = 0;
  for (const Vec3& p : tool.vertices) reach = std::max(reach, -normal.dot(rotation * p));
  return Pose{surface + (reach + kGap) * normal, rotation};
}

Case sphere_on_box() {
  Case c;
  c.name = "sphere_on_box";
  Shape sphere;
  sphere.type = ShapeType::kSphere;
  sphere.radius = 0.02;
  sphere.subdivisions = 3;
  c.tool = shape_mesh(sphere);
  Shape box;
  box.type = ShapeType::kBox;
  box.size = Vec3(0.4, 0.4, 0.02);
  SceneObject object;
  object.name = "box";
  object.mesh = shape_mesh(box);
  for (Vec3& v : object.mesh.vertices) v.z() -= 0.01;  // top face at z = 0
  c.ccd = std::make_unique<MeshCcd>(c.tool, std::vector<SceneObject>{object});
  std::mt19937 rng(5);
  for (int i = 0; i < kPoses; ++i)
    c.poses.push_back(resting_pose(c.tool, random_rotation(rng), Vec3::Zero(), Vec3::UnitZ()));
  return c;
}

Case armadillo_on_bunny() {
  Case c;
  c.name = "armadillo_on_bunny";
  const std::string models = bench::models_folder();
  c.tool = centred(read_mesh_file(models + "armadillo.off", 3.305e-4));
  SceneObject bunny;
  bunny.name = "bunny00.off";
  bunny.mesh = read_mesh_file(models + "bunny00.off", 0.3);
  c.ccd = std::make_unique<MeshCcd>(c.tool, std::vector<SceneObject>{bunny});
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  while (static_cast<int>(c.poses.size()) < kPoses) {
    const auto& tri = bunny.mesh.triangles[std::uniform_int_distribution<std::size_t>(
        0, bunny.mesh.triangles.size() - 1)(rng)];
    double u = unit(rng), v = unit(rng);
    if (u + v > 1) u = 1 - u, v = 1 - v;
    const Vec3& a = bunny.mesh.vertices[static_cast<std::size_t>(tri[0])];
    const Vec3& b = bunny.mesh.vertices[static_cast<std::size_t>(tri[1])];
    const Vec3& d = bunny.mesh.vertices[static_cast<std::size_t>(tri[2])];
    const Vec3 normal = (b - a).cross(d - a);
    if (!(normal.norm() > 0)) continue;
    // The tangent plane is not the bunny: moved out along the normal until
    // no feature pair is nearer than half the gap (the god-object's proxy
    // never intersects the scene).
    Pose pose = resting_pose(c.tool, random_rotation(rng), a + u * (b - a) + v * (d - a),
                             normal.normalized());
    for (int step = 0; step < 1000; ++step) {
      const ProximityResult near = c.ccd->proximity(pose, 0.5 * kGap, 1);
      if (near.pairs.empty()) break;
      pose.p += kGap * normal.normalized();
    }
    c.poses.push_back(pose);
  }
  return c;
}

Case fandisk_on_armadillo() {
  Case c;
  c.name = "fandisk_on_armadillo";
  c.max_pairs = kCrowdedMaxPairs;
  const std::string models = bench::models_folder();
  c.tool = centred(read_mesh_file(models + "fandisk.off", 0.06));
  SceneObject armadillo;
  armadillo.name = "armadillo.off";
  armadillo.mesh = read_mesh_file(models + "armadillo.off", 0.0019827);
  for (Vec3& v : armadillo.mesh.vertices) v += Vec3(0.00002, -0.04253, 0.00001);
  c.ccd = std::make_unique<MeshCcd>(c.tool, std::vector<SceneObject>{armadillo});
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> offset(-0.003, 0.003);
  while (static_cast<int>(c.poses.size()) < kPoses) {
    // Lowered from well above in 0.5 mm, then 0.02 mm, steps until a
    // feature pair comes within the gap; the pose one fine step above.
    Pose pose{Vec3(offset(rng), offset(rng), 0.2), Quat::Identity()};
    for (const double step : {5e-4, 2e-5}) {
      while (c.ccd->proximity(pose, step + kGap, 1).pairs.empty()) pose.p.z() -= step;
      pose.p.z() += step;
    }
    c.poses.push_back(pose);
  }
  return c;
}

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  const std::size_t i = static_cast<std::size_t>(std::ceil(p * static_cast<double>(v.size()))) - 1;
  return v[std::min(i, v.size() - 1)];
}

struct Row {
  std::string name;
  double band = 0, median_us = 0, p99_us = 0, bv_tests = 0, pair_tests = 0, pairs = 0;
};

Row measure(const Case& c, double band) {
  Row row;
  row.name = c.name;
  row.band = band;
  std::vector<double> per_pose;
  for (const Pose& pose : c.poses) {
    std::vector<double> runs;
    for (int r = 0; r < kRunsPerPose; ++r) {
      const auto begin = std::chrono::steady_clock::now();
      const ProximityResult result = c.ccd->proximity(pose, band, c.max_pairs);
      runs.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count());
      if (r == 0) {
        row.bv_tests += static_cast<double>(result.bv_tests) / kPoses;
        row.pair_tests += static_cast<double>(result.pair_tests) / kPoses;
        row.pairs += static_cast<double>(result.pairs.size()) / kPoses;
      }
    }
    per_pose.push_back(1e6 * percentile(runs, 0.5));
  }
  row.median_us = percentile(per_pose, 0.5);
  row.p99_us = percentile(per_pose, 0.99);
  return row;
}

std::vector<Case>& cases() {
  static std::vector<Case> all = [] {
    std::vector<Case> v;
    v.push_back(sphere_on_box());
    if (bench::models_present({"armadillo.off", "bunny00.off"})) v.push_back(armadillo_on_bunny());
    if (bench::models_present({"armadillo.off", "fandisk.off"}))
      v.push_back(fandisk_on_armadillo());
    return v;
  }();
  return all;
}

void BM_Proximity(benchmark::State& state) {
  const Case& c = cases()[static_cast<std::size_t>(state.range(0))];
  const double band = 1e-4 * static_cast<double>(state.range(1));
  std::size_t next = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(c.ccd->proximity(c.poses[next], band, c.max_pairs));
    next = (next + 1) % c.poses.size();
  }
  state.SetLabel(c.name + ", band " + std::to_string(band * 1e3).substr(0, 3) + " mm");
}

}  // namespace
}  // namespace hb

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  const auto& all = hb::cases();
  for (std::size_t i = 0; i < all.size(); ++i)
    for (const int band : {5, 50})
      benchmark::RegisterBenchmark("BM_Proximity", hb::BM_Proximity)
          ->Args({static_cast<int64_t>(i), band})
          ->Unit(benchmark::kMicrosecond);
  benchmark::RunSpecifiedBenchmarks();
  std::printf("\n%-20s %7s %10s %10s %10s %11s %7s\n", "case", "band_mm", "median_us", "p99_us",
              "bv_tests", "pair_tests", "pairs");
  for (const hb::Case& c : all)
    for (const double band : {5e-4, 5e-3}) {
      const hb::Row row = hb::measure(c, band);
      std::printf("%-20s %7.1f %10.1f %10.1f %10.0f %11.0f %7.1f\n", row.name.c_str(), 1e3 * band,
                  row.median_us, row.p99_us, row.bv_tests, row.pair_tests, row.pairs);
    }
  return 0;
}
