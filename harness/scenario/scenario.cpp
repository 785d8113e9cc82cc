// Scenario JSON (DESIGN.md, "Formats -> Scenario JSON"): the keys read here
// are a contract. Every rejection names the file, the JSON pointer and what
// was expected; unknown keys are errors so that a typo never silently falls
// back to a default. Quaternions are written [qw, qx, qy, qz].
#include "harness/scenario/scenario.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>

#include "hapticbench/content_hash.h"
#include "hapticbench/input_error.h"
#include "hapticbench/mass_properties.h"
#include "hapticbench/shapes.h"
#include "hapticbench/triangle_mesh.h"
#include "harness/closed_loop/closed_loop_device.h"
#include "harness/mesh_io/mesh_io.h"
#include "harness/metrics/metric_table.h"
#include "harness/process/input_file.h"
#include "harness/reference/oracle.h"
#include "harness/scenario/input_error_context.h"
#include "harness/scenario/json_fields.h"
#include "harness/scenario/json_params.h"
#include "harness/trace/generators.h"
#include "harness/trace/trace.h"

namespace hb {

namespace {

using Json = nlohmann::ordered_json;

constexpr double kDefaultToolDensity = 1000;  // kg/m³, water
constexpr double kUnitQuaternionTolerance = 1e-6;
constexpr double kMaxTraceDurationS = kMaxRunDurationS;
constexpr double kMaxOracleSamples = 1e6;  ///< tool surface samples the oracles may test per tick
constexpr double kNotApplicable = std::numeric_limits<double>::quiet_NaN();
/// The finest encoder resolutions a closed-loop device may have (m, rad):
/// below them a position divided by the resolution leaves the doubles.
constexpr double kFinestEncoderM = 1e-9, kFinestEncoderRad = 1e-9;

/// Whether the mesh passes the checks of a distance-only surface.
bool is_valid_surface(const TriangleMesh& mesh, const std::string& path) {
  try {
    require_valid_mesh(mesh, path, MeshRequirement::kSurface);
    return true;
  } catch (const InputError&) {
    return false;
  }
}

/// Budgets whose name (and unit) changed: a scenario that uses the old name
/// still loads, its limit converted, with a warning.
struct RenamedBudget {
  std::string_view old_name, new_name;
  double scale;  ///< new limit = old limit × scale
};
constexpr RenamedBudget kRenamedBudgets[] = {
    {"max_penetration_m", "max_penetration_mm", 1e3},
    {"penetration_rms_m", "penetration_rms_mm", 1e3},
    {"device_penetration_max_m", "device_penetration_max_mm", 1e3},
    {"limit_cycle_amplitude_m", "limit_cycle_amplitude_mm", 1e3},
    {"proxy_chatter_m", "proxy_chatter_mm", 1e3},
    {"passivity_energy_min_j", "passivity_energy_min_mj", 1e3},
    {"display_energy_min_j", "display_energy_min_mj", 1e3},
};

std::string range_warning(const PlausibleRange& range, double value) {
  std::ostringstream text;
  text << range.pointer << ": " << value << " " << range.unit << " is outside the plausible range ["
       << range.low << ", " << range.high << "] " << range.unit << " (" << range.why << ")";
  return text.str();
}

constexpr PlausibleRange kPlausibleRanges[] = {
    {"/coupling/k_t", "N/m", 10, 1e6, "haptic couplings render 0.1 to 10 kN/m",
     [](const Scenario& s) { return s.context.coupling.k_t; }},
    {"/coupling/b_t", "N·s/m", 0, 1e3, "beyond it the coupling is a brake",
     [](const Scenario& s) { return s.context.coupling.b_t; }},
    {"/coupling/k_r", "N·m/rad", 1e-3, 1e3, "devices render up to a few N·m/rad",
     [](const Scenario& s) { return s.context.coupling.k_r; }},
    {"/coupling/b_r", "N·m·s/rad", 0, 10, "beyond it the coupling is a brake",
     [](const Scenario& s) { return s.context.coupling.b_r; }},
    {"/device/max_force_n", "N", 0.1, 1000, "desktop devices display up to tens of N",
     [](const Scenario& s) { return s.context.device.max_force_n; }},
    {"/device/max_torque_nm", "N·m", 1e-3, 100, "desktop devices display up to a few N·m",
     [](const Scenario& s) { return s.context.device.max_torque_nm; }},
    {"/tool", "kg", 1e-4, 100, "the tool's mass (from its density and volume, or mass_kg)",
     [](const Scenario& s) { return s.context.tool.mass.mass_kg; }},
    {"/gravity", "m/s²", 0, 100, "the length of the gravity vector",
     [](const Scenario& s) { return s.context.gravity.norm(); }},
    // Closed-loop replay's hand and device (docs/closed-loop.md).
    {"/closed_loop/hand/mass_kg", "kg", 0, 5, "a hand and forearm moving with the grip",
     [](const Scenario& s) {
       return s.closed_loop ? s.closed_loop->hand.mass_kg : kNotApplicable;
     }},
    {"/closed_loop/hand/k_t", "N/m", 0, 1e4, "a grip's stiffness is up to a few kN/m",
     [](const Scenario& s) { return s.closed_loop ? s.closed_loop->hand.k_t : kNotApplicable; }},
    {"/closed_loop/hand/b_t", "N·s/m", 0, 100, "a grip's damping is up to tens of N·s/m",
     [](const Scenario& s) { return s.closed_loop ? s.closed_loop->hand.b_t : kNotApplicable; }},
    {"/closed_loop/device/mass_kg", "kg", 1e-3, 10, "desktop devices move tens to hundreds of g",
     [](const Scenario& s) {
       return s.closed_loop ? s.closed_loop->device.mass_kg : kNotApplicable;
     }},
    {"/closed_loop/device/friction_n", "N", 0, 10, "backdrive friction is a fraction of a N",
     [](const Scenario& s) {
       return s.closed_loop ? s.closed_loop->device.friction_n : kNotApplicable;
     }},
    {"/closed_loop/device/encoder_m", "m", 0, 1e-3, "encoders resolve µm to tens of µm",
     [](const Scenario& s) {
       return s.closed_loop ? s.closed_loop->device.encoder_m : kNotApplicable;
     }},
    {"/closed_loop/device/velocity_filter_hz", "Hz", 0, 1000,
     "a filter above the 500 Hz Nyquist rate of 1 kHz samples filters nothing",
     [](const Scenario& s) {
       return s.closed_loop ? s.closed_loop->device.velocity_filter_hz : kNotApplicable;
     }},
};

std::vector<std::string> plausibility_warnings(const Scenario& scenario) {
  // A device without limits (the default when "device" is not given) is
  // not a setting to warn about.
  const DeviceLimits unlimited;
  std::vector<std::string> warnings;
  for (const PlausibleRange& range : kPlausibleRanges) {
    const double value = range.value(scenario);
    if (std::isnan(value)) continue;  // does not apply
    const bool unlimited_device =
        range.pointer.starts_with("/device/") &&
        (value == unlimited.max_force_n || value == unlimited.max_torque_nm);
    if (!unlimited_device && !(value >= range.low && value <= range.high))
      warnings.push_back(range_warning(range, value));
  }
  return warnings;
}
constexpr double kTicksPerSecond = 1000;
constexpr int64_t kMaxSubdivisions = 6;

// Exact text of a double, so that hashes change whenever a value does.
std::string exact_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

// Short text of a double for messages.
std::string short_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", value);
  return text;
}

// Names and labels become folder and file names (run folder, ticks_<label>.csv).
// '=' is there for sweep jobs, named "<scenario>__<key>=<value>__...".
bool is_file_name_safe(const std::string& name) {
  if (name.empty() || name == "." || name == "..") return false;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '.' || c == '-' || c == '=';
    if (!ok) return false;
  }
  return true;
}

const char* const kSafeNameExpected =
    "expected a non-empty string of letters, digits, '_', '.', '-' and '='";

// A shape's parameters as text: the shape's identity for caches.
std::string shape_hash(const Shape& shape) {
  ContentHash hash;
  hash.add("shape ").add(shape_type_name(shape.type));
  for (double value : {shape.size.x(), shape.size.y(), shape.size.z(), shape.radius, shape.length,
                       shape.hole_size.x(), shape.hole_size.y()})
    hash.add(" ").add(exact_text(value));
  hash.add(" ").add(std::to_string(shape.subdivisions));
  return hash.hex();
}

// Geometry of a scene object or of the tool: a mesh file or a primitive.
struct Geometry {
  TriangleMesh mesh;
  std::optional<Shape> shape;
  std::string content_hash;
  std::string description;  // "box", "bunny.off"
};

// Loads and resolves one scenario file; one instance per load.
class ScenarioReader {
 public:
  ScenarioReader(std::string path, std::filesystem::path base_dir)
      : path_(std::move(path)), directory_(std::move(base_dir)) {}

  Scenario read(const std::string& bytes) {
    scenario_hash_.add(bytes);
    const Json document = parse_json_document(bytes, path_);
    const JsonField root(document, path_, "");
    root.require_object("expected a JSON object with the scenario's keys");
    root.reject_unknown_keys({"name", "description", "tags", "plugins", "scene", "tool", "trace",
                              "algorithms", "coupling", "device", "gravity", "reference", "budgets",
                              "expected_unstable", "closed_loop"});

    Scenario scenario;
    scenario.path = path_;
    scenario.name = root.member("name", "the scenario's name").string(kSafeNameExpected);
    if (!is_file_name_safe(scenario.name))
      root.existing_member("name").fail(std::string(kSafeNameExpected) +
                                        " (it names the run folder)");
    if (root.has("description"))
      scenario.description = root.existing_member("description").string("expected a string");
    if (root.has("tags")) scenario.tags = read_tags(root.existing_member("tags"));

    if (root.has("plugins")) scenario.plugins = read_plugins(root.existing_member("plugins"));
    // Cheap checks first, so that a typo is reported before meshes load.
    scenario.algorithms = read_algorithms(
        root.member("algorithms", "a non-empty array of {\"name\", \"label\", \"params\"}"));
    if (root.has("reference"))
      scenario.reference = read_reference(root.existing_member("reference"));
    if (root.has("budgets")) scenario.budgets = read_budgets(root.existing_member("budgets"));
    if (root.has("expected_unstable"))
      scenario.expected_unstable =
          read_expected_unstable(root.existing_member("expected_unstable"), scenario.algorithms);
    if (root.has("coupling"))
      scenario.context.coupling = read_coupling(root.existing_member("coupling"));
    if (root.has("device")) scenario.context.device = read_device(root.existing_member("device"));
    if (root.has("closed_loop"))
      scenario.closed_loop = read_closed_loop(root.existing_member("closed_loop"));
    if (root.has("gravity"))
      scenario.context.gravity =
          root.existing_member("gravity").vec3("expected [gx, gy, gz] in m/s², finite numbers");

    const JsonField scene = root.member("scene", "a non-empty array of scene objects");
    const std::size_t count = scene.array_size("expected a non-empty array of scene objects");
    if (count == 0) scene.fail("expected a non-empty array of scene objects");
    for (std::size_t i = 0; i < count; ++i)
      scenario.context.scene.push_back(read_scene_object(scene.element(i), i));

    scenario.context.tool =
        read_tool(root.member("tool", "the tool: {\"shape\": ...} or {\"mesh\": ...}"));
    read_trace(root.member("trace", "{\"generator\": ...} or {\"file\": ...}"), scenario);
    check_oracle_sample_count(scenario);

    scenario.warnings = plausibility_warnings(scenario);
    for (std::string& warning : measurement_warnings(root, scenario))
      scenario.warnings.push_back(std::move(warning));
    scenario.warnings.insert(scenario.warnings.end(), load_warnings_.begin(), load_warnings_.end());
    scenario.content_hash = scenario_hash_.hex();
    return scenario;
  }

 private:
  // Paths in a scenario are relative to its base folder (the scenario file's own).
  std::string resolve(const std::string& relative) const {
    const std::filesystem::path path(relative);
    if (path.is_absolute() || directory_.empty()) return path.lexically_normal().string();
    return (directory_ / path).lexically_normal().string();
  }

  // The file a field names, which must exist.
  std::string existing_file(const JsonField& field, const std::string& what) const {
    const std::string relative = field.string("expected the path of a " + what);
    if (relative.empty()) field.fail("expected the path of a " + what);
    const std::string path = resolve(relative);
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error))
      field.fail_with(what + " \"" + relative + "\" not found (looked for " + path + ")");
    return path;
  }

  Pose read_pose(const JsonField& field) const {
    field.require_object("expected {\"p\": [x, y, z], \"q\": [qw, qx, qy, qz]}");
    field.reject_unknown_keys({"p", "q"});
    Pose pose;
    if (field.has("p"))
      pose.p = field.existing_member("p").vec3("expected [x, y, z] in metres, finite numbers");
    if (field.has("q")) {
      const JsonField q_field = field.existing_member("q");
      const std::vector<double> q =
          q_field.numbers(4, "expected a unit quaternion [qw, qx, qy, qz], finite numbers");
      const Quat quat(q[0], q[1], q[2], q[3]);
      const double norm = quat.norm();
      if (std::abs(norm - 1) > kUnitQuaternionTolerance)
        q_field.fail_with("not a unit quaternion (|q| = " + short_text(norm) +
                          "); expected [qw, qx, qy, qz] with |q| = 1 within 1e-6");
      pose.q = quat.normalized();
    }
    return pose;
  }

  Shape read_shape(const JsonField& field) const {
    field.require_object(
        "expected {\"type\": \"box\"|\"sphere\"|\"capsule\"|\"box_with_hole\", ...}");
    const std::string type =
        field.member("type", "\"box\", \"sphere\", \"capsule\" or \"box_with_hole\"")
            .choice({"box", "sphere", "capsule", "box_with_hole"});
    Shape shape;
    const std::string size_expected = "expected [x, y, z] full extents in metres, each > 0";
    auto read_size = [&] {
      const JsonField size = field.member("size", "[x, y, z] full extents in metres");
      shape.size = size.vec3(size_expected);
      if (!(shape.size.array() > 0).all()) size.fail(size_expected);
    };
    auto read_radius = [&] {
      shape.radius = field.member("radius", "a radius in metres, > 0")
                         .positive_number("expected a positive radius (m)");
    };
    auto read_subdivisions = [&] {
      if (field.has("subdivisions"))
        shape.subdivisions = static_cast<int>(
            field.existing_member("subdivisions")
                .integer(0, kMaxSubdivisions, "expected a whole number in [0, 6]"));
    };
    if (type == "box") {
      field.reject_unknown_keys({"type", "size"});
      shape.type = ShapeType::kBox;
      read_size();
    } else if (type == "sphere") {
      field.reject_unknown_keys({"type", "radius", "subdivisions"});
      shape.type = ShapeType::kSphere;
      read_radius();
      read_subdivisions();
    } else if (type == "capsule") {
      field.reject_unknown_keys({"type", "radius", "length", "subdivisions"});
      shape.type = ShapeType::kCapsule;
      read_radius();
      shape.length = field.member("length", "the axis segment's length in metres, >= 0")
                         .non_negative_number("expected a length >= 0 (m)");
      read_subdivisions();
    } else {
      field.reject_unknown_keys({"type", "size", "hole_size"});
      shape.type = ShapeType::kBoxWithHole;
      read_size();
      const JsonField hole = field.member("hole_size", "[x, y] extents of the hole in metres");
      const std::string hole_expected =
          "expected [x, y] hole extents in metres, each > 0 and smaller than size x, y (" +
          short_text(shape.size.x()) + ", " + short_text(shape.size.y()) + ")";
      const std::vector<double> h = hole.numbers(2, hole_expected);
      if (!(h[0] > 0 && h[1] > 0 && h[0] < shape.size.x() && h[1] < shape.size.y()))
        hole.fail(hole_expected);
      shape.hole_size = Vec3(h[0], h[1], 0);
    }
    return shape;
  }

  // `mesh` (+ `scale`) or `shape`, exactly one. A mesh must be a closed
  // solid unless `requirement` says a clean surface is enough.
  Geometry read_geometry(const JsonField& entry,
                         MeshRequirement requirement = MeshRequirement::kClosedSolid) {
    const bool has_mesh = entry.has("mesh");
    const bool has_shape = entry.has("shape");
    if (has_mesh == has_shape)
      entry.fail_with(has_mesh ? "give either \"mesh\" or \"shape\", not both"
                               : "missing geometry; expected \"mesh\": FILE or \"shape\": {...}");
    Geometry geometry;
    if (has_shape) {
      if (entry.has("scale"))
        entry.existing_member("scale").fail_with(
            "\"scale\" applies to a mesh file only; give the shape's size in metres");
      const Shape shape = read_shape(entry.existing_member("shape"));
      geometry.mesh = shape_mesh(shape);
      geometry.shape = shape;
      geometry.content_hash = shape_hash(shape);
      geometry.description = shape_type_name(shape.type);
      return geometry;
    }
    double scale = 1;
    if (entry.has("scale"))
      scale = entry.existing_member("scale").positive_number(
          "expected a positive scale (metres per file unit)");
    const JsonField mesh_field = entry.existing_member("mesh");
    const std::string path = existing_file(mesh_field, "mesh file");
    std::string file_hash;
    bool read = false;
    try {
      geometry.mesh = read_mesh_file(path, scale);
      read = true;
      require_valid_mesh(geometry.mesh, path, requirement);
      file_hash = file_content_hash(path);
    } catch (const InputError& error) {
      const InputError located = with_reference_note(error, path_, mesh_field.pointer());
      // A scene mesh that is open or crosses itself may still be a scene:
      // say how, when it is a surface that "distance_only" admits.
      if (read && requirement == MeshRequirement::kClosedSolid &&
          entry.pointer().rfind("/scene/", 0) == 0 && is_valid_surface(geometry.mesh, path))
        throw InputError(located.source(), located.location(),
                         located.message() + "; if the mesh is open by design, mark the object " +
                             "\"distance_only\": true at " + entry.pointer() +
                             " (ground truth then gives distances, no inside: "
                             "docs/ground-truth.md)");
      throw located;
    }
    scenario_hash_.add(file_hash);
    geometry.content_hash =
        ContentHash().add(file_hash).add(" scale ").add(exact_text(scale)).hex();
    geometry.description = std::filesystem::path(path).filename().string();
    return geometry;
  }

  SceneObject read_scene_object(const JsonField& entry, std::size_t index) {
    entry.require_object("expected a scene object {\"mesh\"|\"shape\", \"pose\", \"name\"}");
    entry.reject_unknown_keys(
        {"name", "mesh", "scale", "shape", "pose", "distance_only", "friction"});
    SceneObject object;
    // "distance_only": true admits an open or self-intersecting mesh, for
    // which ground truth can give distances but not inside/outside.
    if (entry.has("distance_only"))
      object.distance_only =
          entry.existing_member("distance_only").boolean("expected true or false");
    Geometry geometry = read_geometry(
        entry, object.distance_only ? MeshRequirement::kSurface : MeshRequirement::kClosedSolid);
    object.mesh = std::move(geometry.mesh);
    object.shape = geometry.shape;
    object.content_hash = geometry.content_hash;
    object.name = geometry.shape ? "scene[" + std::to_string(index) + "]" : geometry.description;
    if (entry.has("name")) {
      const JsonField name = entry.existing_member("name");
      object.name = name.string("expected a non-empty string");
      if (object.name.empty()) name.fail("expected a non-empty string");
    }
    if (entry.has("pose")) object.pose = read_pose(entry.existing_member("pose"));
    if (entry.has("friction"))
      object.friction = entry.existing_member("friction")
                            .non_negative_number(
                                "expected a Coulomb friction coefficient, a finite number >= 0 (0: "
                                "frictionless)");
    return object;
  }

  Mat3 read_inertia(const JsonField& field) const {
    const std::string expected =
        "expected [Ixx, Iyy, Izz] or a symmetric positive definite 3x3 matrix "
        "[[...], [...], [...]] (kg·m², about the centre of mass)";
    if (!field.json().is_array() || field.json().size() != 3) field.fail(expected);
    Mat3 inertia = Mat3::Zero();
    if (field.json()[0].is_array()) {
      for (std::size_t row = 0; row < 3; ++row) {
        const std::vector<double> values = field.element(row).numbers(3, expected);
        for (std::size_t col = 0; col < 3; ++col)
          inertia(static_cast<int>(row), static_cast<int>(col)) = values[col];
      }
    } else {
      const Vec3 diagonal = field.vec3(expected);
      inertia = diagonal.asDiagonal();
    }
    const double scale = inertia.cwiseAbs().maxCoeff();
    if ((inertia - inertia.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale)
      field.fail(expected + "; this one is not symmetric");
    const Vec3 moments = Eigen::SelfAdjointEigenSolver<Mat3>(inertia).eigenvalues();
    if (!(moments.minCoeff() > 0)) field.fail(expected + "; this one is not positive definite");
    // Principal moments of a real body satisfy I1 + I2 >= I3.
    if (moments(0) + moments(1) < moments(2) * (1 - 1e-9))
      field.fail(expected + "; its principal moments violate I1 + I2 >= I3, no body has them");
    return inertia;
  }

  Tool read_tool(const JsonField& entry) {
    entry.require_object("expected the tool: {\"shape\"|\"mesh\", \"density\"|\"mass_kg\"}");
    entry.reject_unknown_keys({"mesh", "scale", "shape", "density", "mass_kg", "inertia"});
    Geometry geometry = read_geometry(entry);
    const bool has_mass = entry.has("mass_kg");
    if (has_mass && entry.has("density"))
      entry.existing_member("density").fail_with(
          "give either \"density\" or \"mass_kg\", not both");
    if (entry.has("inertia") && !has_mass)
      entry.existing_member("inertia").fail_with(
          "an explicit \"inertia\" needs an explicit \"mass_kg\" beside it");

    double density = kDefaultToolDensity;
    if (entry.has("density"))
      density =
          entry.existing_member("density").positive_number("expected a positive number (kg/m³)");
    Tool tool;
    tool.mass = mass_properties_from_density(geometry.mesh, density);
    if (!(tool.mass.mass_kg > 0) || !std::isfinite(tool.mass.mass_kg))
      entry.fail_with("the tool's geometry encloses no volume, so it has no mass");
    ContentHash hash;
    hash.add(geometry.content_hash);
    if (has_mass) {
      // Same distribution of mass, scaled to the given total.
      const double mass_kg =
          entry.existing_member("mass_kg").positive_number("expected a positive mass (kg)");
      tool.mass.inertia_about_com *= mass_kg / tool.mass.mass_kg;
      tool.mass.mass_kg = mass_kg;
      hash.add(" mass_kg ").add(exact_text(mass_kg));
      if (entry.has("inertia")) {
        tool.mass.inertia_about_com = read_inertia(entry.existing_member("inertia"));
        for (int i = 0; i < 9; ++i) hash.add(" ").add(exact_text(tool.mass.inertia_about_com(i)));
      }
    } else {
      hash.add(" density ").add(exact_text(density));
    }
    tool.mesh = std::move(geometry.mesh);
    tool.shape = geometry.shape;
    tool.content_hash = hash.hex();
    return tool;
  }

  // Each plugin file, relative to the scenario, must exist; it is hashed
  // with the scenario and returned as a path (a run loads it, as the plugin
  // policy allows).
  std::vector<ScenarioPlugin> read_plugins(const JsonField& field) {
    const std::size_t count =
        field.array_size("expected an array of plugin file paths (shared libraries)");
    std::vector<ScenarioPlugin> plugins;
    for (std::size_t i = 0; i < count; ++i) {
      const JsonField entry = field.element(i);
      const std::string path = existing_file(entry, "plugin");
      scenario_hash_.add(file_content_hash(path));
      plugins.push_back({path, entry.pointer()});
    }
    return plugins;
  }

  static std::vector<std::string> read_tags(const JsonField& field) {
    const char* const expected = "expected an array of distinct tags (e.g. [\"stress\"])";
    const std::size_t count = field.array_size(expected);
    std::vector<std::string> tags;
    for (std::size_t i = 0; i < count; ++i) {
      const JsonField tag = field.element(i);
      std::string text = tag.string(kSafeNameExpected);
      if (!is_file_name_safe(text)) tag.fail(kSafeNameExpected);
      if (std::find(tags.begin(), tags.end(), text) != tags.end())
        tag.fail("the tag \"" + text + "\" is given twice");
      tags.push_back(std::move(text));
    }
    return tags;
  }

  CouplingGains read_coupling(const JsonField& field) const {
    field.require_object("expected {\"k_t\", \"b_t\", \"k_r\", \"b_r\"}");
    field.reject_unknown_keys({"k_t", "b_t", "k_r", "b_r"});
    CouplingGains gains;
    if (field.has("k_t"))
      gains.k_t = field.existing_member("k_t").positive_number("expected a positive number (N/m)");
    if (field.has("b_t"))
      gains.b_t =
          field.existing_member("b_t").non_negative_number("expected a number >= 0 (N·s/m)");
    if (field.has("k_r"))
      gains.k_r =
          field.existing_member("k_r").positive_number("expected a positive number (N·m/rad)");
    if (field.has("b_r"))
      gains.b_r =
          field.existing_member("b_r").non_negative_number("expected a number >= 0 (N·m·s/rad)");
    return gains;
  }

  DeviceLimits read_device(const JsonField& field) const {
    field.require_object("expected {\"max_force_n\", \"max_torque_nm\"}");
    field.reject_unknown_keys({"max_force_n", "max_torque_nm"});
    DeviceLimits limits;
    if (field.has("max_force_n"))
      limits.max_force_n =
          field.existing_member("max_force_n").positive_number("expected a positive force (N)");
    if (field.has("max_torque_nm"))
      limits.max_torque_nm = field.existing_member("max_torque_nm")
                                 .positive_number("expected a positive torque (N·m)");
    return limits;
  }

  // The hand and device of closed-loop replay; a missing key keeps its
  // default (closed_loop_model.h).
  ClosedLoopModel read_closed_loop(const JsonField& field) const {
    field.require_object("expected {\"hand\": {...}, \"device\": {...}} (either may be left out)");
    field.reject_unknown_keys({"hand", "device"});
    ClosedLoopModel model;
    // key, unit, where the value goes, whether it must be > 0 (else >= 0).
    struct Setting {
      const char* key;
      const char* unit;
      double* value;
      bool positive;
    };
    const auto read_settings = [](const JsonField& block, std::initializer_list<Setting> settings) {
      block.require_object("expected an object of numbers");
      std::vector<std::string_view> keys;
      for (const Setting& setting : settings) keys.push_back(setting.key);
      block.reject_unknown_keys(keys);
      for (const Setting& setting : settings) {
        if (!block.has(setting.key)) continue;
        const JsonField value = block.existing_member(setting.key);
        *setting.value =
            setting.positive
                ? value.positive_number(std::string("expected a number > 0 (") + setting.unit + ")")
                : value.non_negative_number(std::string("expected a number >= 0 (") + setting.unit +
                                            ")");
      }
    };
    if (field.has("hand")) {
      HandModel& hand = model.hand;
      read_settings(field.existing_member("hand"),
                    {{"mass_kg", "kg", &hand.mass_kg, false},
                     {"inertia_kgm2", "kg·m²", &hand.inertia_kgm2, false},
                     {"k_t", "N/m", &hand.k_t, false},
                     {"b_t", "N·s/m", &hand.b_t, false},
                     {"k_r", "N·m/rad", &hand.k_r, false},
                     {"b_r", "N·m·s/rad", &hand.b_r, false}});
    }
    if (field.has("device")) {
      DeviceModel& device = model.device;
      read_settings(field.existing_member("device"),
                    {{"mass_kg", "kg", &device.mass_kg, true},
                     {"inertia_kgm2", "kg·m²", &device.inertia_kgm2, true},
                     {"b_t", "N·s/m", &device.b_t, false},
                     {"b_r", "N·m·s/rad", &device.b_r, false},
                     {"friction_n", "N", &device.friction_n, false},
                     {"friction_nm", "N·m", &device.friction_nm, false},
                     {"encoder_m", "m", &device.encoder_m, false},
                     {"encoder_rad", "rad", &device.encoder_rad, false},
                     {"velocity_filter_hz", "Hz", &device.velocity_filter_hz, false}});
    }
    if (field.has("device")) {
      const JsonField device = field.existing_member("device");
      for (const auto& [key, value, finest, unit] :
           {std::tuple{"encoder_m", model.device.encoder_m, kFinestEncoderM, "m"},
            std::tuple{"encoder_rad", model.device.encoder_rad, kFinestEncoderRad, "rad"}})
        if (value > 0 && value < finest) {
          std::ostringstream text;
          text << "expected 0 (exact) or a resolution of at least " << finest << " " << unit
               << ", got " << value << " (finer ones overflow the position counts)";
          device.existing_member(key).fail(text.str());
        }
    }
    if (!ClosedLoopDevice(model, 1 / kTicksPerSecond).well_defined())
      field.fail(
          "the hand and device give a motion too fast to integrate over a tick "
          "(stiffness or damping far too large for the masses)");
    return model;
  }

  // Whole ticks of the 1 kHz clock in a duration.
  int64_t read_duration_ticks(const JsonField& field) const {
    const std::string expected = "expected a duration in [0.001, 3600] s";
    const double seconds = field.number(expected);
    if (!(seconds >= 1 / kTicksPerSecond && seconds <= kMaxTraceDurationS)) field.fail(expected);
    return std::llround(seconds * kTicksPerSecond);
  }

  void read_trace(const JsonField& field, Scenario& scenario) {
    field.require_object("expected {\"generator\": NAME, ...} or {\"file\": PATH, ...}");
    const bool has_file = field.has("file");
    if (has_file == field.has("generator"))
      field.fail_with(has_file ? "give either \"file\" or \"generator\", not both"
                               : "missing; expected \"generator\": NAME or \"file\": PATH");
    if (has_file) {
      field.reject_unknown_keys({"file", "format", "duration_s", "units"});
      const JsonField file_field = field.existing_member("file");
      const std::string path = existing_file(file_field, "trace file");
      const std::string extension = std::filesystem::path(path).extension().string();
      std::string format = extension == ".tum" || extension == ".txt" ? "tum" : "csv";
      if (field.has("format")) format = field.existing_member("format").choice({"csv", "tum"});
      const int64_t ticks =
          field.has("duration_s") ? read_duration_ticks(field.existing_member("duration_s")) : 0;
      std::optional<TraceUnits> units;
      if (field.has("units")) {
        const JsonField units_field = field.existing_member("units");
        units = parse_trace_units(units_field.string(kTraceUnitsExpected));
        if (!units) units_field.fail(kTraceUnitsExpected);
      }
      try {
        Trace trace = read_trace_file(
            path, format == "tum" ? TraceFileFormat::kTum : TraceFileFormat::kHapticbenchCsv,
            units);
        scenario.trace_description =
            "file " + path + " (" + format + trace_reading_note(trace.info) + ")";
        for (const std::string& warning : trace_plausibility_warnings(trace))
          load_warnings_.push_back(file_field.pointer() + ": " + path + ": " + warning);
        scenario.trajectory = DeviceTrajectory::of_trace(std::move(trace), ticks);
        scenario_hash_.add(file_content_hash(path));
      } catch (const InputError& error) {
        // An error about the trace's samples is the trace file's.
        const InputError located =
            error.source().empty() ? InputError(path, error.location(), error.message()) : error;
        throw with_reference_note(located, path_, file_field.pointer());
      }
    } else {
      field.reject_unknown_keys({"generator", "duration_s", "seed", "params"});
      const JsonField name_field = field.existing_member("generator");
      const std::string name = name_field.string("expected a generator name");
      GeneratorRequest request;
      const int64_t ticks = read_duration_ticks(
          field.member("duration_s", "the trace's length in seconds, in [0.001, 3600]"));
      request.duration_s = static_cast<double>(ticks) / kTicksPerSecond;
      if (field.has("seed"))
        request.seed = static_cast<uint64_t>(field.existing_member("seed").integer(
            0, std::numeric_limits<int64_t>::max(), "expected a whole number >= 0"));
      request.params = ParamSet("/trace/params");
      if (field.has("params"))
        request.params =
            param_set_from_json(field.existing_member("params").json(), "/trace/params", path_);
      try {
        GeneratedTrace trace = make_generated_trace(name, request, name_field.pointer());
        scenario.trajectory = DeviceTrajectory(std::move(trace.source), ticks);
      } catch (const InputError& error) {
        throw with_default_source(error, path_);
      }
      scenario.trace_description =
          "generator " + name + " (seed " + std::to_string(request.seed) + ")";
    }
    if (scenario.trajectory.ticks() == 0)
      field.fail_with("the trace gives no samples on the 1 kHz clock");
  }

  std::vector<AlgorithmSpec> read_algorithms(const JsonField& field) const {
    const std::string expected = "expected a non-empty array of {\"name\", \"label\", \"params\"}";
    const std::size_t count = field.array_size(expected);
    if (count == 0) field.fail(expected);
    std::vector<AlgorithmSpec> specs;
    std::map<std::string, std::string> label_owner;  // label -> JSON pointer of its entry
    for (std::size_t i = 0; i < count; ++i) {
      const JsonField entry = field.element(i);
      entry.require_object("expected {\"name\", \"label\", \"params\"}");
      entry.reject_unknown_keys({"name", "label", "params"});
      AlgorithmSpec spec;
      spec.pointer = entry.pointer();
      const JsonField name = entry.member("name", "an algorithm name (hapticbench list)");
      spec.name = name.string("expected an algorithm name (hapticbench list names them)");
      if (spec.name.empty()) name.fail("expected an algorithm name (hapticbench list names them)");

      spec.label = spec.name;
      std::string label_pointer = name.pointer();
      if (entry.has("label")) {
        const JsonField label = entry.existing_member("label");
        spec.label = label.string(kSafeNameExpected);
        if (!is_file_name_safe(spec.label))
          label.fail(std::string(kSafeNameExpected) + " (it names output files)");
        label_pointer = label.pointer();
      }
      const auto [owner, inserted] = label_owner.emplace(spec.label, entry.pointer());
      if (!inserted)
        throw InputError(path_, label_pointer,
                         "duplicate label \"" + spec.label + "\" (also used by " + owner->second +
                             "); give each entry a distinct \"label\"");

      const std::string prefix = entry.pointer() + "/params";
      spec.params = ParamSet(prefix);
      spec.params_json = "{}";
      if (entry.has("params")) {
        const Json& params = entry.existing_member("params").json();
        spec.params = param_set_from_json(params, prefix, path_);
        spec.params_json = params.dump();
      }
      specs.push_back(std::move(spec));
    }
    return specs;
  }

  // The oracles test about area / spacing² tool surface samples every tick;
  // a spacing far below the tool's size would take hours and gigabytes
  // (1e-5 m on a 2 cm sphere ran past 120 s at 6.4 GB), so it is refused.
  // The tool's surface samples serve the oracles and the mesh force
  // reference alike: the limit holds whenever either may run.
  void check_oracle_sample_count(const Scenario& scenario) const {
    if (scenario.reference.oracle_backends.empty() && scenario.reference.force != "auto") return;
    const TriangleMesh& tool = scenario.context.tool.mesh;
    const double spacing = scenario.reference.sample_spacing_m > 0
                               ? scenario.reference.sample_spacing_m
                               : tool.bounds().diagonal().norm() / 40.0;
    double area = 0;
    for (const auto& [a, b, c] : tool.triangles)
      area +=
          0.5 *
          (tool.vertices[b] - tool.vertices[a]).cross(tool.vertices[c] - tool.vertices[a]).norm();
    const double estimate = area / (spacing * spacing);
    if (estimate > kMaxOracleSamples) {
      std::ostringstream text;
      text << "a spacing of " << spacing << " m gives about " << std::llround(estimate)
           << " tool surface samples (tool area " << area << " m²); at most "
           << static_cast<int64_t>(kMaxOracleSamples) << " are allowed: use a spacing of at least "
           << std::sqrt(area / kMaxOracleSamples) << " m";
      throw InputError(path_, "/reference/sample_spacing_m", text.str());
    }
  }

  ReferenceSpec read_reference(const JsonField& field) const {
    field.require_object(
        "expected {\"oracle\", \"exact_every\", \"analytic\", \"force\", \"force_every\", "
        "\"sample_spacing_m\"}");
    field.reject_unknown_keys(
        {"oracle", "exact_every", "analytic", "force", "force_every", "sample_spacing_m"});
    ReferenceSpec reference;
    if (field.has("oracle")) {
      std::vector<std::string_view> choices = {"none"};
      for (const OracleBackendEntry& backend : hb::oracle_backends())
        choices.push_back(backend.name);
      // "all": every backend; "both", its name from when there were two, still reads so.
      choices.push_back("all");
      choices.push_back("both");
      reference.oracle = field.existing_member("oracle").choice(choices);
      const bool all = reference.oracle == "all" || reference.oracle == "both";
      for (const OracleBackendEntry& backend : hb::oracle_backends())
        if (all || reference.oracle == backend.name)
          reference.oracle_backends.emplace_back(backend.name);
    }
    if (field.has("exact_every"))
      reference.exact_every = field.existing_member("exact_every")
                                  .integer(1, std::numeric_limits<int64_t>::max(),
                                           "expected a whole number of ticks >= 1");
    if (field.has("analytic"))
      reference.analytic = field.existing_member("analytic").choice({"auto", "none"});
    if (field.has("force"))
      reference.force = field.existing_member("force").choice({"auto", "none"});
    if (field.has("force_every"))
      reference.force_every = field.existing_member("force_every")
                                  .integer(1, std::numeric_limits<int64_t>::max(),
                                           "expected a whole number of ticks >= 1");
    if (field.has("sample_spacing_m"))
      reference.sample_spacing_m = field.existing_member("sample_spacing_m")
                                       .positive_number("expected a positive spacing in metres");
    return reference;
  }

  std::vector<Budget> read_budgets(const JsonField& field) {
    field.require_object("expected an object {budget name: limit}");
    std::vector<std::string_view> names;
    for (const std::string& name : known_budget_names()) names.emplace_back(name);
    for (const RenamedBudget& renamed : kRenamedBudgets) names.push_back(renamed.old_name);
    field.reject_unknown_keys(names, "budget");
    std::vector<Budget> budgets;
    for (const auto& item : field.json().items()) {
      const JsonField entry = field.existing_member(item.key());
      double limit = entry.number("expected the budget's limit, a finite number");
      std::string name = item.key();
      for (const RenamedBudget& renamed : kRenamedBudgets)
        if (name == renamed.old_name) {
          // Read in the old unit, kept in the new one; the file should say so.
          limit *= renamed.scale;
          name = renamed.new_name;
          std::ostringstream text;
          text << entry.pointer() << ": the budget " << renamed.old_name << " is now " << name
               << " (one unit per quantity: the console's and the report's); read as \"" << name
               << "\": " << limit;
          load_warnings_.push_back(text.str());
        }
      for (const Budget& earlier : budgets)
        if (earlier.name == name)
          entry.fail_with("the budget " + name + " is given twice (under its old name too)");
      budgets.push_back({name, limit});
    }
    return budgets;
  }

  // Settings that run but measure less than they seem to.
  static std::vector<std::string> measurement_warnings(const JsonField& root,
                                                       const Scenario& scenario) {
    std::vector<std::string> warnings;
    if (root.existing_member("tool").has("mesh"))
      for (std::size_t i = 0; i < scenario.algorithms.size(); ++i)
        if (scenario.algorithms[i].name == "god_object_3dof")
          warnings.push_back("/algorithms/" + std::to_string(i) + ": " +
                             scenario.algorithms[i].label +
                             " (god_object_3dof) renders the tool's origin only: the mesh tool's "
                             "surface never touches the scene, so its contacts and forces are "
                             "those of a point");
    const JsonField scene = root.existing_member("scene");
    bool mesh_scene = false;
    for (std::size_t i = 0; i < scenario.context.scene.size(); ++i)
      mesh_scene = mesh_scene || scene.element(i).has("mesh");
    if (mesh_scene && !root.has("reference"))
      warnings.push_back(
          "/reference: absent, and the scene has meshes: no penetration truth (the oracle is off "
          "by default and the closed forms cover primitives only); add \"reference\": "
          "{\"oracle\": \"embree\"}");
    return warnings;
  }

  // {label: why}: every key a label of the scenario's algorithms, every
  // value a non-empty reason.
  std::map<std::string, std::string> read_expected_unstable(
      const JsonField& field, const std::vector<AlgorithmSpec>& algorithms) const {
    field.require_object("expected an object {label: why its instability is expected}");
    std::vector<std::string_view> labels;
    for (const AlgorithmSpec& spec : algorithms) labels.emplace_back(spec.label);
    field.reject_unknown_keys(labels, "label");
    std::map<std::string, std::string> expected;
    for (const auto& item : field.json().items()) {
      const std::string why = field.existing_member(item.key())
                                  .string(
                                      "expected a text saying why this label's instability "
                                      "is expected");
      if (why.empty())
        field.existing_member(item.key())
            .fail("expected a text saying why this label's instability is expected");
      expected[item.key()] = why;
    }
    return expected;
  }

  std::string path_;
  std::filesystem::path directory_;
  // warnings: budgets under their old names, a trace implausible for a desk device
  std::vector<std::string> load_warnings_;
  ContentHash scenario_hash_;  // scenario bytes, then every named file's hash in reading order
};

}  // namespace

const std::vector<std::string>& known_budget_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> budgets;
    for (const MetricDefinition& metric : metric_table())
      if (metric.budget) budgets.emplace_back(metric.name);
    return budgets;
  }();
  return names;
}

Scenario load_scenario(const std::string& path) {
  return load_scenario_json(read_regular_file(path, "a scenario file (.json)"), path,
                            std::filesystem::path(path).parent_path());
}

Scenario load_scenario_json(const std::string& json_text, const std::string& source_path,
                            const std::filesystem::path& base_dir) {
  return ScenarioReader(source_path, base_dir).read(json_text);
}

std::span<const PlausibleRange> plausible_ranges() { return kPlausibleRanges; }

}  // namespace hb
