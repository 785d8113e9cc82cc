// The scenario reader behind load_scenario (scenario.h), private to
// harness/scenario/: one ScenarioReader per load reads the sections of a
// scenario file in a fixed order (scenario.cpp says what it guarantees).
// Its member functions are defined by section: the root in scenario.cpp,
// scene objects and the tool in scenario_geometry.cpp, the trace in
// scenario_trace.cpp, the remaining settings in scenario_settings.cpp, and
// the whole-scenario checks and warnings in scenario_checks.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "hapticbench/content_hash.h"
#include "hapticbench/shapes.h"
#include "hapticbench/triangle_mesh.h"
#include "harness/scenario/json_fields.h"
#include "harness/scenario/scenario.h"

namespace hb::scenario_detail {

using Json = nlohmann::ordered_json;

inline constexpr double kTicksPerSecond = 1000;

inline constexpr const char* kSafeNameExpected =
    "expected a non-empty string of letters, digits, '_', '.', '-' and '='";

// Names and labels become folder and file names (run folder, ticks_<label>.csv).
// '=' is there for sweep jobs, named "<scenario>__<key>=<value>__...".
bool is_file_name_safe(const std::string& name);

/// Settings outside their plausible range (plausible_ranges()), as warnings.
std::vector<std::string> plausibility_warnings(const Scenario& scenario);

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

  Scenario read(const std::string& bytes);

 private:
  // Files the scenario names (scenario.cpp).
  std::string resolve(const std::string& relative) const;
  std::string existing_file(const JsonField& field, const std::string& what) const;

  // Scene objects and the tool (scenario_geometry.cpp).
  Pose read_pose(const JsonField& field) const;
  Shape read_shape(const JsonField& field) const;
  Geometry read_geometry(const JsonField& entry,
                         MeshRequirement requirement = MeshRequirement::kClosedSolid);
  SceneObject read_scene_object(const JsonField& entry, std::size_t index);
  Mat3 read_inertia(const JsonField& field) const;
  Tool read_tool(const JsonField& entry);

  // The trace (scenario_trace.cpp).
  int64_t read_duration_ticks(const JsonField& field) const;
  void read_trace(const JsonField& field, Scenario& scenario);

  // Tags, plugins, algorithms, reference, budgets, expected_unstable,
  // coupling, device, closed loop (scenario_settings.cpp).
  static std::vector<std::string> read_tags(const JsonField& field);
  std::vector<ScenarioPlugin> read_plugins(const JsonField& field);
  std::vector<AlgorithmSpec> read_algorithms(const JsonField& field) const;
  ReferenceSpec read_reference(const JsonField& field) const;
  std::vector<Budget> read_budgets(const JsonField& field);
  std::map<std::string, std::string> read_expected_unstable(
      const JsonField& field, const std::vector<AlgorithmSpec>& algorithms) const;
  CouplingGains read_coupling(const JsonField& field) const;
  DeviceLimits read_device(const JsonField& field) const;
  ClosedLoopModel read_closed_loop(const JsonField& field) const;

  // Checks of the scenario as a whole (scenario_checks.cpp).
  void check_oracle_sample_count(const Scenario& scenario) const;
  static std::vector<std::string> measurement_warnings(const JsonField& root,
                                                       const Scenario& scenario);

  std::string path_;
  std::filesystem::path directory_;
  // warnings: budgets under their old names, a trace implausible for a desk device
  std::vector<std::string> load_warnings_;
  ContentHash scenario_hash_;  // scenario bytes, then every named file's hash in reading order
};

}  // namespace hb::scenario_detail
