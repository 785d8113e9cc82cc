// hapticbench init FILE.json [--scene SHAPE|MESH] [--tool SHAPE|MESH]
// A scenario to start from: a scene object with its top face at z = 0, a
// tool, a press aimed at the scene's top, the algorithms that can render
// that pair, a reference and budgets, each section explained in comments.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "algorithms/core/replacing_file.h"
#include "hapticbench/input_error.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/mesh_io/mesh_io.h"
#include "harness/sweep/job_name.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

const std::string kInitUsage =
    "usage: hapticbench init FILE.json [--scene SHAPE|MESH] [--tool SHAPE|MESH]\n"
    "  writes a scenario to start from, explained in // comments: the scene object's\n"
    "  top at z = 0, the tool above it, a press into it, the algorithms that render the\n"
    "  pair, the reference and budgets. Never overwrites a file.\n"
    "  --scene  box (default), sphere, capsule, box_with_hole, or a mesh file\n"
    "           (.off/.obj/.stl/.ply, in metres: set \"scale\" otherwise)\n"
    "  --tool   sphere (default), box, capsule, or a mesh file\n";

/// A scene object or tool: a primitive by name or a mesh file.
struct Part {
  std::string json;  ///< the geometry's JSON: "shape": {...} or "mesh": "..."
  double top_m = 0;  ///< highest point above the part's own origin (m, z)
  double low_m = 0;  ///< lowest point below the part's own origin (m, z, >= 0 below)
  double centre_x = 0, centre_y = 0;  ///< middle of its extent in x and y (m)
  double press_x = 0;                 ///< where on the scene the press aims, x from the middle (m)
  bool mesh = false;
  double extent_m = 0;                  ///< largest side of its bounds (m)
  double scale = 1;                     ///< mesh: metres per file unit chosen
  double file_extent = 0;               ///< mesh: largest side of its bounds in file units
  double half_x = 0, half_y = 0;        ///< half its extent in x and y (m)
  std::optional<TriangleMesh> surface;  ///< a mesh scene, scaled: where the press lands
  std::vector<Vec3> points;  ///< a mesh tool, scaled: up to 500 of its vertices (tool frame)
};

std::string number(double value) {
  std::ostringstream text;
  text.precision(6);
  text << value;
  return text.str();
}

/// The default primitives: a 20 x 20 x 2 cm block, a 5 cm ball, an upright
/// capsule, a plate with a 3 cm hole; tools 1 cm across or so.
Part primitive(const std::string& name, bool tool) {
  Part part;
  if (name == "box") {
    const double side = tool ? 0.02 : 0.2, height = tool ? 0.02 : 0.02;
    part.json = "\"shape\": { \"type\": \"box\", \"size\": [" + number(side) + ", " + number(side) +
                ", " + number(height) + "] }";
    part.top_m = part.low_m = height / 2;
  } else if (name == "sphere") {
    const double radius = tool ? 0.01 : 0.05;
    part.json = "\"shape\": { \"type\": \"sphere\", \"radius\": " + number(radius) +
                ", \"subdivisions\": 3 }";
    part.top_m = part.low_m = radius;
  } else if (name == "capsule") {
    const double radius = tool ? 0.005 : 0.02, length = tool ? 0.03 : 0.1;
    part.json = "\"shape\": { \"type\": \"capsule\", \"radius\": " + number(radius) +
                ", \"length\": " + number(length) + " }";
    part.top_m = part.low_m = length / 2 + radius;
  } else if (name == "box_with_hole" && !tool) {
    part.json =
        "\"shape\": { \"type\": \"box_with_hole\", \"size\": [0.1, 0.1, 0.02], \"hole_size\": "
        "[0.03, 0.03] }";
    part.top_m = part.low_m = 0.01;
    part.press_x = 0.035;  // beside the hole, on the plate
  } else {
    throw InputError("", tool ? "--tool" : "--scene",
                     "expected " +
                         std::string(tool ? "sphere, box, capsule"
                                          : "box, sphere, capsule, "
                                            "box_with_hole") +
                         " or a mesh file, got \"" + name + "\"");
  }
  return part;
}

/// The highest point of the mesh on the vertical line through (x, y), or
/// nullopt when the line misses it.
std::optional<double> top_at(const TriangleMesh& mesh, double x, double y) {
  std::optional<double> top;
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    // Barycentric coordinates of (x, y) in the triangle's projection on z = 0.
    const double det = (b.y() - c.y()) * (a.x() - c.x()) + (c.x() - b.x()) * (a.y() - c.y());
    if (std::abs(det) < 1e-18) continue;  // seen edge-on from above
    const double u = ((b.y() - c.y()) * (x - c.x()) + (c.x() - b.x()) * (y - c.y())) / det;
    const double v = ((c.y() - a.y()) * (x - c.x()) + (a.x() - c.x()) * (y - c.y())) / det;
    if (u < 0 || v < 0 || u + v > 1) continue;
    const double z = u * a.z() + v * b.z() + (1 - u - v) * c.z();
    if (!top || z > *top) top = z;
  }
  return top;
}

/// A mesh scene object or tool. Meshes come in any unit: one whose bounds
/// are far from the size of such a part (a scene of 5 cm to 2 m, a tool of
/// 5 mm to 20 cm) is scaled to `typical_m` across, and the scale is said.
Part mesh_part(const std::string& path, const fs::path& scenario_folder, bool tool) {
  const double typical_m = tool ? 0.03 : 0.2;
  const double smallest_m = tool ? 0.005 : 0.05, largest_m = tool ? 0.2 : 2.0;
  TriangleMesh mesh = read_mesh_file(path);
  const double file_extent = mesh.bounds().sizes().maxCoeff();
  Part part;
  part.mesh = true;
  part.file_extent = file_extent;
  if (file_extent > 0 && (file_extent < smallest_m || file_extent > largest_m)) {
    part.scale = typical_m / file_extent;
    for (Vec3& vertex : mesh.vertices) vertex = part.scale * vertex;  // as the reader scales
  }
  const Eigen::AlignedBox3d bounds = mesh.bounds();
  // Relative to the scenario when the mesh is in its folder or below.
  const fs::path absolute = fs::absolute(path).lexically_normal();
  const fs::path relative = absolute.lexically_relative(fs::absolute(scenario_folder));
  const bool below = !relative.empty() && *relative.begin() != "..";
  part.json = "\"mesh\": \"" + (below ? relative : absolute).generic_string() +
              "\", \"scale\": " + number(part.scale);
  part.centre_x = bounds.center().x();
  part.centre_y = bounds.center().y();
  // A scene is pressed where the vertical through its middle meets it.
  part.top_m = top_at(mesh, part.centre_x, part.centre_y).value_or(bounds.max().z());
  part.low_m = -bounds.min().z();
  part.extent_m = bounds.sizes().maxCoeff();
  part.half_x = bounds.sizes().x() / 2;
  part.half_y = bounds.sizes().y() / 2;
  if (!tool) part.surface = mesh;
  constexpr std::size_t kToolPoints = 500;
  const std::size_t stride = mesh.vertices.size() / kToolPoints + 1;
  if (tool)
    for (std::size_t i = 0; i < mesh.vertices.size(); i += stride)
      part.points.push_back(mesh.vertices[i]);
  return part;
}

bool is_mesh_path(const std::string& value) {
  const std::string extension = fs::path(value).extension().string();
  return extension == ".off" || extension == ".obj" || extension == ".stl" || extension == ".ply";
}

struct InitArguments {
  std::string file;
  std::string scene = "box", tool = "sphere";
};

InitArguments parse_init_arguments(const std::vector<std::string>& args) {
  InitArguments parsed;
  for (std::size_t i = 0; i < args.size(); ++i) {
    check_help(args[i]);
    if (args[i] == "--scene" || args[i] == "--tool") {
      std::string& part = args[i] == "--scene" ? parsed.scene : parsed.tool;
      part = option_value(args, i);
    } else if (args[i].rfind("--", 0) == 0)
      throw UsageError{"unknown option " + args[i]};
    else if (parsed.file.empty())
      parsed.file = args[i];
    else
      throw UsageError{"one scenario file at a time"};
  }
  if (parsed.file.empty()) throw UsageError{"no scenario file given"};
  if (fs::path(parsed.file).extension() != ".json")
    throw UsageError{"the scenario file's name ends in .json, got \"" + parsed.file + "\""};
  return parsed;
}

std::string scenario_text(const std::string& name, const Part& scene, const Part& tool,
                          const std::string& scene_name, const std::string& tool_name) {
  const bool primitives = !scene.mesh && !tool.mesh;
  // The press starts 1 cm above the scene's top, goes down to touch it and
  // 2 mm past it; the tool frame sits tool.low_m above the tool's lowest point.
  // Over a mesh the press starts 1 cm above the first point it would touch:
  // the least height of the tool's lowest points (its vertices, or its
  // bottom over its footprint) above the surface under them, with the tool
  // frame at z = 0 over the scene's middle.
  double start_z = tool.low_m + 0.01;
  if (scene.surface) {
    std::vector<Vec3> points = tool.points;
    constexpr int kSamples = 7;  // per side of a primitive tool's footprint
    if (points.empty())
      for (int i = 0; i < kSamples; ++i)
        for (int j = 0; j < kSamples; ++j)
          points.emplace_back((2.0 * i / (kSamples - 1) - 1) * tool.half_x,
                              (2.0 * j / (kSamples - 1) - 1) * tool.half_y, -tool.low_m);
    std::optional<double> least;
    for (const Vec3& point : points) {
      const std::optional<double> top =
          top_at(*scene.surface, scene.centre_x + point.x(), scene.centre_y + point.y());
      if (top) least = std::min(least.value_or(point.z()), point.z() - (*top - scene.top_m));
    }
    if (least) start_z = 0.01 - *least;
  }
  std::ostringstream out;
  out << "// A scenario made by `hapticbench init` (" << scene_name << " scene, " << tool_name
      << " tool). Edit it, check it\n"
      << "// with `hapticbench validate " << name << ".json` (it prints how close the trace\n"
      << "// brings the tool to the scene), then `hapticbench run " << name << ".json`.\n"
      << "// Every key: docs/scenario-format.md. Units: m, kg, s, N; quaternions [w, x, y, z].\n"
      << "{\n"
      << "  \"name\": \"" << name << "\",\n"
      << "  \"description\": \"A " << tool_name << " pressed 2 mm into a " << scene_name
      << ".\",\n\n"
      << "  // The scene: objects placed by \"pose\" (object frame to world). This one's top\n"
      << "  // is at z = 0, its middle over the origin.";
  if (scene.mesh)
    out << " A mesh must be closed and outward\n"
        << "  // oriented (or marked \"distance_only\": true); \"scale\" is metres per file unit.";
  if (scene.scale != 1)
    out << "\n  // Its bounds span " << number(scene.file_extent) << " file units: scaled to "
        << number(scene.extent_m) << " m across; give the file's own unit\n"
        << "  // instead (\"scale\": 0.001 for mm) and move the pose and the trace to match.";
  out << "\n  \"scene\": [\n    { " << scene.json << ",\n      \"pose\": { \"p\": ["
      << number(-scene.centre_x) << ", " << number(-scene.centre_y) << ", " << number(-scene.top_m)
      << "], \"q\": [1, 0, 0, 0] } }\n  ],\n\n"
      << "  // The tool the device holds, in its own frame (the trace moves that frame);\n"
      << "  // its mass from the density (kg/m³) or \"mass_kg\".\n"
      << (tool.scale != 1 ? "  // Its bounds span " + number(tool.file_extent) +
                                " file units: scaled to " + number(tool.extent_m) +
                                " m across, a hand-held tool; give the\n  // file's own "
                                "unit instead (\"scale\": 0.001 for mm).\n"
                          : std::string())
      << "  \"tool\": { " << tool.json << ", \"density\": 1000 },\n\n"
      << "  // The device's motion: a generator (traces/README.md; `hapticbench list`) or a\n"
      << "  // recorded file: { \"file\": \"my_log.csv\", \"units\": \"mm\" }.\n"
      << "  \"trace\": { \"generator\": \"press\", \"duration_s\": 2.0, \"seed\": 1,\n"
      << "             \"params\": { \"start\": [" << number(scene.press_x) << ", 0, "
      << number(start_z)
      << "], \"axis\": [0, 0, -1], \"surface_distance\": 0.01, \"depth\": 0.002 } },\n\n"
      << "  // The virtual coupling between device and proxy (N/m, N·s/m, N·m/rad, N·m·s/rad)\n"
      << "  // and what the device can display.\n"
      << "  \"coupling\": { \"k_t\": 2000, \"b_t\": 5, \"k_r\": 5, \"b_r\": 0.05 },\n"
      << "  \"device\": { \"max_force_n\": 20, \"max_torque_nm\": 1 },\n\n"
      << "  // The algorithms to compare (`hapticbench list --params` gives every parameter).\n"
      << "  // coupling_only renders no contact: the baseline every other one should beat.\n"
      << "  \"algorithms\": [\n"
      << "    { \"name\": \"coupling_only\", \"label\": \"coupling_only\" },\n";
  if (primitives) out << "    { \"name\": \"penalty_analytic\", \"label\": \"penalty\" },\n";
  out << "    { \"name\": \"god_object\", \"label\": \"god_object\" },\n"
      << "    { \"name\": \"constrained_dynamics\", \"label\": \"constrained_dynamics\" },\n"
      << "    { \"name\": \"voxmap_pointshell\", \"label\": \"voxmap_pointshell\" }\n"
      << "  ],\n"
      << "  \"expected_unstable\": { \"coupling_only\": \"renders no contact: the tool passes "
         "through\" },\n\n"
      << "  // Ground truth: the Embree oracle measures penetration on meshes; on primitives\n"
      << "  // the analytic reference gives the ideal force too (docs/ground-truth.md).\n"
      << "  \"reference\": { \"oracle\": \"embree\", \"exact_every\": 10, \"analytic\": \"auto\" "
         "},\n\n"
      << "  // What a run must meet (docs/metric-table.md); a failed budget exits 1.\n"
      << "  \"budgets\": { \"nonfinite\": 0, \"tick_p99_us\": 1000 }\n"
      << "}\n";
  return out.str();
}

}  // namespace

int init_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const std::optional<InitArguments> parsed =
      parse_command_line([&] { return parse_init_arguments(args); }, kInitUsage, exit_code);
  if (!parsed) return exit_code;
  const fs::path file(parsed->file);
  const std::string name = file.stem().string();
  if (!is_safe_folder_name(name))
    throw InputError(parsed->file, "",
                     "the file's name (without .json) names the scenario and its run folder: "
                     "letters, digits, '_', '.', '-', '='");
  std::error_code error;
  if (fs::exists(fs::symlink_status(file, error)))
    throw InputError(parsed->file, "", "exists already; init never overwrites a file");
  const fs::path folder = file.parent_path().empty() ? fs::path(".") : file.parent_path();
  const Part scene = is_mesh_path(parsed->scene) ? mesh_part(parsed->scene, folder, false)
                                                 : primitive(parsed->scene, /*tool=*/false);
  const Part tool = is_mesh_path(parsed->tool) ? mesh_part(parsed->tool, folder, true)
                                               : primitive(parsed->tool, /*tool=*/true);
  const std::string scene_name =
      scene.mesh ? fs::path(parsed->scene).filename().string() : parsed->scene;
  const std::string tool_name =
      tool.mesh ? fs::path(parsed->tool).filename().string() : parsed->tool;
  TemporarySibling written(file);
  written.write(scenario_text(name, scene, tool, scene_name, tool_name));
  written.commit();
  std::cout << "wrote " << parsed->file << ": a " << tool_name << " pressed into a " << scene_name
            << "; next: hapticbench validate " << parsed->file << "\n";
  return kExitOk;
}

}  // namespace hb
