// hapticbench sweep SWEEP.json [--jobs N] [--shard I/N] [--out DIR]: the
// command line of harness/drivers/sweep_runner.h.
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "hapticbench/input_error.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/cli/option_table.h"
#include "harness/drivers/sweep_runner.h"
#include "harness/sweep/sweep_shard.h"

namespace hb {

namespace {

constexpr long long kMaxParallelJobs = 1024;

struct SweepArguments {
  SweepRunOptions settings;
  std::optional<std::size_t> run_job;
  std::optional<ProgressStyle> progress;
};

using Table = OptionTable<SweepArguments>;

const Table& sweep_table() {
  const auto in_settings = [](auto field) { return member_of(&SweepArguments::settings, field); };
  static const Table table(
      {"sweep",
       {},
       {"Every job is validated before any runs; a job whose run folder already has "
        "summary.json is skipped, so running the command again resumes the sweep."},
       {}},
      {Table::positional("SWEEP.json", "the sweep file: scenarios and a grid of parameters", 1, 1,
                         in_settings(&SweepRunOptions::sweep_file)),
       Table::whole("--jobs", "N",
                    "run up to N jobs at a time, each in its own process; concurrent jobs share "
                    "the cores, so compare timings from --jobs 1 runs",
                    {1, kMaxParallelJobs, ""}, in_settings(&SweepRunOptions::jobs))
           .with_default("1"),
       Table::value("--shard", "I/N",
                    "run only the jobs whose index % N == I (one task of a job "
                    "array)",
                    [](SweepArguments& parsed, const std::string& value) {
                      try {
                        parsed.settings.shard = parse_sweep_shard(value);
                      } catch (const InputError& error) {
                        throw UsageError{std::string(error.what())};
                      }
                    }),
       Table::value("--out", "DIR", "one run folder per job, DIR/<job name>/, and DIR/sweep.json",
                    in_settings(&SweepRunOptions::out))
           .with_default("`out/sweeps/<sweep name>/`"),
       Table::whole("--run-job", "K", "run job K alone, in this process (what each worker runs)",
                    {0, 999999999, "a job index >= 0"}, &SweepArguments::run_job),
       Table::progress(&SweepArguments::progress), Table::quiet(&SweepArguments::progress)});
  return table;
}

// Throws UsageError or HelpRequested.
SweepArguments parse_sweep_arguments(const std::vector<std::string>& args) {
  SweepArguments parsed = sweep_table().parse(args);
  parsed.settings.progress = parsed.progress.value_or(default_progress_style());
  if (parsed.run_job && (parsed.settings.shard || parsed.settings.jobs != 1))
    throw UsageError{"--run-job runs one job; it takes no --jobs or --shard"};
  return parsed;
}

}  // namespace

int sweep_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const auto parse_result = parse_command_line([&] { return parse_sweep_arguments(args); },
                                               sweep_table().usage(), exit_code);
  if (!parse_result) return exit_code;
  const SweepArguments& parsed = *parse_result;
  try {
    return parsed.run_job ? run_sweep_job(parsed.settings, *parsed.run_job)
                          : run_sweep(parsed.settings);
  } catch (const InputError& error) {
    std::cerr << "error: " << error.what() << "\n";
    return kExitBadInput;
  }
}

const CommandSyntax& sweep_syntax() { return sweep_table().syntax(); }

}  // namespace hb
