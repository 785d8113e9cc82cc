// Scene objects and the tool of a scenario: mesh files or primitive shapes,
// their poses, and the tool's mass and inertia. Every mesh file read is
// hashed into the scenario's content hash.
#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "hapticbench/content_hash.h"
#include "hapticbench/input_error.h"
#include "hapticbench/mass_properties.h"
#include "hapticbench/shapes.h"
#include "hapticbench/triangle_mesh.h"
#include "harness/mesh_io/mesh_io.h"
#include "harness/scenario/input_error_context.h"
#include "harness/scenario/scenario_reader.h"

namespace hb::scenario_detail {

namespace {

constexpr double kDefaultToolDensity = 1000;  // kg/m³, water
constexpr double kUnitQuaternionTolerance = 1e-6;
constexpr int64_t kMaxSubdivisions = 6;

/// Whether the mesh passes the checks of a distance-only surface.
bool is_valid_surface(const TriangleMesh& mesh, const std::string& path) {
  try {
    require_valid_mesh(mesh, path, MeshRequirement::kSurface);
    return true;
  } catch (const InputError&) {
    return false;
  }
}

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

}  // namespace

Pose ScenarioReader::read_pose(const JsonField& field) const {
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

Shape ScenarioReader::read_shape(const JsonField& field) const {
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
      shape.subdivisions =
          static_cast<int>(field.existing_member("subdivisions")
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
Geometry ScenarioReader::read_geometry(const JsonField& entry, MeshRequirement requirement) {
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
  geometry.content_hash = ContentHash().add(file_hash).add(" scale ").add(exact_text(scale)).hex();
  geometry.description = std::filesystem::path(path).filename().string();
  return geometry;
}

SceneObject ScenarioReader::read_scene_object(const JsonField& entry, std::size_t index) {
  entry.require_object("expected a scene object {\"mesh\"|\"shape\", \"pose\", \"name\"}");
  entry.reject_unknown_keys(
      {"name", "mesh", "scale", "shape", "pose", "distance_only", "friction"});
  SceneObject object;
  // "distance_only": true admits an open or self-intersecting mesh, for
  // which ground truth can give distances but not inside/outside.
  if (entry.has("distance_only"))
    object.distance_only = entry.existing_member("distance_only").boolean("expected true or false");
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

Mat3 ScenarioReader::read_inertia(const JsonField& field) const {
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

Tool ScenarioReader::read_tool(const JsonField& entry) {
  entry.require_object("expected the tool: {\"shape\"|\"mesh\", \"density\"|\"mass_kg\"}");
  entry.reject_unknown_keys({"mesh", "scale", "shape", "density", "mass_kg", "inertia"});
  Geometry geometry = read_geometry(entry);
  const bool has_mass = entry.has("mass_kg");
  if (has_mass && entry.has("density"))
    entry.existing_member("density").fail_with("give either \"density\" or \"mass_kg\", not both");
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

}  // namespace hb::scenario_detail
