// Fuzz target: the sweep file parser.
#include "harness/sweep/sweep_spec.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  return hb::fuzz::expect_input_errors_only([&] {
    hb::parse_sweep_spec(hb::fuzz::text_of(data, size),
                         std::string(HAPTICBENCH_SOURCE_DIR) + "/scenarios/sweeps/fuzz.json");
  });
}
