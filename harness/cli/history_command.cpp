// hapticbench history add HISTORY_DIR RUN_DIR... [--commit ID]
// hapticbench history show HISTORY_DIR [--rel-tol X] [--tolerances FILE]
#include <iostream>
#include <optional>

#include "hapticbench/input_error.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/compare/comparison.h"
#include "harness/history/history_store.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

const std::string kHistoryUsage =
    "usage: hapticbench history add HISTORY_DIR RUN_DIR... [--commit ID]\n"
    "       hapticbench history show HISTORY_DIR [--rel-tol X] [--tolerances FILE]\n"
    "  add   keeps the runs' summaries (run folders or suites) as the entry of their\n"
    "        commit (--commit: another name for it); the same commit again replaces\n"
    "        its entry, a new one is appended (entries in the order added)\n"
    "  show  lists the entries and, per scenario, label and check, the first entry at\n"
    "        which it moved beyond its tolerance against the entry before (compare's\n"
    "        accuracy, stability and instruction checks; no wall-clock times)\n"
    "  `hapticbench report --history HISTORY_DIR` draws each metric's trend\n";

struct HistoryArguments {
  std::string action;
  fs::path history_dir;
  std::vector<fs::path> run_dirs;
  std::optional<std::string> commit;
  std::optional<std::string> tolerances_file;
  CompareOptions options;
};

HistoryArguments parse_history_arguments(const std::vector<std::string>& args) {
  HistoryArguments parsed;
  std::vector<std::string> positional;
  for (std::size_t i = 0; i < args.size(); ++i) {
    check_help(args[i]);
    if (args[i] == "--commit") {
      parsed.commit = option_value(args, i);
    } else if (args[i] == "--tolerances") {
      parsed.tolerances_file = option_value(args, i);
    } else if (args[i] == "--rel-tol") {
      const std::string& value = option_value(args, i);
      const std::optional<double> number = parse_number(value);
      if (!number || !(*number >= 0))
        throw UsageError{"--rel-tol: expected a number >= 0, got \"" + value + "\""};
      parsed.options.rel_tol = *number;
    } else if (args[i].rfind("--", 0) == 0) {
      throw UsageError{"unknown option " + args[i]};
    } else {
      positional.push_back(args[i]);
    }
  }
  if (positional.empty()) throw UsageError{"expected add or show"};
  parsed.action = positional[0];
  if (parsed.action != "add" && parsed.action != "show")
    throw UsageError{"expected add or show, got \"" + parsed.action + "\""};
  if (positional.size() < 2) throw UsageError{"missing HISTORY_DIR"};
  parsed.history_dir = positional[1];
  for (std::size_t i = 2; i < positional.size(); ++i) parsed.run_dirs.emplace_back(positional[i]);
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
  const std::optional<HistoryArguments> parsed =
      parse_command_line([&] { return parse_history_arguments(args); }, kHistoryUsage, exit_code);
  if (!parsed) return exit_code;
  if (parsed->action == "show") return show(*parsed);
  const HistoryEntry entry = add_to_history(parsed->history_dir, parsed->run_dirs, parsed->commit);
  std::cout << "history " << parsed->history_dir.string() << ": entry " << entry.folder << " ("
            << entry.scenarios.size() << " scenarios of commit " << entry.commit << ")\n";
  return kExitOk;
}

}  // namespace hb
