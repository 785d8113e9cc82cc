// Synthetic device trajectories, deterministic by seed, in a visible table.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "hapticbench/param_set.h"
#include "harness/trace/trace.h"

namespace hb {

struct GeneratorRequest {
  double duration_s = 1.0;  ///< length of the trace (s), > 0
  uint64_t seed = 1;        ///< random generators use only this seed
  ParamSet params;          ///< generator-specific; unknown keys are rejected
};

/// A generated trace: its samples are computed when asked for, so an
/// hour-long trace costs no memory until it is written out.
struct GeneratedTrace {
  TraceInfo info;
  TraceSource source;  ///< 1 kHz from t = 0, with analytic twists
  /// Every sample.
  Trace sampled() const;
};

struct GeneratorEntry {
  std::string_view name;     ///< used in a scenario's trace.generator
  std::string_view summary;  ///< one line for `hapticbench list`
  /// Checks the parameters (InputError) and returns the trace.
  GeneratedTrace (*generate)(const GeneratorRequest& request);
};

/// Every generator, in the order `hapticbench list` shows them (traces/README.md
/// describes each). Every one also takes "repeat_sample_at_s" (s): the
/// sample at that tick repeats the previous one, pose and twist (a device
/// that reports the same sample twice).
std::span<const GeneratorEntry> generator_table();

/// Looks a generator up and runs it; throws InputError naming `field` for
/// an unknown name, the sibling field "duration_s" for a bad duration, and
/// the parameter's field (params prefix + key) for bad or unknown
/// parameters. Samples are at 1 kHz with analytic twists, from t = 0 to
/// t = duration inclusive: round(duration_s * 1000) + 1 samples.
GeneratedTrace make_generated_trace(const std::string& name, const GeneratorRequest& request,
                                    const std::string& field);
/// make_generated_trace(...).sampled(): every sample.
Trace generate_trace(const std::string& name, const GeneratorRequest& request,
                     const std::string& field);

}  // namespace hb
