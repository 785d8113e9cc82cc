#include "harness/sweep/sweep_table.h"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "harness/metrics/formatted_number.h"
#include "harness/metrics/metric_table.h"

namespace hb {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

constexpr std::string_view kMarker = "<!-- hapticbench sweep table -->";

/// A summary of a run folder, or a discarded value: the table reads what
/// the job wrote and shows "-" for what is missing.
Json read_summary(const fs::path& run_folder) {
  std::ifstream in(run_folder / "summary.json", std::ios::binary);
  if (!in) return Json(Json::value_t::discarded);
  return Json::parse(in, nullptr, /*allow_exceptions=*/false);
}

/// A run's value of a metric in the table's display unit (scale × the
/// summary's value), or nullopt.
std::optional<double> metric_value(const Json& run, std::string_view metric, double scale) {
  const MetricDefinition* definition = find_metric(metric);
  if (definition == nullptr) return std::nullopt;
  const Json::json_pointer pointer{std::string(definition->json_pointer)};
  if (!run.contains(pointer) || !run[pointer].is_number()) return std::nullopt;
  return run[pointer].get<double>() * scale;
}

std::string stability_cell(const Json& run) {
  const Json::json_pointer verdict_pointer("/stability/verdict");
  if (!run.contains(verdict_pointer) || !run[verdict_pointer].is_object()) return "-";
  const Json& verdict = run[verdict_pointer];
  if (verdict.value("stable", false)) return "stable";
  std::string cell = verdict.contains("failed") && verdict["failed"].is_string()
                         ? verdict["failed"].get<std::string>()
                         : std::string("unstable");
  if (verdict.contains("expected_unstable") && verdict["expected_unstable"].is_string())
    cell += "*";
  return cell;
}

std::string budgets_cell(const Json& run) {
  if (!run.contains("budgets") || !run["budgets"].is_array() || run["budgets"].empty())
    return "none";
  std::size_t pass = 0;
  for (const Json& budget : run["budgets"])
    if (budget.is_object() && budget.value("pass", false)) ++pass;
  const std::size_t total = run["budgets"].size();
  return std::to_string(pass) + "/" + std::to_string(total) + (pass == total ? " pass" : " FAIL");
}

std::string value_text(const Json& value) {
  return value.is_string() ? value.get<std::string>() : value.dump();
}

/// Grid values in numeric order: numbers by value and before any text,
/// text by its characters.
bool value_less(const Json& a, const Json& b) {
  if (a.is_number() && b.is_number()) return a.get<double>() < b.get<double>();
  if (a.is_number() != b.is_number()) return a.is_number();
  return value_text(a) < value_text(b);
}

bool job_less(const SweepJob& a, const SweepJob& b) {
  if (a.scenario_index != b.scenario_index) return a.scenario_index < b.scenario_index;
  for (std::size_t axis = 0; axis < a.grid_values.size(); ++axis) {
    const Json& x = a.grid_values[axis].second;
    const Json& y = b.grid_values[axis].second;
    if (value_less(x, y)) return true;
    if (value_less(y, x)) return false;
  }
  return a.index < b.index;
}

std::string fixed(const std::optional<double>& value, const char* format) {
  return value ? formatted(format, *value) : "-";
}

/// The table's columns after the grid's: header, and cell of a row.
struct Column {
  const char* header;
  std::string (*cell)(const SweepTableRow& row);
};

constexpr Column kColumns[] = {
    {"label", [](const SweepTableRow& r) { return r.label.empty() ? r.status : r.label; }},
    {"F_err_N", [](const SweepTableRow& r) { return fixed(r.force_err_rms_n, "%.4f"); }},
    {"pen_max_mm", [](const SweepTableRow& r) { return fixed(r.penetration_max_mm, "%.3f"); }},
    {"p50_us", [](const SweepTableRow& r) { return fixed(r.step_p50_us, "%.2f"); }},
    {"p99_us", [](const SweepTableRow& r) { return fixed(r.step_p99_us, "%.2f"); }},
    {"stability", [](const SweepTableRow& r) { return r.stability; }},
    {"budgets", [](const SweepTableRow& r) { return r.budgets; }},
};

/// The header cells: the grid keys' last components (the whole pointer
/// when two keys share one), then the columns.
std::vector<std::string> header_cells(const SweepSpec& spec) {
  std::vector<std::string> cells;
  for (const SweepGridAxis& axis : spec.grid) {
    std::string name = axis.pointer.substr(axis.pointer.rfind('/') + 1);
    for (const SweepGridAxis& other : spec.grid)
      if (&other != &axis && other.pointer.substr(other.pointer.rfind('/') + 1) == name)
        name = axis.pointer;
    cells.push_back(name);
  }
  if (spec.scenario_paths.size() > 1) cells.insert(cells.begin(), "scenario");
  for (const Column& column : kColumns) cells.emplace_back(column.header);
  return cells;
}

std::vector<std::string> row_cells(const SweepSpec& spec, const SweepTableRow& row) {
  std::vector<std::string> cells = row.grid_cells;
  if (spec.scenario_paths.size() > 1) cells.insert(cells.begin(), row.scenario);
  for (const Column& column : kColumns) cells.push_back(column.cell(row));
  return cells;
}

}  // namespace

std::vector<SweepTableRow> sweep_table_rows(const SweepSpec& spec,
                                            const std::vector<SweepJob>& jobs,
                                            const std::vector<SweepJobState>& states,
                                            const fs::path& out_dir) {
  std::vector<const SweepJob*> ordered;
  for (const SweepJob& job : jobs) ordered.push_back(&job);
  std::stable_sort(ordered.begin(), ordered.end(),
                   [](const SweepJob* a, const SweepJob* b) { return job_less(*a, *b); });
  std::vector<SweepTableRow> rows;
  for (const SweepJob* job : ordered) {
    SweepTableRow base;
    base.job_index = job->index;
    base.scenario = spec.scenario_entries[job->scenario_index];
    base.status = sweep_job_status_name(states[job->index].status);
    for (const auto& [pointer, value] : job->grid_values)
      base.grid_cells.push_back(value_text(value));
    const Json summary = read_summary(out_dir / job->name);
    if (!summary.is_object() || !summary.contains("runs") || !summary["runs"].is_array() ||
        summary["runs"].empty()) {
      rows.push_back(base);
      continue;
    }
    for (const Json& run : summary["runs"]) {
      if (!run.is_object()) continue;
      SweepTableRow row = base;
      row.label =
          run.contains("label") && run["label"].is_string() ? run["label"].get<std::string>() : "?";
      row.force_err_rms_n = metric_value(run, "force_err_rms_n", 1);
      row.penetration_max_mm = metric_value(run, "max_penetration_mm", 1e3);
      row.step_p50_us = metric_value(run, "tick_p50_us", 1e-3);
      row.step_p99_us = metric_value(run, "tick_p99_us", 1e-3);
      row.stability = stability_cell(run);
      row.budgets = budgets_cell(run);
      rows.push_back(std::move(row));
    }
  }
  return rows;
}

void print_sweep_table(std::ostream& out, const SweepSpec& spec,
                       const std::vector<SweepTableRow>& rows) {
  std::vector<std::vector<std::string>> lines{header_cells(spec)};
  for (const SweepTableRow& row : rows) lines.push_back(row_cells(spec, row));
  std::vector<std::size_t> widths(lines.front().size(), 0);
  for (const auto& cells : lines)
    for (std::size_t c = 0; c < cells.size(); ++c) widths[c] = std::max(widths[c], cells[c].size());
  out << "sweep " << spec.name << ", every job (grid values in numeric order; * expected):\n";
  for (const auto& cells : lines) {
    std::string text = " ";
    for (std::size_t c = 0; c < cells.size(); ++c)
      text += " " + cells[c] + std::string(widths[c] - cells[c].size(), ' ');
    while (!text.empty() && text.back() == ' ') text.pop_back();
    out << text << "\n";
  }
}

std::string sweep_table_markdown(const SweepSpec& spec, const std::vector<SweepTableRow>& rows) {
  std::string text = std::string(kMarker) + "\n# Sweep " + spec.name + "\n\n";
  text += "Sweep file `" + spec.path + "`. Grid:\n\n";
  for (const SweepGridAxis& axis : spec.grid) {
    text += "- `" + axis.pointer + "`:";
    for (const Json& value : axis.values) text += " " + value_text(value);
    text += "\n";
  }
  text +=
      "\nOne row per job and label, grid values in numeric order. F_err_N: force error RMS (N); "
      "pen_max_mm: largest penetration (mm); p50_us, p99_us: step time percentiles (µs); "
      "stability: the verdict (* where the scenario expects instability); budgets: met of "
      "given.\n\n";
  const std::vector<std::string> header = header_cells(spec);
  auto markdown_row = [](const std::vector<std::string>& cells) {
    std::string line = "|";
    for (const std::string& cell : cells) line += " " + cell + " |";
    return line + "\n";
  };
  text += markdown_row(header);
  text += markdown_row(std::vector<std::string>(header.size(), "---"));
  for (const SweepTableRow& row : rows) text += markdown_row(row_cells(spec, row));
  return text;
}

bool is_sweep_table_file(const fs::path& path) {
  std::error_code error;
  if (!fs::is_regular_file(path, error)) return false;
  std::ifstream in(path, std::ios::binary);
  std::string first_line;
  std::getline(in, first_line);
  return first_line == kMarker;
}

}  // namespace hb
