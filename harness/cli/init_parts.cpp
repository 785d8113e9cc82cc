// The scene objects and tools of `hapticbench init` (init_scenario.h).
#include <algorithm>
#include <cmath>
#include <sstream>

#include "hapticbench/input_error.h"
#include "harness/cli/init_scenario.h"
#include "harness/mesh_io/mesh_io.h"

namespace hb {

namespace fs = std::filesystem;

std::string init_number(double value) {
  std::ostringstream text;
  text.precision(6);
  text << value;
  return text.str();
}

InitPart init_primitive(const std::string& name, bool tool) {
  InitPart part;
  if (name == "box") {
    const double side = tool ? 0.02 : 0.2, height = tool ? 0.02 : 0.02;
    part.json = "\"shape\": { \"type\": \"box\", \"size\": [" + init_number(side) + ", " +
                init_number(side) + ", " + init_number(height) + "] }";
    part.top_m = part.low_m = height / 2;
  } else if (name == "sphere") {
    const double radius = tool ? 0.01 : 0.05;
    part.json = "\"shape\": { \"type\": \"sphere\", \"radius\": " + init_number(radius) +
                ", \"subdivisions\": 3 }";
    part.top_m = part.low_m = radius;
  } else if (name == "capsule") {
    const double radius = tool ? 0.005 : 0.02, length = tool ? 0.03 : 0.1;
    part.json = "\"shape\": { \"type\": \"capsule\", \"radius\": " + init_number(radius) +
                ", \"length\": " + init_number(length) + " }";
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

std::optional<double> mesh_top_at(const TriangleMesh& mesh, double x, double y) {
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

InitPart init_mesh_part(const std::string& path, const std::filesystem::path& scenario_folder,
                        bool tool) {
  const double typical_m = tool ? 0.03 : 0.2;
  const double smallest_m = tool ? 0.005 : 0.05, largest_m = tool ? 0.2 : 2.0;
  TriangleMesh mesh = read_mesh_file(path);
  const double file_extent = mesh.bounds().sizes().maxCoeff();
  InitPart part;
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
              "\", \"scale\": " + init_number(part.scale);
  part.centre_x = bounds.center().x();
  part.centre_y = bounds.center().y();
  // A scene is pressed where the vertical through its middle meets it.
  part.top_m = mesh_top_at(mesh, part.centre_x, part.centre_y).value_or(bounds.max().z());
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

}  // namespace hb
