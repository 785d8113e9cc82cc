// Fuzz target: CCD query files (the shared data's rational CSV format).
#include "harness/cli/ccd_query_file.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  // The first byte picks the kind (the file name tells it); the rest is the file.
  const auto path =
      hb::fuzz::file_of(data + 1, size - 1, data[0] & 1 ? "edge-edge.csv" : "vertex-face.csv");
  return hb::fuzz::expect_input_errors_only([&] { hb::read_ccd_query_file(path); });
}
