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
    if (!trace.samples.empty()) hb::resample_to_ticks(trace);
  });
}
