// Fuzz target: compare's reader of summary.json.
#include "harness/compare/scenario_summary.h"
#include "harness/scenario/json_fields.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  return hb::fuzz::expect_input_errors_only([&] {
    hb::scenario_summary_from_json(
        hb::parse_json_document(hb::fuzz::text_of(data, size), "summary.json"), "summary.json");
  });
}
