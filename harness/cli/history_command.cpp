// hapticbench history add HISTORY_DIR RUN_DIR... [--commit ID]
// hapticbench history show HISTORY_DIR [--rel-tol X] [--tolerances FILE]
#include <iostream>
#include <optional>

#include "hapticbench/input_error.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/cli/option_table.h"
#include "harness/compare/comparison.h"
#include "harness/history/history_store.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

struct HistoryArguments {
  std::string action;
  fs::path history_dir;
  std::vector<fs::path> run_dirs;
  std::optional<std::string> commit;
  std::optional<std::string> tolerances_file;
  CompareOptions options;
};

using Table = OptionTable<HistoryArguments>;

const Table& history_table() {
  static const Table table(
      {"history",
       {"add: keeps the runs' summaries (run folders or suites) as the entry of their commit; the "
        "same commit again replaces its entry, a new one is appended (entries in the order "
        "added).",
        "show: lists the entries and, per scenario, label and check, the first entry at which it "
        "moved beyond its tolerance against the entry before (compare's accuracy, stability and "
        "instruction checks; no wall-clock times)."},
       {"`hapticbench report --history HISTORY_DIR` draws each metric's trend."},
       {}},
      {Table::positional("add|show", "what to do", 1, 1,
                         [](HistoryArguments& parsed, const std::string& action) {
                           if (action != "add" && action != "show")
                             throw UsageError{"expected add or show, got \"" + action + "\""};
                           parsed.action = action;
                         })
           .missing("add or show"),
       Table::positional("HISTORY_DIR", "the history folder", 1, 1, &HistoryArguments::history_dir),
       Table::positional("RUN_DIR", "add: a run folder or a suite of them", 0, kAnyCount,
                         &HistoryArguments::run_dirs),
       Table::value("--commit", "ID", "add: another name for the runs' commit",
                    &HistoryArguments::commit),
       Table::number("--rel-tol", "X", "show: tolerance relative to the entry before", at_least(0),
                     member_of(&HistoryArguments::options, &CompareOptions::rel_tol))
           .with_default("0.05"),
       Table::value("--tolerances", "FILE",
                    "show: per-metric tolerances in place of the defaults (as compare's)",
                    &HistoryArguments::tolerances_file)});
  return table;
}

HistoryArguments parse_history_arguments(const std::vector<std::string>& args) {
  HistoryArguments parsed = history_table().parse(args);
  if (parsed.action == "add" && parsed.run_dirs.empty()) throw UsageError{"missing RUN_DIR"};
  if (parsed.action == "show" && !parsed.run_dirs.empty())
    throw UsageError{"show takes the history folder only"};
  if (parsed.action == "show" && parsed.commit) throw UsageError{"--commit is for add"};
  parsed.options.timing = false;  // the store keeps no ticks
  return parsed;
}

int show(const HistoryArguments& arguments) {
  const std::vector<HistoryEntry> entries = read_history(arguments.history_dir);
  CompareOptions options = arguments.options;
  if (arguments.tolerances_file)
    options.tolerances = read_tolerances_file(*arguments.tolerances_file);
  std::cout << "history " << arguments.history_dir.string() << ": " << entries.size() << " entr"
            << (entries.size() == 1 ? "y" : "ies") << ", oldest first\n";
  for (std::size_t i = 0; i < entries.size(); ++i)
    std::cout << "  " << i + 1 << "  " << entries[i].commit << "  " << entries[i].date << "  "
              << entries[i].scenarios.size() << " scenarios\n";
  const std::vector<HistoryMove> moves = first_moves(arguments.history_dir, entries, options);
  if (moves.empty()) {
    std::cout << "no check moved beyond its tolerance between consecutive entries\n";
    return kExitOk;
  }
  std::cout << "first moves (each check's first entry beyond its tolerance against the one "
               "before):\n";
  for (const HistoryMove& move : moves) {
    const CheckRow& row = move.row;
    std::cout << "  " << entries[move.entry].commit << "  " << row.scenario
              << (row.label.empty() ? "" : " " + row.label) << "  " << row.check << "  "
              << display_value(row.baseline) << " -> " << display_value(row.candidate) << "  "
              << verdict_name(row.verdict) << (row.note.empty() ? "" : " (" + row.note + ")")
              << "\n";
  }
  return kExitOk;
}

}  // namespace

int history_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const std::optional<HistoryArguments> parsed = parse_command_line(
      [&] { return parse_history_arguments(args); }, history_table().usage(), exit_code);
  if (!parsed) return exit_code;
  if (parsed->action == "show") return show(*parsed);
  const HistoryEntry entry = add_to_history(parsed->history_dir, parsed->run_dirs, parsed->commit);
  std::cout << "history " << parsed->history_dir.string() << ": entry " << entry.folder << " ("
            << entry.scenarios.size() << " scenarios of commit " << entry.commit << ")\n";
  return kExitOk;
}

const CommandSyntax& history_syntax() { return history_table().syntax(); }

}  // namespace hb
