// hapticbench sweep SWEEP.json [--jobs N] [--shard I/N] [--out DIR]: the
// command line of harness/drivers/sweep_runner.h.
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "hapticbench/input_error.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/drivers/sweep_runner.h"
#include "harness/sweep/sweep_shard.h"

namespace hb {

namespace {

const std::string kSweepUsage =
    "usage: hapticbench sweep SWEEP.json [--jobs N] [--shard I/N] [--out DIR]\n"
    "                         [--progress STYLE] [--quiet]\n"
    "  --jobs N     run up to N jobs at a time, each in its own process (default 1);\n"
    "               concurrent jobs share the cores, so compare timings from --jobs 1 runs\n"
    "  --shard I/N  run only the jobs whose index % N == I (one task of a job array)\n"
    "  --out DIR    one run folder per job, DIR/<job name>/, and DIR/sweep.json;\n"
    "               default out/sweeps/<sweep name>/\n"
    "  --run-job K  run job K alone, in this process (what each worker runs)\n"
    "  every job is validated before any runs; a job whose run folder already has\n"
    "  summary.json is skipped, so running the command again resumes the sweep.\n" +
    std::string(kProgressUsage);

constexpr std::size_t kMaxParallelJobs = 1024;

struct SweepArguments {
  SweepRunSettings settings;
  std::optional<std::size_t> run_job;
  std::optional<ProgressStyle> progress;
};

std::optional<std::size_t> whole_number(const std::string& text, std::size_t min, std::size_t max) {
  if (text.empty() || text.size() > 9) return std::nullopt;
  std::size_t value = 0;
  for (char c : text) {
    if (c < '0' || c > '9') return std::nullopt;
    value = value * 10 + static_cast<std::size_t>(c - '0');
  }
  if (value < min || value > max) return std::nullopt;
  return value;
}

// Throws UsageError or HelpRequested.
SweepArguments parse_sweep_arguments(const std::vector<std::string>& args) {
  SweepArguments parsed;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    check_help(a);
    if (a == "--jobs" || a == "--shard" || a == "--out" || a == "--run-job") {
      const std::string& value = option_value(args, i);
      if (a == "--jobs") {
        const std::optional<std::size_t> jobs = whole_number(value, 1, kMaxParallelJobs);
        if (!jobs)
          throw UsageError{"--jobs: expected a whole number in [1, " +
                           std::to_string(kMaxParallelJobs) + "], got \"" + value + "\""};
        parsed.settings.jobs = *jobs;
      } else if (a == "--shard") {
        try {
          parsed.settings.shard = parse_sweep_shard(value);
        } catch (const InputError& error) {
          throw UsageError{std::string(error.what())};
        }
      } else if (a == "--out") {
        parsed.settings.out = value;
      } else {
        parsed.run_job = whole_number(value, 0, 999999999);
        if (!parsed.run_job)
          throw UsageError{"--run-job: expected a job index >= 0, got \"" + value + "\""};
      }
    } else if (parse_progress_option(args, i, parsed.progress)) {
    } else if (a.rfind("--", 0) == 0) {
      throw UsageError{"unknown option " + a};
    } else if (!parsed.settings.sweep_file.empty()) {
      throw UsageError{"one sweep file at a time (got " + parsed.settings.sweep_file + " and " + a +
                       ")"};
    } else {
      parsed.settings.sweep_file = a;
    }
  }
  if (parsed.settings.sweep_file.empty()) throw UsageError{"no sweep file given"};
  parsed.settings.progress = parsed.progress.value_or(default_progress_style());
  if (parsed.run_job && (parsed.settings.shard || parsed.settings.jobs != 1))
    throw UsageError{"--run-job runs one job; it takes no --jobs or --shard"};
  return parsed;
}

}  // namespace

int sweep_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const auto parse_result =
      parse_command_line([&] { return parse_sweep_arguments(args); }, kSweepUsage, exit_code);
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

}  // namespace hb
