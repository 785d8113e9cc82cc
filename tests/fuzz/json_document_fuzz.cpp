// Fuzz target: parse_json_document (every JSON input hapticbench reads).
#include "harness/scenario/json_fields.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  return hb::fuzz::expect_input_errors_only(
      [&] { hb::parse_json_document(hb::fuzz::text_of(data, size), "fuzz.json"); });
}
