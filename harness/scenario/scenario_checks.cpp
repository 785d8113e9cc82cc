// Checks of a scenario as a whole, once every section is read: the cost of
// the oracles' tool surface samples (an error), and settings that are
// implausible or measure less than they seem to (warnings).
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "hapticbench/input_error.h"
#include "hapticbench/triangle_mesh.h"
#include "harness/scenario/scenario_reader.h"

namespace hb::scenario_detail {

namespace {

constexpr double kMaxOracleSamples = 1e6;  ///< tool surface samples the oracles may test per tick

std::string range_warning(const PlausibleRange& range, double value) {
  std::ostringstream text;
  text << range.pointer << ": " << value << " " << range.unit << " is outside the plausible range ["
       << range.low << ", " << range.high << "] " << range.unit << " (" << range.why << ")";
  return text.str();
}

}  // namespace

std::vector<std::string> plausibility_warnings(const Scenario& scenario) {
  // A device without limits (the default when "device" is not given) is
  // not a setting to warn about.
  const DeviceLimits unlimited;
  std::vector<std::string> warnings;
  for (const PlausibleRange& range : plausible_ranges()) {
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

// The oracles test about area / spacing² tool surface samples every tick;
// a spacing far below the tool's size would take hours and gigabytes
// (1e-5 m on a 2 cm sphere ran past 120 s at 6.4 GB), so it is refused.
// The tool's surface samples serve the oracles and the mesh force
// reference alike: the limit holds whenever either may run.
void ScenarioReader::check_oracle_sample_count(const Scenario& scenario) const {
  if (scenario.reference.oracle_backends.empty() && scenario.reference.force != "auto") return;
  const TriangleMesh& tool = scenario.context.tool.mesh;
  const double spacing = scenario.reference.sample_spacing_m > 0
                             ? scenario.reference.sample_spacing_m
                             : tool.bounds().diagonal().norm() / 40.0;
  double area = 0;
  for (const auto& [a, b, c] : tool.triangles)
    area += 0.5 *
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

// Settings that run but measure less than they seem to.
std::vector<std::string> ScenarioReader::measurement_warnings(const JsonField& root,
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

}  // namespace hb::scenario_detail
