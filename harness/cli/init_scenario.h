// The scenario `hapticbench init` writes: the scene object and the tool it
// is made of (a primitive by name or a mesh file), placed so that a press
// reaches the scene's top, and the scenario's text, each section explained
// in comments.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "hapticbench/triangle_mesh.h"

namespace hb {

/// A scene object or tool: a primitive by name or a mesh file.
struct InitPart {
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

/// `value` with up to 6 significant digits, as the scenario shows numbers.
std::string init_number(double value);

/// The default primitives: a 20 x 20 x 2 cm block, a 5 cm ball, an upright
/// capsule, a plate with a 3 cm hole; tools 1 cm across or so. Throws
/// InputError naming --scene or --tool for another name.
InitPart init_primitive(const std::string& name, bool tool);

/// The highest point of the mesh on the vertical line through (x, y), or
/// nullopt when the line misses it.
std::optional<double> mesh_top_at(const TriangleMesh& mesh, double x, double y);

/// A mesh scene object or tool. Meshes come in any unit: one whose bounds
/// are far from the size of such a part (a scene of 5 cm to 2 m, a tool of
/// 5 mm to 20 cm) is scaled to a typical size across, and the scale is said.
InitPart init_mesh_part(const std::string& path, const std::filesystem::path& scenario_folder,
                        bool tool);

/// Whether `value` names a mesh file (.off, .obj, .stl, .ply) rather than a primitive.
bool is_mesh_path(const std::string& value);

/// The scenario file's text: `name` (its file's stem), the scene object and
/// the tool, as `scene_name` and `tool_name` call them.
std::string init_scenario_text(const std::string& name, const InitPart& scene, const InitPart& tool,
                               const std::string& scene_name, const std::string& tool_name);

}  // namespace hb
