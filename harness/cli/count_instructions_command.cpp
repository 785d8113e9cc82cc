// `hapticbench count-instructions SCENARIO --schedule DIR --out FILE
// [--algo NAME]`: internal, started under callgrind by `run --instructions`
// (harness/run/instruction_counting.h).
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/cli/option_table.h"
#include "harness/progress/progress_display.h"
#include "harness/replay/instruction_count.h"
#include "harness/run/instruction_counting.h"

namespace hb {

namespace {

struct CountArguments {
  std::string scenario_path, schedule_dir, out;
  AlgorithmSelection only;
  std::optional<ProgressStyle> progress;
};

using Table = OptionTable<CountArguments>;

const Table& count_instructions_table() {
  static const Table table(
      {"count-instructions",
       {"Internal: started under valgrind's callgrind by `hapticbench run --instructions`."},
       {},
       {}},
      {Table::positional("SCENARIO", "the scenario file", 1, 1, &CountArguments::scenario_path),
       Table::value("--schedule", "DIR", "the folder of the slow-loop schedules to follow",
                    &CountArguments::schedule_dir)
           .required(),
       Table::value("--out", "FILE", "the counts, as JSON", &CountArguments::out).required(),
       Table::value("--algo", "NAME", "count only this algorithm (name, label or pattern)",
                    &CountArguments::only),
       Table::progress(&CountArguments::progress).with_default("none: its stderr is a file")});
  return table;
}

}  // namespace

int count_instructions_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const std::optional<CountArguments> parsed =
      parse_command_line([&] { return count_instructions_table().parse(args); },
                         count_instructions_table().usage(), exit_code);
  if (!parsed) return exit_code;
  if (!running_on_valgrind()) {
    std::cerr << "count-instructions: must run under valgrind --tool=callgrind (use "
                 "`hapticbench run --instructions`)\n";
    return kExitBadInput;
  }
  ProgressSettings settings;
  settings.style = parsed->progress.value_or(ProgressStyle::kNone);
  ProgressDisplay progress(std::cerr, std::move(settings));
  count_instructions_here(parsed->scenario_path, parsed->only, parsed->schedule_dir, parsed->out,
                          &progress);
  return kExitOk;
}

const CommandSyntax& count_instructions_syntax() { return count_instructions_table().syntax(); }

}  // namespace hb
