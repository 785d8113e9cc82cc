#include "harness/cli/command_table.h"

#include <algorithm>
#include <utility>

#include "harness/cli/commands.h"

namespace hb {

namespace {

/// Where the top-level usage starts a summary that follows its synopsis.
constexpr std::size_t kSummaryColumn = 46;

const std::pair<int, const char*> kExitCodes[] = {
    {kExitOk, "ok"},
    {kExitBudgetFailed, "a budget, a stability verdict or a regression failed"},
    {kExitBadInput, "bad input or usage"},
    {kExitInternal, "internal error"},
};

OptionSpec global_option(std::string name, std::string value_name, std::string help) {
  OptionSpec spec;
  spec.name = std::move(name);
  spec.value_name = std::move(value_name);
  spec.help = std::move(help);
  return spec;
}

}  // namespace

const std::vector<CommandEntry>& command_table() {
  static const std::vector<CommandEntry> table = {
      {"run", "replay scenarios, write run folders",
       "SCENARIO... [--algo NAME]... [--out DIR] [--repeat N] [--instructions] [--schedule P]",
       run_command, run_syntax},
      {"validate", "check a scenario, mesh or trace file", "FILE...", validate_command,
       validate_syntax},
      {"init", "write a scenario to start from", "FILE.json [--scene S] [--tool T]", init_command,
       init_syntax},
      {"list", "algorithms, generators, scenarios; or a table of the docs (Markdown)",
       "[SCENARIO_DIR] | --metrics | --generators | --params | --limits | --commands", list_command,
       list_syntax},
      {"generate", "write a synthetic trace", "NAME --duration S --out FILE.csv", generate_command,
       generate_syntax},
      {"report", "one HTML page with figures from run folders", "RUN_DIR... [--out report.html]",
       report_command, report_syntax},
      {"compare", "regression gate against a baseline", "BASELINE CANDIDATE [--gate] [--out DIR]",
       compare_command, compare_syntax},
      {"history", "runs kept by commit; where a metric moved", "add DIR RUN_DIR... | show DIR",
       history_command, history_syntax},
      {"sweep", "run a grid of jobs", "SWEEP.json [--jobs N] [--shard I/N] [--out DIR]",
       sweep_command, sweep_syntax},
      {"stability", "largest stable value of one parameter",
       "SCENARIO.json --label L --param PTR --range LO HI [--tolerance R] [--out DIR]",
       stability_command, stability_syntax},
      {"zwidth", "stable region over two parameters (Z-width)",
       "SCENARIO.json --label L --x PTR --x-values V,.. --y PTR --y-range LO HI", zwidth_command,
       zwidth_syntax},
      {"ccd", "primitive CCD on query files: FN/FP, ns/query", "QUERIES.csv... [--json]",
       ccd_command, ccd_syntax},
      {"export", "Google Benchmark JSON of run folders", "--format gbench RUN_DIR... [--out FILE]",
       export_command, export_syntax},
      {"count-instructions", "count instructions under callgrind (the child of run --instructions)",
       "SCENARIO --schedule DIR --out FILE", count_instructions_command, count_instructions_syntax,
       /*internal=*/true},
  };
  return table;
}

const CommandEntry* find_command(std::string_view name) {
  for (const CommandEntry& entry : command_table())
    if (entry.name == name) return &entry;
  return nullptr;
}

const std::vector<OptionSpec>& global_options() {
  static const std::vector<OptionSpec> options = [] {
    std::vector<OptionSpec> made = {
        global_option("--memory-limit", "MB",
                      "the most memory the command may use; an input that needs more is exit 2"),
        global_option("--plugin", "PATH.so",
                      "load renderers built outside hapticbench (also "
                      "HAPTICBENCH_PLUGINS=/abs/A.so:/abs/B.so; docs/plugins.md)"),
        global_option("--allow-scenario-plugins", "",
                      "load the plugins scenario files name (a scenario alone never loads code; "
                      "validate never does)"),
    };
    made[0].default_text = "half of the machine's";
    made[1].repeatable = true;
    return made;
  }();
  return options;
}

std::string top_level_usage() {
  std::string out =
      "usage: hapticbench COMMAND [ARGS]   (hapticbench COMMAND --help: its arguments;\n"
      "                                     hapticbench --version: this build)\n";
  for (const CommandEntry& entry : command_table()) {
    if (entry.internal) continue;
    std::string line = "  ";
    line.append(entry.name).append(" ").append(entry.synopsis);
    if (line.size() + 1 >= kSummaryColumn) {  // the summary goes on the next line
      out += line + '\n';
      line.clear();
    }
    line.resize(kSummaryColumn, ' ');
    out += line;
    out += wrapped_text(std::string(entry.summary), kSummaryColumn, kSummaryColumn);
  }
  std::string codes = "exit codes:";
  for (const auto& [code, meaning] : kExitCodes)
    codes.append(code == kExitOk ? " " : ", ")
        .append(std::to_string(code))
        .append(" ")
        .append(meaning);
  return out + "every command:\n" + option_list_text(global_options(), 2) +
         wrapped_text(codes, 0, 12);
}

std::string command_reference_markdown() {
  std::string out = "| command | what it does |\n| --- | --- |\n";
  for (const CommandEntry& entry : command_table())
    if (!entry.internal)
      out.append("| [`")
          .append(entry.name)
          .append("`](#hapticbench-")
          .append(entry.name)
          .append(") | ")
          .append(entry.summary)
          .append(" |\n");
  out += "\nEvery command takes these options too, anywhere after its name:\n\n" +
         markdown_option_table(global_options()) + "\n| exit code | meaning |\n| --- | --- |\n";
  for (const auto& [code, meaning] : kExitCodes)
    out += "| " + std::to_string(code) + " | " + meaning + " |\n";
  for (const CommandEntry& entry : command_table())
    if (!entry.internal) out.append("\n").append(reference_markdown(entry.syntax(), entry.summary));
  return out;
}

}  // namespace hb
