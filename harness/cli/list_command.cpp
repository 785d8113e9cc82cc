// hapticbench list [SCENARIO_DIR]: algorithms, generators and the scenarios
// shipped in scenarios/. The tables the docs hold, as Markdown
// (doc_tables.h): list --metrics (docs/metric-table.md), --generators (the
// generators' parameters, traces/README.md), --params (the algorithms'
// parameters, docs/algorithms/README.md), --limits (the plausible ranges,
// docs/limits.md), --commands (every command's reference,
// docs/command-line.md).
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>

#include "algorithms/registry.h"
#include "hapticbench/input_error.h"
#include "harness/cli/command_line.h"
#include "harness/cli/command_table.h"
#include "harness/cli/commands.h"
#include "harness/cli/doc_tables.h"
#include "harness/cli/option_table.h"
#include "harness/trace/generators.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

// The tables of the docs `list` prints, by the option that asks for each.
enum class DocTable { kNone, kMetrics, kGenerators, kParams, kLimits, kCommands };

struct ListArguments {
  std::optional<std::string> scenario_root;
  DocTable table = DocTable::kNone;
};

using Table = OptionTable<ListArguments>;

Table::Row table_flag(std::string name, std::string help, DocTable table) {
  return Table::flag(std::move(name), std::move(help), [table](ListArguments& parsed) {
    if (parsed.table != DocTable::kNone && parsed.table != table)
      throw UsageError{"one table at a time"};
    parsed.table = table;
  });
}

const Table& list_table() {
  static const Table table(
      {"list",
       {"Lists the algorithms, the generators, and the scenario and sweep files in SCENARIO_DIR; "
        "with a table option, prints that table of the docs as Markdown instead."},
       {},
       {}},
      {Table::positional("SCENARIO_DIR", "a folder of scenario files", 0, 1,
                         &ListArguments::scenario_root)
           .with_default("scenarios"),
       table_flag("--metrics", "every metric (docs/metric-table.md)", DocTable::kMetrics),
       table_flag("--generators", "the generators' parameters (traces/README.md)",
                  DocTable::kGenerators),
       table_flag("--params", "the algorithms' parameters (docs/algorithms/README.md)",
                  DocTable::kParams),
       table_flag("--limits", "the plausible ranges (docs/limits.md)", DocTable::kLimits),
       table_flag("--commands", "every command's reference (docs/command-line.md)",
                  DocTable::kCommands)});
  return table;
}

ListArguments parse_list_arguments(const std::vector<std::string>& args) {
  ListArguments parsed = list_table().parse(args);
  if (parsed.table != DocTable::kNone && parsed.scenario_root)
    throw UsageError{"a table of the docs takes no SCENARIO_DIR"};
  return parsed;
}

}  // namespace

int list_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const std::optional<ListArguments> parsed = parse_command_line(
      [&] { return parse_list_arguments(args); }, list_table().usage(), exit_code);
  if (!parsed) return exit_code;
  switch (parsed->table) {
    case DocTable::kMetrics:
      print_metric_table(std::cout);
      return kExitOk;
    case DocTable::kGenerators:
      print_generator_parameters(std::cout);
      return kExitOk;
    case DocTable::kParams:
      print_algorithm_parameters(std::cout);
      return kExitOk;
    case DocTable::kLimits:
      print_plausible_ranges(std::cout);
      return kExitOk;
    case DocTable::kCommands:
      std::cout << command_reference_markdown();
      return kExitOk;
    case DocTable::kNone:
      break;
  }
  const std::string scenario_root = parsed->scenario_root.value_or("scenarios");
  if (parsed->scenario_root) {
    std::error_code error;
    // A folder the user names must exist; the default may be absent.
    if (!fs::is_directory(scenario_root, error))
      throw InputError(scenario_root, "", "not a folder; expected a folder of scenario files");
  }

  std::cout << "algorithms:\n";
  for (const AlgorithmEntry& entry : algorithm_table()) {
    const std::string plugin = algorithm_origin(entry.name);
    std::cout << "  " << entry.name << "  -  " << entry.summary
              << (plugin.empty() ? "" : " [plugin " + plugin + "]") << "\n";
  }
  std::cout << "generators:\n";
  for (const GeneratorEntry& entry : generator_table())
    std::cout << "  " << entry.name << "  -  " << entry.summary << "\n";

  // Sweep files live in a folder named "sweeps"; everything else is a scenario.
  std::vector<std::string> scenarios, sweeps;
  std::error_code error;
  if (fs::is_directory(scenario_root, error)) {
    for (const auto& entry : fs::recursive_directory_iterator(scenario_root, error)) {
      if (entry.path().extension() != ".json") continue;
      const bool is_sweep = entry.path().parent_path().filename() == "sweeps";
      (is_sweep ? sweeps : scenarios).push_back(entry.path().string());
    }
  }
  std::sort(scenarios.begin(), scenarios.end());
  std::sort(sweeps.begin(), sweeps.end());
  std::cout << "scenarios (" << scenario_root << "/):\n";
  if (scenarios.empty())
    std::cout << "  (none found; run from the project folder or pass a folder)\n";
  for (const std::string& file : scenarios) std::cout << "  " << file << "\n";
  std::cout << "sweeps:\n";
  if (sweeps.empty()) std::cout << "  (none)\n";
  for (const std::string& file : sweeps) std::cout << "  " << file << "\n";
  return kExitOk;
}

const CommandSyntax& list_syntax() { return list_table().syntax(); }

}  // namespace hb
