// `hapticbench count-instructions SCENARIO --schedule DIR --out FILE
// [--algo NAME]`: internal, started under callgrind by `run --instructions`
// (harness/run/instruction_counting.h).
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "harness/cli/commands.h"
#include "harness/progress/progress_display.h"
#include "harness/replay/instruction_count.h"
#include "harness/run/instruction_counting.h"

namespace hb {

int count_instructions_command(const std::vector<std::string>& args) {
  std::string scenario_path, schedule_dir, out;
  AlgorithmSelection only;
  ProgressStyle progress_style = ProgressStyle::kNone;  // its stderr is a file
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--progress" && i + 1 < args.size() && progress_style_named(args[i + 1])) {
      progress_style = *progress_style_named(args[++i]);
    } else if (a == "--algo" && i + 1 < args.size()) {
      only.push_back(args[++i]);
    } else if ((a == "--schedule" || a == "--out") && i + 1 < args.size()) {
      (a == "--schedule" ? schedule_dir : out) = args[++i];
    } else if (scenario_path.empty() && a.rfind("--", 0) != 0) {
      scenario_path = a;
    } else {
      std::cerr << "count-instructions: unexpected argument " << a << "\n";
      return kExitBadInput;
    }
  }
  if (scenario_path.empty() || schedule_dir.empty() || out.empty()) {
    std::cerr << "usage (internal, started by run --instructions): hapticbench "
                 "count-instructions SCENARIO --schedule DIR --out FILE [--algo NAME]\n"
                 "                          [--progress bar|plain|none]\n";
    return kExitBadInput;
  }
  if (!running_on_valgrind()) {
    std::cerr << "count-instructions: must run under valgrind --tool=callgrind (use "
                 "`hapticbench run --instructions`)\n";
    return kExitBadInput;
  }
  ProgressSettings settings;
  settings.style = progress_style;
  ProgressDisplay progress(std::cerr, std::move(settings));
  count_instructions_here(scenario_path, only, schedule_dir, out, &progress);
  return kExitOk;
}

}  // namespace hb
