// Fuzz target: trace files, hapticbench CSV and TUM, and their resampling
// onto the 1 kHz clock (what run does with them).
#include "harness/trace/trace.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  // The first byte picks the format; the rest is the file.
  const bool tum = data[0] & 1;
  const auto path = hb::fuzz::file_of(data + 1, size - 1, tum ? "trace.tum" : "trace.csv");
  return hb::fuzz::expect_input_errors_only([&] {
    const hb::Trace trace = hb::read_trace_file(
        path.string(), tum ? hb::TraceFileFormat::kTum : hb::TraceFileFormat::kHapticbenchCsv);
    // Resampled unless it spans between a minute and the allowed hour: such
    // a trace only costs time, which the fuzzer would report as a timeout
    // (longer ones are refused before anything is allocated).
    if (trace.samples.empty()) return;
    const double span_s = static_cast<double>(trace.samples.back().t_ns) * 1e-9;
    if (span_s <= 60 || span_s > hb::kMaxRunDurationS) hb::resample_to_ticks(trace);
  });
}
