// The settings of a scenario: tags, plugins, algorithms, reference,
// budgets, expected_unstable, coupling, device and closed loop. A plugin
// file is hashed into the scenario's content hash, never loaded here.
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "hapticbench/content_hash.h"
#include "hapticbench/input_error.h"
#include "harness/closed_loop/closed_loop_device.h"
#include "harness/reference/oracle.h"
#include "harness/scenario/json_params.h"
#include "harness/scenario/scenario_reader.h"

namespace hb::scenario_detail {

namespace {

/// The finest encoder resolutions a closed-loop device may have (m, rad):
/// below them a position divided by the resolution leaves the doubles.
constexpr double kFinestEncoderM = 1e-9, kFinestEncoderRad = 1e-9;

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

}  // namespace

std::vector<std::string> ScenarioReader::read_tags(const JsonField& field) {
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

// Each plugin file, relative to the scenario, must exist; it is hashed
// with the scenario and returned as a path (a run loads it, as the plugin
// policy allows).
std::vector<ScenarioPlugin> ScenarioReader::read_plugins(const JsonField& field) {
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

std::vector<AlgorithmSpec> ScenarioReader::read_algorithms(const JsonField& field) const {
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

ReferenceSpec ScenarioReader::read_reference(const JsonField& field) const {
  field.require_object(
      "expected {\"oracle\", \"exact_every\", \"analytic\", \"force\", \"force_every\", "
      "\"sample_spacing_m\"}");
  field.reject_unknown_keys(
      {"oracle", "exact_every", "analytic", "force", "force_every", "sample_spacing_m"});
  ReferenceSpec reference;
  if (field.has("oracle")) {
    std::vector<std::string_view> choices = {"none"};
    for (const OracleBackendEntry& backend : hb::oracle_backends()) choices.push_back(backend.name);
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
  if (field.has("force")) reference.force = field.existing_member("force").choice({"auto", "none"});
  if (field.has("force_every"))
    reference.force_every = field.existing_member("force_every")
                                .integer(1, std::numeric_limits<int64_t>::max(),
                                         "expected a whole number of ticks >= 1");
  if (field.has("sample_spacing_m"))
    reference.sample_spacing_m = field.existing_member("sample_spacing_m")
                                     .positive_number("expected a positive spacing in metres");
  return reference;
}

std::vector<Budget> ScenarioReader::read_budgets(const JsonField& field) {
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

// {label: why}: every key a label of the scenario's algorithms, every
// value a non-empty reason.
std::map<std::string, std::string> ScenarioReader::read_expected_unstable(
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

CouplingGains ScenarioReader::read_coupling(const JsonField& field) const {
  field.require_object("expected {\"k_t\", \"b_t\", \"k_r\", \"b_r\"}");
  field.reject_unknown_keys({"k_t", "b_t", "k_r", "b_r"});
  CouplingGains gains;
  if (field.has("k_t"))
    gains.k_t = field.existing_member("k_t").positive_number("expected a positive number (N/m)");
  if (field.has("b_t"))
    gains.b_t = field.existing_member("b_t").non_negative_number("expected a number >= 0 (N·s/m)");
  if (field.has("k_r"))
    gains.k_r =
        field.existing_member("k_r").positive_number("expected a positive number (N·m/rad)");
  if (field.has("b_r"))
    gains.b_r =
        field.existing_member("b_r").non_negative_number("expected a number >= 0 (N·m·s/rad)");
  return gains;
}

DeviceLimits ScenarioReader::read_device(const JsonField& field) const {
  field.require_object("expected {\"max_force_n\", \"max_torque_nm\"}");
  field.reject_unknown_keys({"max_force_n", "max_torque_nm"});
  DeviceLimits limits;
  if (field.has("max_force_n"))
    limits.max_force_n =
        field.existing_member("max_force_n").positive_number("expected a positive force (N)");
  if (field.has("max_torque_nm"))
    limits.max_torque_nm =
        field.existing_member("max_torque_nm").positive_number("expected a positive torque (N·m)");
  return limits;
}

// The hand and device of closed-loop replay; a missing key keeps its
// default (closed_loop_model.h).
ClosedLoopModel ScenarioReader::read_closed_loop(const JsonField& field) const {
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

}  // namespace hb::scenario_detail
