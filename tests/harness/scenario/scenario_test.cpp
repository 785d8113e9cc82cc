// load_scenario: valid files resolve to the right geometry, mass, trace and
// algorithms (checked against closed forms), and every kind of bad input is
// rejected with an InputError naming the file and the place in it.
#include "harness/scenario/scenario.h"

#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <variant>

#include "hapticbench/input_error.h"
#include "harness/metrics/metric_table.h"
#include "harness/reference/oracle.h"
#include "harness/scenario/json_params.h"
#include "tests/support/scratch_dir.h"

namespace hb {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

const std::string kDataDir = std::string(HAPTICBENCH_SOURCE_DIR) + "/tests/harness/scenario/data";

// Volume enclosed by a closed, outward-oriented mesh: sum of signed
// tetrahedra against the origin (computed here, independently of the code
// under test).
double enclosed_volume(const TriangleMesh& mesh) {
  double six_volume = 0;
  for (const auto& t : mesh.triangles)
    six_volume += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]]));
  return six_volume / 6;
}

// A valid scenario with a generated trace and only primitive shapes; the
// bad-input cases below each break one thing in it.
Json valid_generated_scenario() {
  return Json::parse(R"({
    "name": "press_box",
    "scene": [ { "shape": { "type": "box", "size": [0.4, 0.4, 0.02] },
                 "pose": { "p": [0, 0, -0.01], "q": [1, 0, 0, 0] } } ],
    "tool": { "shape": { "type": "sphere", "radius": 0.02, "subdivisions": 4 }, "density": 1000 },
    "trace": { "generator": "press", "duration_s": 0.25, "seed": 3 },
    "coupling": { "k_t": 2000, "b_t": 5, "k_r": 5, "b_r": 0.05 },
    "algorithms": [ { "name": "coupling_only", "label": "first" } ],
    "budgets": { "tick_p99_us": 1000 }
  })");
}

// Loads `scenario` written to a scratch file and returns the error text;
// fails the test when no InputError is thrown.
struct Rejection {
  std::string what;
  std::string source;
  std::string location;
  std::string scenario_path;
};

Rejection rejection_of_text(const std::string& text) {
  const test::ScratchDir dir("scenario");
  const std::string path = dir.write("broken.json", text);
  try {
    load_scenario(path);
  } catch (const InputError& error) {
    return {error.what(), error.source(), error.location(), path};
  }
  FAIL("load_scenario accepted the scenario:\n" << text);
  return {};
}

Rejection rejection_of(const std::function<void(Json&)>& break_it) {
  Json scenario = valid_generated_scenario();
  break_it(scenario);
  return rejection_of_text(scenario.dump(2));
}

TEST_CASE("a scenario with shapes and a generated trace loads with exact mass properties") {
  const std::string path = kDataDir + "/generated_sphere.json";
  const Scenario scenario = load_scenario(path);

  CHECK(scenario.name == "sphere_over_box");
  CHECK(scenario.path == path);
  REQUIRE(scenario.context.scene.size() == 1);
  const SceneObject& box = scenario.context.scene[0];
  REQUIRE(box.shape.has_value());
  CHECK(box.shape->type == ShapeType::kBox);
  CHECK(box.shape->size.isApprox(Vec3(0.4, 0.4, 0.02)));
  CHECK(box.pose.p.isApprox(Vec3(0, 0, -0.01)));
  CHECK(box.pose.q.isApprox(Quat::Identity()));
  CHECK(enclosed_volume(box.mesh) == Approx(0.4 * 0.4 * 0.02).epsilon(1e-12));
  CHECK_FALSE(box.content_hash.empty());

  // 2 cm sphere tool, density 1000 kg/m³: mass = volume of its mesh times ρ,
  // and that mesh is an inscribed icosphere slightly smaller than the sphere.
  const Tool& tool = scenario.context.tool;
  REQUIRE(tool.shape.has_value());
  CHECK(tool.shape->type == ShapeType::kSphere);
  CHECK(tool.shape->radius == 0.02);
  CHECK(tool.shape->subdivisions == 4);
  const double mesh_volume = enclosed_volume(tool.mesh);
  const double sphere_volume = 4.0 / 3.0 * std::numbers::pi * std::pow(0.02, 3);
  CHECK(tool.mass.mass_kg == Approx(mesh_volume * 1000).epsilon(1e-9));
  CHECK(mesh_volume < sphere_volume);
  CHECK(mesh_volume > 0.99 * sphere_volume);
  CHECK(tool.mass.centre_of_mass.norm() < 1e-12);
  // Solid sphere: I = 2/5 m r² on every axis (to the icosphere's accuracy).
  const double sphere_inertia = 0.4 * tool.mass.mass_kg * 0.02 * 0.02;
  CHECK(tool.mass.inertia_about_com(0, 0) == Approx(sphere_inertia).epsilon(0.02));
  CHECK(std::abs(tool.mass.inertia_about_com(0, 1)) < 1e-6 * sphere_inertia);

  // Generated trace: duration_s · 1000 ticks on the 1 kHz clock.
  const std::vector<DeviceSample> samples = scenario.trajectory.all();
  REQUIRE(samples.size() == 500);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    CHECK(samples[k].tick == static_cast<int64_t>(k));
    CHECK(samples[k].t_ns == static_cast<int64_t>(k) * 1'000'000);
  }
  CHECK(scenario.trace_description == "generator press (seed 7)");

  // Defaults where the file says nothing.
  const CouplingGains default_gains;
  CHECK(scenario.context.coupling.k_t == default_gains.k_t);
  CHECK(scenario.context.gravity == Vec3::Zero());
  CHECK(scenario.reference.oracle == "none");
  CHECK(scenario.reference.analytic == "auto");
  CHECK(scenario.budgets.empty());
  REQUIRE(scenario.algorithms.size() == 1);
  CHECK(scenario.algorithms[0].name == "coupling_only");
  CHECK(scenario.algorithms[0].label == "coupling_only");
  CHECK(scenario.algorithms[0].params.values().empty());
  CHECK(scenario.algorithms[0].params.prefix() == "/algorithms/0/params");
  CHECK(scenario.algorithms[0].params_json == "{}");
  CHECK(scenario.content_hash.size() == 16);
}

TEST_CASE("a scenario with mesh files and a trace file loads, paths relative to it") {
  const Scenario scenario = load_scenario(kDataDir + "/mesh_and_trace.json");

  CHECK(scenario.name == "cube_on_cube");
  REQUIRE(scenario.context.scene.size() == 1);
  const SceneObject& cube = scenario.context.scene[0];
  CHECK_FALSE(cube.shape.has_value());
  CHECK(cube.name == "cube_2units.off");
  CHECK(cube.mesh.triangles.size() == 12);
  // 2 file units at 0.01 m per unit: a 2 cm cube from the origin.
  CHECK(cube.mesh.bounds().min().isApprox(Vec3::Zero()));
  CHECK(cube.mesh.bounds().max().isApprox(Vec3(0.02, 0.02, 0.02)));
  CHECK(enclosed_volume(cube.mesh) == Approx(8e-6).epsilon(1e-12));
  // q is written [qw, qx, qy, qz]: [0, 0, 0, 1] is a half turn about z.
  CHECK(cube.pose.q.w() == 0);
  CHECK(cube.pose.q.z() == 1);
  CHECK(cube.pose.transform_point(Vec3(1, 0, 0)).isApprox(Vec3(-1, 0, -0.02)));

  // Explicit mass: the cube's own mass distribution scaled to 0.5 kg. The
  // centre of mass comes from the geometry (the file's origin is a corner).
  const Tool& tool = scenario.context.tool;
  CHECK_FALSE(tool.shape.has_value());
  CHECK(tool.mass.mass_kg == 0.5);
  CHECK(tool.mass.centre_of_mass.isApprox(Vec3(0.01, 0.01, 0.01), 1e-12));
  const double cube_inertia = 0.5 * 0.02 * 0.02 / 6;  // m a² / 6 about the centre
  CHECK(tool.mass.inertia_about_com.isApprox(cube_inertia * Mat3::Identity(), 1e-9));

  // The CSV moves x at 0.1 m/s; the 1 kHz samples interpolate it linearly.
  const std::vector<DeviceSample> samples = scenario.trajectory.all();
  REQUIRE(samples.size() == 50);
  CHECK(samples[25].pose.p.isApprox(Vec3(0.0025, 0, 0.05), 1e-12));
  CHECK(samples[37].pose.p.x() == Approx(0.0037).epsilon(1e-12));
  CHECK(samples[25].twist.v.x() == Approx(0.1).epsilon(1e-9));
  CHECK(scenario.trace_description.find("line_trace.csv") != std::string::npos);

  CHECK(scenario.context.coupling.k_t == 1500);
  CHECK(scenario.context.coupling.b_t == 4);
  CHECK(scenario.context.coupling.k_r == 3);
  CHECK(scenario.context.coupling.b_r == 0.02);
  CHECK(scenario.context.device.max_force_n == 8);
  CHECK(scenario.context.device.max_torque_nm == 0.5);
  CHECK(scenario.context.gravity == Vec3(0, 0, -9.81));
  CHECK(scenario.reference.oracle == "embree");
  CHECK(scenario.reference.exact_every == 5);
  CHECK(scenario.reference.analytic == "none");

  REQUIRE(scenario.algorithms.size() == 1);
  const AlgorithmSpec& algorithm = scenario.algorithms[0];
  CHECK(algorithm.label == "baseline");
  CHECK(algorithm.params_json == R"({"proxy_mass_kg":0.1,"integrator":"implicit_euler"})");
  CHECK(algorithm.params.number("proxy_mass_kg", 0, 0, 1) == 0.1);
  CHECK(algorithm.params.choice("integrator", "", {"explicit_euler", "implicit_euler"}) ==
        "implicit_euler");

  // Budgets stay in the file's order, not sorted.
  REQUIRE(scenario.budgets.size() == 4);
  CHECK(scenario.budgets[0].name == "tick_p99_us");
  CHECK(scenario.budgets[0].limit == 1000);
  CHECK(scenario.budgets[1].name == "max_penetration_mm");
  CHECK(scenario.budgets[1].limit == 2);
  CHECK(scenario.budgets[2].name == "force_dir_err_deg");
  CHECK(scenario.budgets[3].name == "nonfinite");
}

TEST_CASE("the content hash follows the scenario and every file it names") {
  const test::ScratchDir dir("scenario");
  auto cube_off = [](double side) {
    std::ostringstream out;
    out << "OFF\n8 12 0\n";
    for (int i = 0; i < 8; ++i)
      out << (i == 1 || i == 2 || i == 5 || i == 6 ? side : 0) << " "
          << (i == 2 || i == 3 || i == 6 || i == 7 ? side : 0) << " " << (i >= 4 ? side : 0)
          << "\n";
    out << "3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n"
           "3 3 7 6\n3 3 6 2\n3 0 4 7\n3 0 7 3\n3 1 2 6\n3 1 6 5\n";
    return out.str();
  };
  Json scenario = valid_generated_scenario();
  scenario["scene"][0] = Json::parse(R"({ "mesh": "block.off", "scale": 0.01 })");
  const std::string text = scenario.dump(2);
  const std::string path = dir.write("hashed.json", text);

  dir.write("block.off", cube_off(2));
  const Scenario first = load_scenario(path);
  const Scenario again = load_scenario(path);
  CHECK(first.content_hash == again.content_hash);
  CHECK(first.context.scene[0].content_hash == again.context.scene[0].content_hash);

  dir.write("block.off", cube_off(3));
  const Scenario changed_mesh = load_scenario(path);
  CHECK(enclosed_volume(changed_mesh.context.scene[0].mesh) == Approx(27e-6).epsilon(1e-12));
  CHECK(changed_mesh.content_hash != first.content_hash);
  CHECK(changed_mesh.context.scene[0].content_hash != first.context.scene[0].content_hash);

  dir.write("hashed.json", text + "\n");
  CHECK(load_scenario(path).content_hash != changed_mesh.content_hash);
}

TEST_CASE("params objects become ParamSets with their JSON pointer as prefix") {
  const Json params = Json::parse(R"({"k": 3, "mode": "fast", "on": true, "v": [1, 2.5]})");
  const ParamSet set = param_set_from_json(params, "/algorithms/2/params", "x.json");
  CHECK(set.prefix() == "/algorithms/2/params");
  CHECK(std::get<double>(set.values().at("k")) == 3);
  CHECK(std::get<std::string>(set.values().at("mode")) == "fast");
  CHECK(std::get<bool>(set.values().at("on")) == true);
  CHECK(std::get<std::vector<double>>(set.values().at("v")) == std::vector<double>{1, 2.5});

  for (const char* bad : {R"({"n": null})", R"({"n": {"a": 1}})", R"({"n": [1, "a"]})"}) {
    INFO(bad);
    try {
      param_set_from_json(Json::parse(bad), "/trace/params", "x.json");
      FAIL("accepted");
    } catch (const InputError& error) {
      CHECK(std::string(error.what()).find("x.json: /trace/params/n: expected a number") == 0);
    }
  }
  CHECK_THROWS_AS(param_set_from_json(nlohmann::json::array(), "/p", "x.json"), InputError);
}

// Each case: what() names the scenario file (or the file at fault) and the
// JSON path, and says what was expected.
TEST_CASE("malformed JSON is reported with its line") {
  const Rejection r = rejection_of_text("{\n  \"name\": \"x\",\n  \"scene\" []\n}\n");
  INFO(r.what);
  CHECK(r.source == r.scenario_path);
  CHECK(r.location.find("line 3") == 0);
  CHECK(r.what.find(r.scenario_path + ": line 3, column") == 0);
  CHECK(r.what.find("malformed JSON") != std::string::npos);
}

TEST_CASE("a key given twice is an error, not a silent override") {
  const Rejection r =
      rejection_of_text(R"({"name": "a", "coupling": {"k_t": 100, "k_t": 200}, "scene": []})");
  INFO(r.what);
  CHECK(r.what.find(r.scenario_path + ": /coupling/k_t: key given twice") == 0);
}

TEST_CASE("a missing mesh file is named with its JSON path") {
  const Rejection r = rejection_of(
      [](Json& s) { s["scene"][0] = Json::parse(R"({ "mesh": "models/does_not_exist.off" })"); });
  INFO(r.what);
  CHECK(r.what.find(r.scenario_path + ": /scene/0/mesh: mesh file \"models/does_not_exist.off\" "
                                      "not found") == 0);
}

TEST_CASE("an open mesh is rejected naming the mesh file and where it was referenced") {
  const std::string open_mesh = kDataDir + "/open_cube.off";
  const Rejection r = rejection_of([&](Json& s) { s["scene"][0] = Json{{"mesh", open_mesh}}; });
  INFO(r.what);
  CHECK(r.source == open_mesh);
  CHECK(r.what.find(open_mesh + ": ") == 0);
  CHECK(r.what.find("referenced by " + r.scenario_path + " at /scene/0/mesh") != std::string::npos);
  // A scene object may be an open surface: the error says how.
  CHECK(r.what.find("mark the object \"distance_only\": true at /scene/0") != std::string::npos);

  const Rejection tool = rejection_of([&](Json& s) { s["tool"] = Json{{"mesh", open_mesh}}; });
  INFO(tool.what);
  CHECK(tool.source == open_mesh);
  CHECK(tool.what.find("at /tool/mesh") != std::string::npos);
  CHECK(tool.what.find("distance_only") == std::string::npos);  // a tool must be closed
}

TEST_CASE("an unknown generator names /trace/generator") {
  const Rejection r = rejection_of([](Json& s) { s["trace"]["generator"] = "no_such_motion"; });
  INFO(r.what);
  CHECK(r.source == r.scenario_path);
  CHECK(r.location == "/trace/generator");
  CHECK(r.what.find("no_such_motion") != std::string::npos);
}

TEST_CASE("a negative coupling stiffness names /coupling/k_t and the value") {
  const Rejection r = rejection_of([](Json& s) { s["coupling"]["k_t"] = -100; });
  INFO(r.what);
  CHECK(r.what == r.scenario_path + ": /coupling/k_t: expected a positive number (N/m), got -100");
}

TEST_CASE("a pose quaternion must be unit length") {
  const Rejection r = rejection_of([](Json& s) {
    s["scene"][0]["pose"]["q"] = Json::array({1.0, 0.1, 0.0, 0.0});
  });
  INFO(r.what);
  CHECK(r.what.find(r.scenario_path + ": /scene/0/pose/q: not a unit quaternion (|q| = 1.00498") ==
        0);
}

TEST_CASE("an unknown top-level key is named, with the likely intended key") {
  const Rejection r = rejection_of([](Json& s) { s["budget"] = Json::object(); });
  INFO(r.what);
  CHECK(r.what.find(r.scenario_path + ": /budget: unknown key \"budget\" (did you mean "
                                      "\"budgets\"?)") == 0);
}

TEST_CASE("labels must be unique, including the default label = name") {
  const Rejection r = rejection_of([](Json& s) {
    s["algorithms"].push_back(Json{{"name", "coupling_only"}, {"label", "first"}});
  });
  INFO(r.what);
  CHECK(r.what.find(r.scenario_path +
                    ": /algorithms/1/label: duplicate label \"first\" (also used by "
                    "/algorithms/0)") == 0);

  const Rejection by_name = rejection_of([](Json& s) {
    s["algorithms"] = Json::parse(R"([{"name": "coupling_only"}, {"name": "coupling_only"}])");
  });
  INFO(by_name.what);
  CHECK(by_name.location == "/algorithms/1/name");
  CHECK(by_name.what.find("duplicate label \"coupling_only\"") != std::string::npos);
}

TEST_CASE("an unknown budget name is rejected") {
  const Rejection r = rejection_of([](Json& s) { s["budgets"]["tick_p99"] = 900; });
  INFO(r.what);
  CHECK(r.what.find(r.scenario_path + ": /budgets/tick_p99: unknown budget \"tick_p99\" (did you "
                                      "mean \"tick_p99_us\"?)") == 0);
}

TEST_CASE("a trace file with NaN is rejected naming the trace file and its line") {
  const std::string nan_trace = kDataDir + "/nan_trace.csv";
  const Rejection r = rejection_of([&](Json& s) { s["trace"] = Json{{"file", nan_trace}}; });
  INFO(r.what);
  CHECK(r.source == nan_trace);
  CHECK(r.location == "line 4");
  CHECK(r.what.find("referenced by " + r.scenario_path + " at /trace/file") != std::string::npos);
}

TEST_CASE(
    "a trace file in mm: read as metres it is a warning naming mm, and /trace/units converts it") {
  const test::ScratchDir dir("scenario");
  // A 1 kHz press 30 mm above the box, logged in mm with an epoch clock.
  std::string csv = "t_ns,px,py,pz,qw,qx,qy,qz\n";
  for (int i = 0; i <= 100; ++i)
    csv += std::to_string(int64_t{1'700'000'000'000'000'000} + i * 1'000'000) + ",0,0," +
           std::to_string(30 - 0.2 * i) + ",1,0,0,0\n";
  const std::string trace = dir.write("press_mm.csv", csv);
  Json scenario = valid_generated_scenario();
  scenario["trace"] = Json{{"file", trace}};
  const Scenario as_metres = load_scenario(dir.write("metres.json", scenario.dump()));
  const auto warned = std::find_if(as_metres.warnings.begin(), as_metres.warnings.end(),
                                   [](const std::string& w) { return w.find("/trace/file") == 0; });
  REQUIRE(warned != as_metres.warnings.end());
  CHECK(warned->find("the trace may be in mm") != std::string::npos);
  CHECK(as_metres.trace_description.find("times shifted by -1700000000 s") != std::string::npos);

  scenario["trace"]["units"] = "mm";
  const Scenario converted = load_scenario(dir.write("mm.json", scenario.dump()));
  for (const std::string& warning : converted.warnings) CHECK(warning.find("/trace") != 0);
  CHECK(converted.trace_description.find("mm, s, rad converted to m, s, rad") != std::string::npos);
  CHECK(converted.trajectory.at(0).pose.p.z() == Approx(0.030));
  CHECK(converted.trajectory.at(100).pose.p.z() == Approx(0.010));
  CHECK(converted.content_hash != as_metres.content_hash);

  scenario["trace"]["units"] = "furlongs";
  const Rejection r = rejection_of_text(scenario.dump());
  CHECK(r.location == "/trace/units");
}

TEST_CASE("other rule violations name their field") {
  struct Case {
    const char* what_breaks;
    std::function<void(Json&)> break_it;
    std::string expected_location;
  };
  const std::vector<Case> cases = {
      {"negative density", [](Json& s) { s["tool"]["density"] = -3; }, "/tool/density"},
      {"density and mass", [](Json& s) { s["tool"]["mass_kg"] = 0.1; }, "/tool/density"},
      {"inertia without mass",
       [](Json& s) {
         s["tool"]["inertia"] = Json::array({1, 1, 1});
       },
       "/tool/inertia"},
      {"inertia not positive definite",
       [](Json& s) {
         s["tool"].erase("density");
         s["tool"]["mass_kg"] = 0.1;
         s["tool"]["inertia"] = Json::parse("[[1, 0, 0], [0, 1, 0], [0, 0, -1]]");
       },
       "/tool/inertia"},
      {"negative friction", [](Json& s) { s["scene"][0]["friction"] = -0.1; }, "/scene/0/friction"},
      {"friction not a number", [](Json& s) { s["scene"][0]["friction"] = "high"; },
       "/scene/0/friction"},
      {"non-finite friction",
       [](Json& s) { s["scene"][0]["friction"] = std::numeric_limits<double>::infinity(); },
       "/scene/0/friction"},
      {"scale on a shape", [](Json& s) { s["scene"][0]["scale"] = 2; }, "/scene/0/scale"},
      {"mesh and shape", [](Json& s) { s["scene"][0]["mesh"] = "x.off"; }, "/scene/0"},
      {"unknown shape type", [](Json& s) { s["tool"]["shape"]["type"] = "cone"; },
       "/tool/shape/type"},
      {"radius on a box", [](Json& s) { s["scene"][0]["shape"]["radius"] = 1; },
       "/scene/0/shape/radius"},
      {"too many subdivisions", [](Json& s) { s["tool"]["shape"]["subdivisions"] = 7; },
       "/tool/shape/subdivisions"},
      {"hole larger than box",
       [](Json& s) {
         s["scene"][0]["shape"] = Json::parse(R"({"type": "box_with_hole", "size": [0.1, 0.1, 0.05],
                             "hole_size": [0.05, 0.2]})");
       },
       "/scene/0/shape/hole_size"},
      {"pose position of 2 numbers",
       [](Json& s) {
         s["scene"][0]["pose"]["p"] = {0, 0};
       },
       "/scene/0/pose/p"},
      {"unknown pose key", [](Json& s) { s["scene"][0]["pose"]["rotation"] = 0; },
       "/scene/0/pose/rotation"},
      {"empty scene", [](Json& s) { s["scene"] = Json::array(); }, "/scene"},
      {"missing tool", [](Json& s) { s.erase("tool"); }, "/tool"},
      {"name with a slash", [](Json& s) { s["name"] = "a/b"; }, "/name"},
      {"label with a space", [](Json& s) { s["algorithms"][0]["label"] = "a b"; },
       "/algorithms/0/label"},
      {"zero rotational stiffness", [](Json& s) { s["coupling"]["k_r"] = 0; }, "/coupling/k_r"},
      {"negative damping", [](Json& s) { s["coupling"]["b_r"] = -1; }, "/coupling/b_r"},
      {"zero force limit",
       [](Json& s) {
         s["device"] = Json{{"max_force_n", 0}};
       },
       "/device/max_force_n"},
      {"gravity as a number", [](Json& s) { s["gravity"] = 9.81; }, "/gravity"},
      {"trace too long", [](Json& s) { s["trace"]["duration_s"] = 4000; }, "/trace/duration_s"},
      {"negative seed", [](Json& s) { s["trace"]["seed"] = -1; }, "/trace/seed"},
      {"nested generator param",
       [](Json& s) {
         s["trace"]["params"] = {{"start", {{"x", 1}}}};
       },
       "/trace/params/start"},
      {"file and generator", [](Json& s) { s["trace"]["file"] = "a.csv"; }, "/trace"},
      {"unknown oracle",
       [](Json& s) {
         s["reference"] = {{"oracle", "exact"}};
       },
       "/reference/oracle"},
      {"exact_every zero",
       [](Json& s) {
         s["reference"] = {{"exact_every", 0}};
       },
       "/reference/exact_every"},
      {"budget as text", [](Json& s) { s["budgets"]["tick_p99_us"] = "1 ms"; },
       "/budgets/tick_p99_us"},
      {"algorithm params not an object", [](Json& s) { s["algorithms"][0]["params"] = 3; },
       "/algorithms/0/params"},
      {"no algorithms", [](Json& s) { s["algorithms"] = Json::array(); }, "/algorithms"},
      {"closed loop as true", [](Json& s) { s["closed_loop"] = true; }, "/closed_loop"},
      {"negative device mass",
       [](Json& s) {
         s["closed_loop"] = {{"device", {{"mass_kg", -0.1}}}};
       },
       "/closed_loop/device/mass_kg"},
      {"zero device inertia",
       [](Json& s) {
         s["closed_loop"] = {{"device", {{"inertia_kgm2", 0}}}};
       },
       "/closed_loop/device/inertia_kgm2"},
      {"non-finite hand damping",
       [](Json& s) {
         s["closed_loop"] = {{"hand", {{"b_t", std::numeric_limits<double>::infinity()}}}};
       },
       "/closed_loop/hand/b_t"},
      {"hand stiffness as text",
       [](Json& s) {
         s["closed_loop"] = {{"hand", {{"k_t", "stiff"}}}};
       },
       "/closed_loop/hand/k_t"},
      {"unknown device key",
       [](Json& s) {
         s["closed_loop"] = {{"device", {{"friction", 0.1}}}};
       },
       "/closed_loop/device/friction"},
      {"stiffness no tick can integrate",
       [](Json& s) {
         s["closed_loop"] = {{"hand", {{"k_t", 1e300}}}, {"device", {{"mass_kg", 1e-300}}}};
       },
       "/closed_loop"},
  };
  for (const Case& c : cases) {
    INFO(c.what_breaks);
    const Rejection r = rejection_of(c.break_it);
    INFO(r.what);
    CHECK(r.source == r.scenario_path);
    CHECK(r.location == c.expected_location);
  }
}

TEST_CASE("settings outside their plausible range are warned about, defaults are not") {
  const test::ScratchDir dir("scenario");
  Json scenario = valid_generated_scenario();  // no "device": unlimited, not implausible
  CHECK(load_scenario(dir.write("plain.json", scenario.dump(2))).warnings.empty());
  scenario["coupling"]["k_t"] = 1e30;
  scenario["device"] = Json::parse(R"({ "max_force_n": 1e5 })");
  const std::vector<std::string> warnings =
      load_scenario(dir.write("absurd.json", scenario.dump(2))).warnings;
  REQUIRE(warnings.size() == 2);
  CHECK(warnings[0].find("/coupling/k_t: 1e+30 N/m is outside the plausible range [10, 1e+06]") ==
        0);
  CHECK(warnings[1].find("/device/max_force_n: 100000 N is outside") == 0);
}

TEST_CASE("the oracle \"all\" asks for every backend, and \"both\" means the same") {
  const test::ScratchDir dir("scenario");
  Json scenario = valid_generated_scenario();
  std::vector<std::string> every;
  for (const OracleBackendEntry& backend : oracle_backends()) every.emplace_back(backend.name);
  REQUIRE(every.size() >= 2);
  for (const char* name : {"all", "both"}) {
    scenario["reference"] = {{"oracle", name}};
    const Scenario loaded = load_scenario(dir.write(std::string(name) + ".json", scenario.dump(2)));
    CHECK(loaded.reference.oracle_backends == every);
  }
  scenario["reference"] = {{"oracle", every.front()}};
  CHECK(load_scenario(dir.write("one.json", scenario.dump(2))).reference.oracle_backends ==
        std::vector<std::string>{every.front()});
}

TEST_CASE("a scene object's friction coefficient is read, frictionless by default") {
  const test::ScratchDir dir("scenario");
  Json scenario = valid_generated_scenario();
  CHECK(load_scenario(dir.write("plain.json", scenario.dump(2))).context.scene.front().friction ==
        0);
  scenario["scene"][0]["friction"] = 0.8;
  CHECK(load_scenario(dir.write("rough.json", scenario.dump(2))).context.scene.front().friction ==
        0.8);
}

TEST_CASE("tags are read in order, each a safe name given once") {
  const test::ScratchDir dir("scenario");
  Json scenario = valid_generated_scenario();
  CHECK(load_scenario(dir.write("plain.json", scenario.dump(2))).tags.empty());
  scenario["tags"] = {"stress", "friction"};
  CHECK(load_scenario(dir.write("tagged.json", scenario.dump(2))).tags ==
        std::vector<std::string>{"stress", "friction"});
  for (const auto& [tags, expected] : std::vector<std::pair<Json, std::string>>{
           {Json("stress"), "/tags: expected an array of distinct tags"},
           {Json::array({"stress", "stress"}), "/tags/1: the tag \"stress\" is given twice"},
           {Json::array({"a b"}), "/tags/0: expected a non-empty string of letters"},
           {Json::array({1}), "/tags/0: expected a non-empty string of letters"}}) {
    const Rejection r = rejection_of([&](Json& s) { s["tags"] = tags; });
    INFO(r.what);
    CHECK(r.what.find(r.scenario_path + ": " + expected) == 0);
  }
}

TEST_CASE("closed loop: an empty block takes the desk device and hand, keys override them") {
  Json json = valid_generated_scenario();
  const test::ScratchDir dir("scenario");
  CHECK_FALSE(load_scenario(dir.write("open.json", json.dump())).closed_loop);
  json["closed_loop"] = Json::object();
  const Scenario defaults = load_scenario(dir.write("defaults.json", json.dump()));
  REQUIRE(defaults.closed_loop);
  CHECK(defaults.closed_loop->device.mass_kg == ClosedLoopModel{}.device.mass_kg);
  CHECK(defaults.closed_loop->hand.k_t == ClosedLoopModel{}.hand.k_t);
  json["closed_loop"] = Json::parse(R"({"hand": {"k_t": 500}, "device": {"encoder_m": 0}})");
  const Scenario set = load_scenario(dir.write("set.json", json.dump()));
  CHECK(set.closed_loop->hand.k_t == 500);
  CHECK(set.closed_loop->hand.b_t == ClosedLoopModel{}.hand.b_t);
  CHECK(set.closed_loop->device.encoder_m == 0);
}

TEST_CASE("a missing scenario file is an InputError naming it") {
  try {
    load_scenario("/nonexistent/scenario.json");
    FAIL("accepted");
  } catch (const InputError& error) {
    CHECK(error.source() == "/nonexistent/scenario.json");
  }
}

TEST_CASE("budget names are the documented set") {
  const std::vector<std::string>& names = known_budget_names();
  // Exactly the metric table's rows that can be budgets...
  std::size_t budget_rows = 0;
  for (const MetricDefinition& metric : metric_table()) budget_rows += metric.budget ? 1 : 0;
  CHECK(names.size() == budget_rows);
  // ...among them the ones scenarios in the wild use.
  for (const char* name :
       {"tick_p50_us", "tick_p99_us", "tick_p999_us", "tick_max_us", "cpu_per_tick_p99_us",
        "cpu_per_tick_mean_us", "over_budget_ticks", "max_penetration_mm", "penetration_rms_mm",
        "force_err_rms_n", "force_dir_err_deg", "torque_err_rms_nm", "nonfinite",
        "force_jump_max_n", "free_space_force_max_n", "passivity_energy_min_mj", "diverged"})
    CHECK(std::find(names.begin(), names.end(), name) != names.end());
}

TEST_CASE("a budget under its earlier name in m or J loads converted, with a warning") {
  const test::ScratchDir dir("scenario");
  Json scenario = valid_generated_scenario();
  scenario["budgets"] = Json{{"max_penetration_m", 0.002}, {"passivity_energy_min_j", -0.001}};
  const Scenario loaded = load_scenario(dir.write("old_names.json", scenario.dump()));
  REQUIRE(loaded.budgets.size() == 2);
  CHECK(loaded.budgets[0].name == "max_penetration_mm");
  CHECK(loaded.budgets[0].limit == Approx(2.0));
  CHECK(loaded.budgets[1].name == "passivity_energy_min_mj");
  CHECK(loaded.budgets[1].limit == Approx(-1.0));
  const auto warned =
      std::find_if(loaded.warnings.begin(), loaded.warnings.end(), [](const std::string& w) {
        return w.find(
                   "/budgets/max_penetration_m: the budget "
                   "max_penetration_m is now "
                   "max_penetration_mm") == 0;
      });
  CHECK(warned != loaded.warnings.end());
  // Both spellings of one budget: which limit holds would be a guess.
  scenario["budgets"] = Json{{"max_penetration_m", 0.002}, {"max_penetration_mm", 3}};
  const Rejection twice = rejection_of_text(scenario.dump());
  CHECK(twice.what.find("given twice") != std::string::npos);
}

}  // namespace
}  // namespace hb
