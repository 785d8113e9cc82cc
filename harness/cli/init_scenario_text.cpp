// The text of the scenario `hapticbench init` writes (init_scenario.h).
#include <algorithm>
#include <sstream>

#include "harness/cli/init_scenario.h"

namespace hb {

std::string init_scenario_text(const std::string& name, const InitPart& scene, const InitPart& tool,
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
          mesh_top_at(*scene.surface, scene.centre_x + point.x(), scene.centre_y + point.y());
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
    out << "\n  // Its bounds span " << init_number(scene.file_extent) << " file units: scaled to "
        << init_number(scene.extent_m) << " m across; give the file's own unit\n"
        << "  // instead (\"scale\": 0.001 for mm) and move the pose and the trace to match.";
  out << "\n  \"scene\": [\n    { " << scene.json << ",\n      \"pose\": { \"p\": ["
      << init_number(-scene.centre_x) << ", " << init_number(-scene.centre_y) << ", "
      << init_number(-scene.top_m) << "], \"q\": [1, 0, 0, 0] } }\n  ],\n\n"
      << "  // The tool the device holds, in its own frame (the trace moves that frame);\n"
      << "  // its mass from the density (kg/m³) or \"mass_kg\".\n"
      << (tool.scale != 1 ? "  // Its bounds span " + init_number(tool.file_extent) +
                                " file units: scaled to " + init_number(tool.extent_m) +
                                " m across, a hand-held tool; give the\n  // file's own "
                                "unit instead (\"scale\": 0.001 for mm).\n"
                          : std::string())
      << "  \"tool\": { " << tool.json << ", \"density\": 1000 },\n\n"
      << "  // The device's motion: a generator (traces/README.md; `hapticbench list`) or a\n"
      << "  // recorded file: { \"file\": \"my_log.csv\", \"units\": \"mm\" }.\n"
      << "  \"trace\": { \"generator\": \"press\", \"duration_s\": 2.0, \"seed\": 1,\n"
      << "             \"params\": { \"start\": [" << init_number(scene.press_x) << ", 0, "
      << init_number(start_z)
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

}  // namespace hb
