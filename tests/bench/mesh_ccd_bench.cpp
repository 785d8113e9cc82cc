// Mesh continuous collision detection of a 5 cm armadillo (the tool, frame
// at its centre of mass) moving onto a 20 cm bunny (bunny00) along seeded
// random screw motions that end in contact, against FCL 0.7's
// continuousCollide (screw motion, the sampling solver at its default 10
// samples and at 100, and conservative advancement on a few motions).
//
// Accuracy: each motion has two reference times of contact, the first of
// 2000 equally spaced times at which FCL's discrete collide reports
// intersection, refined by bisection to 1e-7: one along this project's
// ScrewMotion (the centre of mass moves on a line while the body turns about
// it; poses handed to FCL as transforms), one along FCL's own ScrewMotion (a
// true screw about a fixed line), since FCL's continuousCollide follows its
// own interpolation between the same two poses. A toi is late when it
// exceeds its reference by more than 1e-7.
//
// Time: each method's median and 99th percentile over the motions of the
// per-motion median of a few runs (one run for conservative advancement),
// besides Google Benchmark's mean per motion. Run:
//   build/tests/bench/mesh_ccd_bench --benchmark_min_time=0.5
#include <benchmark/benchmark.h>
#include <fcl/fcl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "algorithms/ccd/mesh_ccd.h"
#include "algorithms/ccd/screw_motion.h"
#include "hapticbench/mass_properties.h"
#include "harness/mesh_io/mesh_io.h"
#include "tests/bench/bench_models.h"
#include "tests/bench/fcl_models.h"

namespace hb {
namespace {

constexpr int kMotions = 60;
constexpr int kReferenceSamples = 2000;
constexpr double kReferenceTolerance = 1e-7;
constexpr double kLateTolerance = 1e-7;
constexpr int kConservativeAdvancementMotions = 5;

using bench::fcl_model;
using bench::FclModel;

Pose pose_at(const ScrewMotion& motion, double t) {
  return Pose{motion.point_at(Vec3::Zero(), t), Quat(motion.rotation_at(t)).normalized()};
}

struct Motion {
  Pose start, end;
  double reference = 0;      // first contact along ScrewMotion
  double fcl_reference = 0;  // first contact along FCL's screw motion
};

/// One method's answers and per-motion times.
struct Measured {
  std::string name;
  std::vector<double> toi;      // NaN where not run
  std::vector<double> seconds;  // per motion, median of the runs
  std::vector<bool> contact;
  bool fcl_motion = false;  // follows FCL's interpolation
  std::int64_t bv_tests = 0, primitive_queries = 0, primitive_evaluations = 0;
  int budget_exhausted = 0;
};

struct Setup {
  TriangleMesh tool, bunny;
  std::unique_ptr<MeshCcd> ccd;
  std::shared_ptr<FclModel> fcl_tool, fcl_bunny;
  std::vector<Motion> motions;
  std::vector<Measured> results;

  bool collide(const fcl::Transform3d& tool_tf) const {
    fcl::CollisionRequestd request;
    fcl::CollisionResultd result;
    return fcl::collide(fcl_tool.get(), tool_tf, fcl_bunny.get(), fcl::Transform3d::Identity(),
                        request, result) > 0;
  }

  /// The first of kReferenceSamples equally spaced times at which the tool
  /// placed by tf_at(t) intersects the bunny, refined by bisection with the
  /// previous sample (which does not); NaN when none does.
  double first_collision(const std::function<fcl::Transform3d(double)>& tf_at) const {
    double previous = 0;
    for (int i = 1; i < kReferenceSamples; ++i) {
      const double t = i / static_cast<double>(kReferenceSamples - 1);
      if (collide(tf_at(t))) {
        double lo = previous, hi = t;
        while (hi - lo > kReferenceTolerance) {
          const double mid = 0.5 * (lo + hi);
          (collide(tf_at(mid)) ? hi : lo) = mid;
        }
        return hi;
      }
      previous = t;
    }
    return std::numeric_limits<double>::quiet_NaN();
  }
};

Setup make_setup() {
  Setup s;
  const std::string models = bench::models_folder();
  // Scaled as scenarios/meshes/armadillo_on_bunny.json scales the tool: 5 cm;
  // the bunny (1 unit) to 20 cm.
  s.tool = read_mesh_file(models + "armadillo.off", 3.305e-4);
  const Vec3 com = mass_properties_from_density(s.tool, 1000).centre_of_mass;
  for (Vec3& v : s.tool.vertices) v -= com;
  s.bunny = read_mesh_file(models + "bunny00.off", 0.2);
  SceneObject bunny;
  bunny.name = "bunny00.off";
  bunny.mesh = s.bunny;
  const std::vector<SceneObject> scene{bunny};
  s.ccd = std::make_unique<MeshCcd>(s.tool, scene);
  s.fcl_tool = fcl_model(s.tool);
  s.fcl_bunny = fcl_model(s.bunny);

  // End pose: sunk 0.2–2 mm past the tangent plane at a random point of the
  // bunny; start: 5–30 mm away, mostly along the normal, turned by up to
  // 0.4 rad. Kept when the start is free and the end intersects.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal_distribution;
  auto random_unit = [&] {
    return Vec3(normal_distribution(rng), normal_distribution(rng), normal_distribution(rng))
        .normalized();
  };
  while (static_cast<int>(s.motions.size()) < kMotions) {
    const auto& tri = s.bunny.triangles[std::uniform_int_distribution<std::size_t>(
        0, s.bunny.triangles.size() - 1)(rng)];
    double u = unit(rng), v = unit(rng);
    if (u + v > 1) u = 1 - u, v = 1 - v;
    const Vec3 &a = s.bunny.vertices[static_cast<std::size_t>(tri[0])],
               &b = s.bunny.vertices[static_cast<std::size_t>(tri[1])],
               &c = s.bunny.vertices[static_cast<std::size_t>(tri[2])];
    const Vec3 surface = a + u * (b - a) + v * (c - a);
    const Vec3 normal = (b - a).cross(c - a).normalized();
    const Quat end_rotation = Quat(normal_distribution(rng), normal_distribution(rng),
                                   normal_distribution(rng), normal_distribution(rng))
                                  .normalized();
    double reach = 0;
    for (const Vec3& p : s.tool.vertices) reach = std::max(reach, -normal.dot(end_rotation * p));
    const double depth = 2e-4 + 1.8e-3 * unit(rng);
    Motion m;
    m.end = Pose{surface + (reach - depth) * normal, end_rotation};
    const Vec3 away = (normal + 0.6 * random_unit()).normalized();
    if (away.dot(normal) < 0.2) continue;
    m.start =
        Pose{m.end.p + (0.005 + 0.025 * unit(rng)) * away,
             (end_rotation * Quat(Eigen::AngleAxisd(0.4 * unit(rng), random_unit()))).normalized()};
    if (s.collide(bench::fcl_transform(m.start)) || !s.collide(bench::fcl_transform(m.end)))
      continue;
    const ScrewMotion motion(m.start, m.end);
    m.reference =
        s.first_collision([&](double t) { return bench::fcl_transform(pose_at(motion, t)); });
    const fcl::ScrewMotion<double> fcl_motion(bench::fcl_transform(m.start),
                                              bench::fcl_transform(m.end));
    m.fcl_reference = s.first_collision([&](double t) {
      fcl_motion.integrate(t);
      fcl::Transform3d tf;
      fcl_motion.getCurrentTransform(tf);
      return tf;
    });
    if (std::isnan(m.reference) || std::isnan(m.fcl_reference)) continue;
    s.motions.push_back(m);
  }
  return s;
}

Setup& setup() {
  static Setup s = make_setup();
  return s;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? std::numeric_limits<double>::quiet_NaN() : v[v.size() / 2];
}

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t i = static_cast<std::size_t>(std::ceil(p * static_cast<double>(v.size()))) - 1;
  return v[std::min(i, v.size() - 1)];
}

/// Runs `method` on each of the first `count` motions `runs` times; records
/// its toi and the median time.
Measured measure(const std::string& name, int count, int runs, bool fcl_motion,
                 const std::function<std::pair<bool, double>(const Motion&, Measured&)>& method) {
  Setup& s = setup();
  Measured out;
  out.name = name;
  out.fcl_motion = fcl_motion;
  const std::size_t n = s.motions.size();
  out.toi.assign(n, std::numeric_limits<double>::quiet_NaN());
  out.contact.assign(n, false);
  for (std::size_t i = 0; i < n && static_cast<int>(i) < count; ++i) {
    std::vector<double> times;
    for (int r = 0; r < runs; ++r) {
      const auto begin = std::chrono::steady_clock::now();
      const auto [contact, toi] = method(s.motions[i], out);
      times.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count());
      out.toi[i] = toi;
      out.contact[i] = contact;
    }
    out.seconds.push_back(median(times));
  }
  return out;
}

std::pair<bool, double> run_mesh_ccd(const Motion& m, Measured& out) {
  const MeshCcdResult r =
      setup().ccd->first_contact(ScrewMotion(m.start, m.end), MeshCcdSettings{});
  out.bv_tests += r.bv_tests;
  out.primitive_queries += r.primitive_queries;
  out.primitive_evaluations += r.primitive_evaluations;
  out.budget_exhausted += r.budget_exhausted;
  return {r.contact, r.toi};
}

std::pair<bool, double> run_fcl(const Motion& m, fcl::CCDSolverType solver, std::size_t samples) {
  Setup& s = setup();
  fcl::ContinuousCollisionRequestd request;
  request.ccd_motion_type = fcl::CCDM_SCREW;
  request.ccd_solver_type = solver;
  if (samples > 0) request.num_max_iterations = samples;
  fcl::ContinuousCollisionResultd result;
  fcl::continuousCollide(s.fcl_tool.get(), bench::fcl_transform(m.start),
                         bench::fcl_transform(m.end), s.fcl_bunny.get(),
                         fcl::Transform3d::Identity(), fcl::Transform3d::Identity(), request,
                         result);
  return {result.is_collide, result.time_of_contact};
}

/// Accuracy of a method against a reference: late answers, |error|.
struct Accuracy {
  int runs = 0, missed = 0, late = 0;
  double max_error = 0, median_error = 0;
};

Accuracy accuracy(const Measured& m, bool against_fcl_motion) {
  const Setup& s = setup();
  Accuracy a;
  std::vector<double> errors;
  for (std::size_t i = 0; i < s.motions.size(); ++i) {
    if (std::isnan(m.toi[i])) continue;
    ++a.runs;
    const double reference =
        against_fcl_motion ? s.motions[i].fcl_reference : s.motions[i].reference;
    const double toi = m.contact[i] ? m.toi[i] : 1.0;
    if (!m.contact[i]) ++a.missed;
    if (toi > reference + kLateTolerance) ++a.late;
    errors.push_back(std::abs(toi - reference));
  }
  a.median_error = median(errors);
  a.max_error = errors.empty() ? 0 : *std::max_element(errors.begin(), errors.end());
  return a;
}

void counters(benchmark::State& state, const Measured& m) {
  const Accuracy own = accuracy(m, m.fcl_motion);
  state.counters["motions"] = own.runs;
  state.counters["late"] = own.late;
  state.counters["missed"] = own.missed;
  state.counters["max_err"] = own.max_error;
  state.counters["median_err"] = own.median_error;
  state.counters["median_us"] = 1e6 * median(m.seconds);
  state.counters["p99_us"] = 1e6 * percentile(m.seconds, 0.99);
}

/// Google Benchmark's view: one motion per iteration, cycling.
void cycle(benchmark::State& state, int count,
           const std::function<std::pair<bool, double>(const Motion&)>& method) {
  const Setup& s = setup();
  std::size_t next = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(method(s.motions[next]));
    if (++next == std::min<std::size_t>(s.motions.size(), static_cast<std::size_t>(count)))
      next = 0;
  }
}

void BM_MeshCcd(benchmark::State& state) {
  Measured scratch;
  cycle(state, kMotions, [&](const Motion& m) { return run_mesh_ccd(m, scratch); });
  counters(state, setup().results[0]);
}
void BM_FclNaive10(benchmark::State& state) {
  cycle(state, kMotions, [](const Motion& m) { return run_fcl(m, fcl::CCDC_NAIVE, 0); });
  counters(state, setup().results[1]);
}
void BM_FclNaive100(benchmark::State& state) {
  cycle(state, kMotions, [](const Motion& m) { return run_fcl(m, fcl::CCDC_NAIVE, 100); });
  counters(state, setup().results[2]);
}
void BM_FclConservativeAdvancement(benchmark::State& state) {
  cycle(state, kConservativeAdvancementMotions,
        [](const Motion& m) { return run_fcl(m, fcl::CCDC_CONSERVATIVE_ADVANCEMENT, 0); });
  counters(state, setup().results[3]);
}

void print_summary() {
  const Setup& s = setup();
  std::printf(
      "\n%zu armadillo (5 cm, %zu triangles) -> bunny00 (20 cm, %zu triangles) screw "
      "motions ending in contact\n",
      s.motions.size(), s.tool.triangles.size(), s.bunny.triangles.size());
  std::vector<double> references, differences;
  for (const Motion& m : s.motions) {
    references.push_back(m.reference);
    differences.push_back(std::abs(m.reference - m.fcl_reference));
  }
  std::printf("reference toi: median %.4f, min %.4f; |ours - FCL motion's| median %.2e, max %.2e\n",
              median(references), *std::min_element(references.begin(), references.end()),
              median(differences), *std::max_element(differences.begin(), differences.end()));
  std::printf("\n%-30s %8s %10s %10s | %-18s %5s %10s %10s | %-18s %5s %10s %10s\n", "method",
              "motions", "median_us", "p99_us", "vs ScrewMotion ref", "late", "max_err",
              "median_err", "vs FCL-motion ref", "late", "max_err", "median_err");
  for (const Measured& m : s.results) {
    const Accuracy ours = accuracy(m, false), theirs = accuracy(m, true);
    std::printf("%-30s %8d %10.1f %10.1f | %-18s %5d %10.2e %10.2e | %-18s %5d %10.2e %10.2e\n",
                m.name.c_str(), ours.runs, 1e6 * median(m.seconds),
                1e6 * percentile(m.seconds, 0.99), m.fcl_motion ? "" : "(own motion)", ours.late,
                ours.max_error, ours.median_error, m.fcl_motion ? "(own motion)" : "", theirs.late,
                theirs.max_error, theirs.median_error);
  }
  const Measured& ours = s.results[0];
  std::printf(
      "\nmesh CCD per motion (mean): %.0f sphere tests, %.0f kernel calls, %.0f "
      "evaluations; %d motions hit the kernel budget\n",
      static_cast<double>(ours.bv_tests) / static_cast<double>(s.motions.size()),
      static_cast<double>(ours.primitive_queries) / static_cast<double>(s.motions.size()),
      static_cast<double>(ours.primitive_evaluations) / static_cast<double>(s.motions.size()),
      ours.budget_exhausted);
}

}  // namespace
}  // namespace hb

int main(int argc, char** argv) {
  using namespace hb;
  // --once: the mesh CCD once per motion and its totals, nothing else (for
  // counting its instructions: valgrind --tool=callgrind
  // --toggle-collect='*search_first_contact*' mesh_ccd_bench --once).
  const bool once = bench::take_leading_flag(argc, argv, "--once");
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  if (!bench::models_present({"armadillo.off", "bunny00.off"})) return 1;
  Setup& s = setup();
  if (once) {
    const Measured m = measure("mesh_ccd", kMotions, 1, false, run_mesh_ccd);
    const Accuracy a = accuracy(m, false);
    std::printf(
        "%zu motions once: %lld node-pair tests, %lld kernel calls, %d on the budget, %d late\n",
        s.motions.size(), static_cast<long long>(m.bv_tests),
        static_cast<long long>(m.primitive_queries), m.budget_exhausted, a.late);
    return 0;
  }
  s.results.push_back(measure("mesh_ccd (path chords)", kMotions, 5, false,
                              [](const Motion& m, Measured& out) { return run_mesh_ccd(m, out); }));
  // The counters above summed 5 runs per motion.
  s.results[0].bv_tests /= 5;
  s.results[0].primitive_queries /= 5;
  s.results[0].primitive_evaluations /= 5;
  s.results[0].budget_exhausted /= 5;
  s.results.push_back(
      measure("fcl naive, 10 samples", kMotions, 3, true,
              [](const Motion& m, Measured&) { return run_fcl(m, fcl::CCDC_NAIVE, 0); }));
  s.results.push_back(
      measure("fcl naive, 100 samples", kMotions, 3, true,
              [](const Motion& m, Measured&) { return run_fcl(m, fcl::CCDC_NAIVE, 100); }));
  s.results.push_back(measure("fcl conservative advancement", kConservativeAdvancementMotions, 1,
                              true, [](const Motion& m, Measured&) {
                                return run_fcl(m, fcl::CCDC_CONSERVATIVE_ADVANCEMENT, 0);
                              }));
  benchmark::RegisterBenchmark("BM_MeshCcd", BM_MeshCcd)->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("BM_FclNaive10", BM_FclNaive10)->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("BM_FclNaive100", BM_FclNaive100)->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("BM_FclConservativeAdvancement", BM_FclConservativeAdvancement)
      ->Unit(benchmark::kMicrosecond)
      ->Iterations(kConservativeAdvancementMotions);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  print_summary();
  return 0;
}
