// End-to-end: closed-loop replay (docs/closed-loop.md). A hand holding a
// linear device presses a 2 cm sphere into a box face rendered by the
// god-object (a proxy at rest on the face behind the coupling spring k_t, no
// coupling damping): one axis of a sampled virtual wall. The stability
// command finds the display's passivity limit and the exact stability
// limit of the sampled closed loop, both computed here from the model.
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kTickS = 1e-3;
constexpr double kRadius = 0.02;
// The hand and the device of these tests: linear (no friction, exact
// encoders, unfiltered velocity), the device's viscous friction b_d.
constexpr double kHandMass = 0.1, kHandK = 300, kHandB = 2;
constexpr double kDeviceMass = 0.045, kDeviceB = 5;

// The intent (z of the tool frame; the sphere touches the face at z = 2 cm).
// The god-object's slow loop is installed a fixed tick after it starts: a
// latency measured on a loaded machine would feed back through the device.
enum class Intent {
  // A smooth press 2 mm past the touching point in 1 s, then 5 Hz cycles
  // between there and 40 mm deeper, starting at rest: the device stays in
  // contact, near the touching point at the top of each cycle, so that the
  // coupling's store returns to almost nothing every cycle.
  kCycles,
  // From 5 mm above the face down to 20 mm past the touching point in
  // 0.3 s, then held: the impact rings the contact.
  kPressAndHold,
};

void write_scenario(const fs::path& folder, Intent intent, double duration_s) {
  std::ofstream trace(folder / "press.csv");
  trace << "t_ns,px,py,pz,qw,qx,qy,qz\n";
  for (int n = 0; n <= static_cast<int>(std::lround(duration_s / kTickS)); ++n) {
    const double t = n * kTickS;
    double z = 0;
    if (intent == Intent::kCycles) {
      const double preload = 0.002, amplitude = 0.02;
      z = t < 1 ? kRadius - preload * (1 - std::cos(M_PI * t)) / 2
                : kRadius - preload - amplitude * (1 - std::cos(2 * M_PI * 5 * (t - 1)));
    } else {
      const double top = kRadius + 0.005, deep = kRadius - 0.02;
      z = t < 0.3 ? top + (deep - top) * t / 0.3 : deep;
    }
    trace << n * 1'000'000LL << ",0,0," << std::setprecision(17) << z << ",1,0,0,0\n";
  }
  json scenario = json::parse(R"({
    "name": "closed_loop_wall",
    "scene": [ { "shape": { "type": "box", "size": [0.4, 0.4, 0.02] },
                 "pose": { "p": [0, 0, -0.01], "q": [1, 0, 0, 0] } } ],
    "tool": { "shape": { "type": "sphere", "radius": 0.02, "subdivisions": 3 }, "density": 1000 },
    "trace": { "file": "press.csv" },
    "coupling": { "k_t": 2000, "b_t": 0, "k_r": 5, "b_r": 0.05 },
    "algorithms": [ { "name": "god_object", "label": "god_object",
                      "params": { "slow_loop_latency": 1 } } ] })");
  scenario["closed_loop"] = {{"hand", {{"mass_kg", kHandMass}, {"k_t", kHandK}, {"b_t", kHandB}}},
                             {"device",
                              {{"mass_kg", kDeviceMass},
                               {"b_t", kDeviceB},
                               {"friction_n", 0},
                               {"encoder_m", 0},
                               {"velocity_filter_hz", 0}}}};
  std::ofstream(folder / "wall.json") << scenario.dump(2);
}

// Keeps the one algorithm labelled (or named) `label` in a scenario.
void keep_only_label(json& scenario, const std::string& label) {
  json kept = json::array();
  for (const json& algorithm : scenario["algorithms"])
    if (algorithm.value("label", algorithm["name"].get<std::string>()) == label)
      kept.push_back(algorithm);
  REQUIRE(kept.size() == 1);
  scenario["algorithms"] = kept;
}

struct Margin {
  json search;
  double stable = 0, unstable = 0;
};

Margin search_margin(const std::string& args, const fs::path& work) {
  const hb::test::CommandResult result =
      hb::test::run_hapticbench("stability wall.json --label god_object " + args, work);
  INFO(result.stderr_text);
  REQUIRE(result.exit_code == 0);
  Margin margin;
  margin.search = json::parse(hb::test::read_text_file(work / "margin/stability.json"));
  margin.stable = margin.search.at("largest_stable").get<double>();
  REQUIRE_FALSE(margin.search.at("smallest_unstable").is_null());
  margin.unstable = margin.search.at("smallest_unstable").get<double>();
  return margin;
}

// e^{A h} of a small matrix by scaling and squaring of its Taylor series.
template <int N>
std::array<std::array<double, N>, N> exponential(std::array<std::array<double, N>, N> a, double h) {
  using Matrix = std::array<std::array<double, N>, N>;
  const auto multiply = [](const Matrix& x, const Matrix& y) {
    Matrix z{};
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j)
        for (int k = 0; k < N; ++k) z[i][j] += x[i][k] * y[k][j];
    return z;
  };
  constexpr int kSquarings = 10;
  for (auto& row : a)
    for (double& x : row) x *= h / (1 << kSquarings);
  Matrix sum{}, term{};
  for (int i = 0; i < N; ++i) sum[i][i] = term[i][i] = 1;
  for (int k = 1; k <= 20; ++k) {
    term = multiply(term, a);
    for (auto& row : term)
      for (double& x : row) x /= k;
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j) sum[i][j] += term[i][j];
  }
  for (int s = 0; s < kSquarings; ++s) sum = multiply(sum, sum);
  return sum;
}

// The sampled closed loop about the pressed equilibrium: the device (with
// the hand's mass, spring and damper) over one tick with the force held,
// (x, v)_{n+1} = Φ (x, v)_n + g F_n, and the wall F_n = −k x_n − B (x_n −
// x_{n−1}) / T (the coupling's damper on the backward-difference velocity).
// Its characteristic polynomial z³ + a2 z² + a1 z + a0 (state x, v, x_{n−1})
// has every root inside the unit circle exactly when Jury's conditions for
// a cubic hold: P(1) > 0, −P(−1) > 0, |a0| < 1 and |a0² − 1| > |a0 a2 − a1|.
bool jury_stable(double k, double b) {
  const double mass = kHandMass + kDeviceMass;
  // Augmented (x, v, F): the last column of e^{Ah} is the held force's response.
  std::array<std::array<double, 3>, 3> a{};
  a[0][1] = 1;
  a[1][0] = -kHandK / mass;
  a[1][1] = -(kHandB + kDeviceB) / mass;
  a[1][2] = 1 / mass;
  const auto e = exponential<3>(a, kTickS);
  // The closed-loop matrix on (x_n, v_n, x_{n−1}).
  const double gain = k + b / kTickS, memory = b / kTickS;
  const double m[3][3] = {{e[0][0] - e[0][2] * gain, e[0][1], e[0][2] * memory},
                          {e[1][0] - e[1][2] * gain, e[1][1], e[1][2] * memory},
                          {1, 0, 0}};
  const double trace = m[0][0] + m[1][1] + m[2][2];
  const double minors = m[0][0] * m[1][1] - m[0][1] * m[1][0] + m[0][0] * m[2][2] -
                        m[0][2] * m[2][0] + m[1][1] * m[2][2] - m[1][2] * m[2][1];
  const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                     m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  const double a2 = -trace, a1 = minors, a0 = -det;
  const auto p = [&](double z) { return ((z + a2) * z + a1) * z + a0; };
  return p(1) > 0 && -p(-1) > 0 && std::abs(a0) < 1 &&
         std::abs(a0 * a0 - 1) > std::abs(a0 * a2 - a1);
}

double jury_limit(double b) {
  double stable = 1e3, unstable = 1e7;
  REQUIRE(jury_stable(stable, b));
  REQUIRE_FALSE(jury_stable(unstable, b));
  while (unstable / stable > 1 + 1e-9) {
    const double middle = std::sqrt(stable * unstable);
    (jury_stable(middle, b) ? stable : unstable) = middle;
  }
  return stable;
}

TEST_CASE("closed loop: the display's energy changes sign at Colgate and Schenkel's b = k T / 2") {
  // The hand moves the device in and out of the wall at 5 Hz without
  // letting go of it; the wall is the coupling spring sampled every T, the
  // device's viscous friction b_d the only damping inside the grip. The
  // energy the hand puts into the device grows by ≈ (b_d − k T/2) ∫ v² dt
  // at low frequency (Colgate & Schenkel 1997: passive while b > kT/2 + |B|,
  // B = 0 here), so it turns negative above k = 2 b_d / T = 10,000 N/m; the
  // loop itself stays stable well past it.
  const hb::test::ScratchDir work_dir("e2e_closed_loop_passivity");
  const fs::path& work = work_dir.path();
  write_scenario(work, Intent::kCycles, 6);
  const Margin found = search_margin(
      "--param /coupling/k_t --range 2000 13000 --tolerance 0.01 --criterion passivity --out "
      "margin",
      work);
  const double limit = 2 * kDeviceB / kTickS;
  CHECK(found.stable == Approx(limit).epsilon(0.02));
  CHECK(found.unstable == Approx(limit).epsilon(0.02));
  CHECK(found.search.at("criterion").get<std::string>().find("display_energy_min_j") !=
        std::string::npos);
  for (const json& run : found.search.at("runs")) {
    CHECK_FALSE(run.at("display_energy_min_j").is_null());
    CHECK_FALSE(run.at("limit_cycle").get<bool>());  // passivity is lost, not stability
  }
}

TEST_CASE("closed loop: the device buzzes above the exact stability limit of the sampled loop") {
  // The hand presses the device 20 mm (in intent) into the wall and holds:
  // the contact rings at the wall's frequency and dies out below the limit
  // Jury's test gives for the linear loop (hand, device and sampled spring),
  // and grows into a bouncing limit cycle above it.
  const hb::test::ScratchDir work_dir("e2e_closed_loop_stability");
  const fs::path& work = work_dir.path();
  write_scenario(work, Intent::kPressAndHold, 8.3);
  const double limit = jury_limit(0);
  INFO("Jury's limit: " << limit << " N/m");
  CHECK(limit > 2 * kDeviceB / kTickS);  // stable past the passivity limit
  const Margin found = search_margin(
      "--param /coupling/k_t --range 5000 50000 --tolerance 0.01 --criterion oscillation --out "
      "margin",
      work);
  CHECK(found.stable == Approx(limit).epsilon(0.02));
  CHECK(found.unstable == Approx(limit).epsilon(0.02));
  // The small-signal limit stability.json gives beside the search is the
  // same loop's (eigenvalues there, Jury's conditions here).
  CHECK(found.search.at("small_signal_limit").get<double>() == Approx(limit).epsilon(1e-3));
  bool buzzed = false;
  for (const json& run : found.search.at("runs"))
    if (!run.at("stable").get<bool>()) {
      buzzed = buzzed || run.at("limit_cycle").get<bool>();
      CHECK_FALSE(run.at("diverged").get<bool>());
    }
  CHECK(buzzed);
}

TEST_CASE("closed loop: a run in a limit cycle fails the command unless its label is expected to") {
  // The press and hold with the coupling 30 % above Jury's limit: the
  // device bounces in a limit cycle. The run folder is written either way.
  const hb::test::ScratchDir work_dir("e2e_closed_loop_unstable_fails");
  const fs::path& work = work_dir.path();
  write_scenario(work, Intent::kPressAndHold, 1.5);
  json scenario = json::parse(hb::test::read_text_file(work / "wall.json"));
  scenario["coupling"]["k_t"] = 1.3 * jury_limit(0);
  std::ofstream(work / "wall.json") << scenario.dump(2);

  const hb::test::CommandResult unexpected =
      hb::test::run_hapticbench("run wall.json --out plain", work);
  INFO(unexpected.stdout_text << unexpected.stderr_text);
  CHECK(unexpected.exit_code == 1);
  CHECK(unexpected.stderr_text.find("1 unstable run") != std::string::npos);
  const json run =
      json::parse(hb::test::read_text_file(work / "plain/summary.json")).at("runs").at(0);
  const json& verdict = run.at("stability").at("verdict");
  // Above the passivity limit too, the first check failed may be passivity;
  // the limit cycle is there either way.
  CHECK(run.at("closed_loop").at("limit_cycle").get<bool>());
  REQUIRE(verdict.at("failed").is_string());
  const std::string failed = verdict.at("failed");
  CHECK(verdict.at("pass") == false);
  CHECK(verdict.at("expected_unstable").is_null());
  CHECK(unexpected.stdout_text.find(" " + failed + " ") != std::string::npos);  // the column
  CHECK(unexpected.stdout_text.find("UNSTABLE: ") != std::string::npos);
  const std::string junit = hb::test::read_text_file(work / "plain/junit.xml");
  CHECK(junit.find("name=\"stability\"><failure message=\"unstable: ") != std::string::npos);

  // For the report: the intent every 10th tick beside the device's ticks,
  // and the scene's and the tool's bounds in the summary.
  const std::string intent = hb::test::read_text_file(work / "plain/intent.csv");
  CHECK(intent.rfind("t_s,px,py,pz\n0,", 0) == 0);
  const std::size_t ticks = run.at("timing").at("ticks").get<std::size_t>();
  CHECK(static_cast<std::size_t>(std::count(intent.begin(), intent.end(), '\n')) ==
        1 + (ticks + 9) / 10);
  const json outline = json::parse(hb::test::read_text_file(work / "plain/summary.json"))
                           .at("scenario")
                           .at("outline");
  CHECK(outline.at("scene").at(0).at("type") == "box");
  CHECK(outline.at("tool").at("max").at(2).get<double>() > 0);

  // Expected on the command line, or by the scenario: exit 0, still said.
  const hb::test::CommandResult flagged =
      hb::test::run_hapticbench("run wall.json --out flagged --expect-unstable god_object", work);
  CHECK(flagged.exit_code == 0);
  CHECK(flagged.stdout_text.find(failed + "*") != std::string::npos);
  CHECK(flagged.stdout_text.find("unstable, as expected: ") != std::string::npos);
  scenario["expected_unstable"] = {{"god_object", "the coupling is above the loop's limit"}};
  std::ofstream(work / "wall.json") << scenario.dump(2);
  const hb::test::CommandResult declared =
      hb::test::run_hapticbench("run wall.json --out declared", work);
  CHECK(declared.exit_code == 0);
  CHECK(json::parse(hb::test::read_text_file(work / "declared/summary.json"))
            .at("runs")
            .at(0)
            .at("stability")
            .at("verdict")
            .at("expected_unstable") == "the coupling is above the loop's limit");

  // A label the scenario does not run is an input error.
  scenario["expected_unstable"] = {{"god_objet", "typo"}};
  std::ofstream(work / "wall.json") << scenario.dump(2);
  const hb::test::CommandResult typo = hb::test::run_hapticbench("run wall.json --out typo", work);
  CHECK(typo.exit_code == 2);
  CHECK(typo.stderr_text.find("/expected_unstable") != std::string::npos);
  CHECK(typo.stderr_text.find("god_object") != std::string::npos);
  CHECK_FALSE(fs::exists(work / "typo"));
}

}  // namespace

namespace {

TEST_CASE("closed loop: the Z-width map follows Jury's limit as the coupling damping grows") {
  // The same press and hold; for each coupling damping B the largest stable
  // stiffness. The damper acts on the backward-difference velocity, so it
  // both damps the contact and, sampled, feeds it: the limit rises with B
  // as Jury's test on the cubic says.
  const hb::test::ScratchDir work_dir("e2e_closed_loop_zwidth");
  const fs::path& work = work_dir.path();
  write_scenario(work, Intent::kPressAndHold, 8.3);
  const hb::test::CommandResult result = hb::test::run_hapticbench(
      "zwidth wall.json --label god_object --x /coupling/b_t --x-values 0,5 --y /coupling/k_t "
      "--y-range 5000 100000 --tolerance 0.02 --criterion oscillation --out map",
      work);
  INFO(result.stderr_text);
  REQUIRE(result.exit_code == 0);
  const json map = json::parse(hb::test::read_text_file(work / "map/zwidth.json"));
  CHECK(map.at("x_param") == "/coupling/b_t");
  CHECK(map.at("y_param") == "/coupling/k_t");
  const json& points = map.at("points");
  REQUIRE(points.size() == 2);
  for (const json& point : points) {
    const double b = point.at("x").get<double>();
    const double limit = jury_limit(b);
    INFO("B = " << b << " N·s/m, Jury's limit " << limit << " N/m");
    CHECK(point.at("largest_stable").get<double>() == Approx(limit).epsilon(0.03));
    CHECK(point.at("smallest_unstable").get<double>() == Approx(limit).epsilon(0.03));
    CHECK(point.at("small_signal_limit").get<double>() == Approx(limit).epsilon(1e-3));
  }
  CHECK(points[1].at("largest_stable").get<double>() >
        1.5 * points[0].at("largest_stable").get<double>());

  // The report draws the map as the scenario's Z-width figure.
  const hb::test::CommandResult report =
      hb::test::run_hapticbench("report map --out report.html", work);
  INFO(report.stdout_text << report.stderr_text);
  REQUIRE(report.exit_code == 0);
  CHECK(report.stdout_text.find("1 Z-width map") != std::string::npos);
  const std::string page = hb::test::read_text_file(work / "report.html");
  CHECK(page.find("id=\"fig-zwidth-closed_loop_wall\"") != std::string::npos);
}

TEST_CASE("closed loop: the displayed stiffness is fitted only over ten encoder counts") {
  // The god-object at k_t = 21,000 N/m against a wall: rigid behind the
  // coupling, it is felt as k_t (springs in series with a rigid wall). With
  // the default 23 µm encoder the press spans under ten counts, where the
  // fit once read 26,469 N/m (+26 %) off the encoder's staircase: null,
  // with the reason. With an exact encoder the fit is k_t within 1 %.
  const hb::test::ScratchDir work("e2e_closed_loop_stiffness");
  json scenario = json::parse(hb::test::read_text_file(
      hb::test::kSource / "scenarios/closed_loop/sphere_wall_at_limit.json"));
  keep_only_label(scenario, "god_object");
  for (const bool exact : {false, true}) {
    CAPTURE(exact);
    if (exact) scenario["closed_loop"]["device"]["encoder_m"] = 0;
    std::ofstream(work.path() / "wall.json") << scenario.dump(2);
    const auto result = hb::test::run_hapticbench("run wall.json --out run --quiet", work.path());
    INFO(result.stderr_text);
    REQUIRE(result.exit_code <= 1);
    const json closed = json::parse(hb::test::read_text_file(work.path() / "run/summary.json"))
                            .at("runs")
                            .at(0)
                            .at("closed_loop");
    if (exact) {
      CHECK(closed.at("displayed_stiffness_n_per_m").get<double>() == Approx(21000).epsilon(0.01));
    } else {
      CHECK(closed.at("displayed_stiffness_n_per_m").is_null());
      CHECK(closed.at("displayed_stiffness_note").get<std::string>().find("10 encoder counts") !=
            std::string::npos);
    }
  }
}

TEST_CASE("closed loop: the mesh force reference follows the device, as the closed form does") {
  // The device stops short of the operator's intent by the hand's spring; a
  // mesh reference along the intent charged that to the algorithm (6.08 N
  // RMS here, against 0.027 N by the closed form). Following each run's own
  // device, it agrees with the closed form on the same press.
  const hb::test::ScratchDir work("e2e_closed_loop_mesh_reference");
  json scenario = json::parse(
      hb::test::read_text_file(hb::test::kSource / "scenarios/closed_loop/sphere_press_wall.json"));
  keep_only_label(scenario, "god_object");
  double error_n[2] = {0, 0};
  for (const int mesh : {0, 1}) {
    scenario["reference"]["analytic"] = mesh ? "none" : "auto";
    std::ofstream(work.path() / "press.json") << scenario.dump(2);
    const auto result = hb::test::run_hapticbench("run press.json --out run --quiet", work.path());
    INFO(result.stderr_text);
    REQUIRE(result.exit_code <= 1);
    const json summary = json::parse(hb::test::read_text_file(work.path() / "run/summary.json"));
    const json& run = summary.at("runs").at(0);
    error_n[mesh] = run.at("accuracy").at("force_err_rms_n").get<double>();
    if (mesh) {
      CHECK(run.at("force_reference").at("evaluated_ticks").get<int>() > 1000);
      CHECK(run.at("force_reference").at("method").get<std::string>().find("device path") !=
            std::string::npos);
    }
  }
  INFO("closed form " << error_n[0] << " N, mesh reference " << error_n[1] << " N");
  CHECK(error_n[0] < 0.05);
  CHECK(error_n[1] == Approx(error_n[0]).margin(0.005));
}

TEST_CASE("closed loop: every proxy renders no force in free space with the default device") {
  // The device reports a quantised pose and a filtered velocity. The
  // god-object's proxy, which is the device out of contact, took its
  // velocity from a raw backward difference of that pose: the coupling's
  // damper rattled at every encoder step (91 mN peaks on sphere_press_wall,
  // 64 mN here). The dynamic proxies (constrained dynamics, the penalty's
  // and sensation-preserving's) followed the 23 µm staircase through the
  // 21,000 N/m coupling spring with their mass: 0.40-0.44 N peaks. VPS
  // keeps its dynamics within its braking voxels and is not checked here.
  const hb::test::ScratchDir work("e2e_closed_loop_free_space");
  json scenario = json::parse(hb::test::read_text_file(
      hb::test::kSource / "scenarios/closed_loop/sphere_wall_at_limit.json"));
  // Slow loops answered a tick later whatever the machine's load: a late
  // certificate bounds how far a proxy may move, in free space too.
  for (json& algorithm : scenario.at("algorithms"))
    if (algorithm.at("name") != "penalty_analytic" && algorithm.at("name") != "voxmap_pointshell")
      algorithm["params"]["slow_loop_latency"] = 1;
  std::ofstream(work.path() / "press.json") << scenario.dump(2);
  const auto result = hb::test::run_hapticbench("run press.json --out run --quiet", work.path());
  INFO(result.stderr_text);
  REQUIRE(result.exit_code <= 1);
  const json runs =
      json::parse(hb::test::read_text_file(work.path() / "run/summary.json")).at("runs");
  int checked = 0;
  for (const json& run : runs) {
    const std::string label = run.at("label").get<std::string>();
    if (label == "vps_2mm") continue;
    const json& transparency = run.at("transparency");
    INFO(label << ": " << transparency.dump());
    CHECK(transparency.at("free_space_ticks").get<int>() > 500);
    CHECK(transparency.at("free_space_force_max_n").get<double>() <= 0.005);
    ++checked;
  }
  CHECK(checked == 4);
}

TEST_CASE(
    "a slow loop 50 ticks late does not drag the proxy in free space, open or closed loop, nor "
    "let it sink when it comes down") {
  // The sphere circles 8 cm above the slab. Between certificates a proxy
  // moves only within the last one's reach; a reach cut at the search's
  // band held it while the device went on: 60.7 N (god-object) and 74.7 N
  // (constrained dynamics) in open loop, 20.8 N and 16.0 N in closed loop.
  const hb::test::ScratchDir work("e2e_free_space_late_updates");
  json scenario = json::parse(hb::test::read_text_file(
      hb::test::kSource / "scenarios/stress/free_space_late_updates.json"));
  for (const bool closed : {false, true}) {
    if (closed) scenario["closed_loop"] = json::object();
    std::ofstream(work.path() / "late.json") << scenario.dump(2);
    const auto result = hb::test::run_hapticbench("run late.json --out run --quiet", work.path());
    INFO((closed ? "closed loop" : "open loop") << ": " << result.stderr_text);
    REQUIRE(result.exit_code == 0);  // the budgets pass, free_space_force_max_n among them
    const json runs =
        json::parse(hb::test::read_text_file(work.path() / "run/summary.json")).at("runs");
    REQUIRE(runs.size() == 2);
    for (const json& run : runs) {
      const json& transparency = run.at("transparency");
      INFO(run.at("label").get<std::string>() << ": " << transparency.dump());
      CHECK(run.at("params").at("slow_loop_latency") == 50);
      CHECK(transparency.at("free_space_ticks").get<int>() == 3000);
      CHECK(transparency.at("free_space_force_max_n").get<double>() <= 0.01);
    }
  }
  // The reach that lets the proxy follow in free space must still stop it
  // at the surface: the sphere driven from 3 cm above into the slab at
  // 2 m/s, the slow loops 50 ticks late, sinks nowhere (Embree oracle).
  scenario.erase("closed_loop");
  scenario["trace"] = {{"generator", "impact"},
                       {"duration_s", 2.0},
                       {"seed", 1},
                       {"params",
                        {{"start", {0, 0, 0.05}},
                         {"axis", {0, 0, -1}},
                         {"surface_distance", 0.03},
                         {"speed_mps", 2.0},
                         {"depth", 0.01}}}};
  scenario["reference"] = {{"oracle", "embree"}, {"analytic", "none"}};
  scenario["budgets"] = {{"nonfinite", 0}};
  std::ofstream(work.path() / "impact.json") << scenario.dump(2);
  const auto impact =
      hb::test::run_hapticbench("run impact.json --out impact --quiet", work.path());
  INFO(impact.stderr_text);
  REQUIRE(impact.exit_code == 0);
  const json runs =
      json::parse(hb::test::read_text_file(work.path() / "impact/summary.json")).at("runs");
  REQUIRE(runs.size() == 2);
  for (const json& run : runs) {
    INFO(run.at("label").get<std::string>());
    CHECK(run.at("accuracy").at("penetration_max_m").get<double>() == 0);
  }
}

TEST_CASE("closed loop: the same scenario gives the same ticks twice, in both passes") {
  // The slow loops' measured latencies feed back through the device, so the
  // second run follows the first one's schedule (--schedule), as a
  // reproduction of any multi-rate run does (docs/ci-gating.md).
  const hb::test::ScratchDir work_dir("e2e_closed_loop_determinism");
  const fs::path& work = work_dir.path();
  const std::string scenario =
      (fs::path(HAPTICBENCH_SOURCE_DIR) / "scenarios/closed_loop/sphere_press_wall.json").string();
  for (const std::string out : {"first", "second --schedule first"}) {
    const hb::test::CommandResult result =
        hb::test::run_hapticbench("run " + scenario + " --out " + out, work);
    INFO(result.stderr_text);
    REQUIRE(result.exit_code == 0);
    CHECK(result.stdout_text.find("closed loop: device penetration") != std::string::npos);
  }
  const json first = json::parse(hb::test::read_text_file(work / "first/summary.json"));
  const json second = json::parse(hb::test::read_text_file(work / "second/summary.json"));
  REQUIRE(first.at("runs").size() == 4);
  for (std::size_t i = 0; i < first.at("runs").size(); ++i) {
    const json& a = first.at("runs")[i];
    INFO(a.at("label"));
    CHECK(a.at("determinism").at("passes_agree") == true);
    CHECK(a.at("determinism").at("ticks_hash") ==
          second.at("runs")[i].at("determinism").at("ticks_hash"));
    // The device was in the loop: it stopped short of the intent's 5 mm.
    const double penetration = a.at("closed_loop").at("device_penetration_max_m").get<double>();
    CHECK(penetration > 1e-4);
    CHECK(penetration < 2e-3);
    CHECK_FALSE(a.at("closed_loop").at("limit_cycle").get<bool>());
  }
}

TEST_CASE("zwidth rejects bad arguments with exit code 2 and writes nothing") {
  const hb::test::ScratchDir work_dir("e2e_closed_loop_zwidth_usage");
  const fs::path& work = work_dir.path();
  write_scenario(work, Intent::kPressAndHold, 0.5);
  const std::string base = "zwidth wall.json --label god_object --x /coupling/b_t ";
  for (const std::string& args :
       {base + "--x-values 0,x --y /coupling/k_t --y-range 1000 2000",
        base + "--x-values 0,1 --y /coupling/k_t --y-range 2000 1000",
        base + "--x-values 0,1 --y /coupling/b_t --y-range 1000 2000",
        base + "--x-values 0,1 --y-range 1000 2000",
        base + "--x-values -1 --y /coupling/k_t --y-range 1000 2000",
        base + "--x-values 1 --y /coupling/nothing/k --y-range 1000 2000"}) {
    INFO(args);
    const hb::test::CommandResult bad = hb::test::run_hapticbench(args + " --out bad", work);
    CHECK(bad.exit_code == 2);
    CHECK_FALSE(fs::exists(work / "bad"));
  }
}

}  // namespace
