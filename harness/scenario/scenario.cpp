// Scenario JSON (DESIGN.md, "Formats -> Scenario JSON"): the keys read here
// are a contract. Every rejection names the file, the JSON pointer and what
// was expected; unknown keys are errors so that a typo never silently falls
// back to a default. Quaternions are written [qw, qx, qy, qz].
#include "harness/scenario/scenario.h"

#include <filesystem>
#include <limits>

#include "harness/metrics/metric_table.h"
#include "harness/process/input_file.h"
#include "harness/scenario/json_fields.h"
#include "harness/scenario/scenario_reader.h"

namespace hb {

namespace {

constexpr double kNotApplicable = std::numeric_limits<double>::quiet_NaN();

// What plausible_ranges() gives: docs/limits.md's table, and the ranges
// plausibility_warnings (scenario_checks.cpp) applies to every scenario.
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

}  // namespace

namespace scenario_detail {

bool is_file_name_safe(const std::string& name) {
  if (name.empty() || name == "." || name == "..") return false;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '.' || c == '-' || c == '=';
    if (!ok) return false;
  }
  return true;
}

Scenario ScenarioReader::read(const std::string& bytes) {
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
  if (root.has("reference")) scenario.reference = read_reference(root.existing_member("reference"));
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

// Paths in a scenario are relative to its base folder (the scenario file's own).
std::string ScenarioReader::resolve(const std::string& relative) const {
  const std::filesystem::path path(relative);
  if (path.is_absolute() || directory_.empty()) return path.lexically_normal().string();
  return (directory_ / path).lexically_normal().string();
}

// The file a field names, which must exist.
std::string ScenarioReader::existing_file(const JsonField& field, const std::string& what) const {
  const std::string relative = field.string("expected the path of a " + what);
  if (relative.empty()) field.fail("expected the path of a " + what);
  const std::string path = resolve(relative);
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error))
    field.fail_with(what + " \"" + relative + "\" not found (looked for " + path + ")");
  return path;
}

}  // namespace scenario_detail

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
  return scenario_detail::ScenarioReader(source_path, base_dir).read(json_text);
}

std::span<const PlausibleRange> plausible_ranges() { return kPlausibleRanges; }

}  // namespace hb
