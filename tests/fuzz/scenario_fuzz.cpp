// Fuzz target: the scenario loader on a scenario's text (shapes only: mesh
// and trace files it names are read from the seed corpus's folders).
#include "harness/plugins/plugin_loader.h"
#include "harness/scenario/scenario.h"
#include "tests/fuzz/fuzz_support.h"

// Reading a scenario opens no plugin it names (a run request decides that);
// should a reader ever try, the loader refuses every plugin here.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hb::refuse_plugins("plugins are not loaded while fuzzing");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  return hb::fuzz::expect_input_errors_only([&] {
    const std::string folder = std::string(HAPTICBENCH_SOURCE_DIR) + "/scenarios/smoke";
    hb::load_scenario_json(hb::fuzz::text_of(data, size), folder + "/fuzz.json", folder);
  });
}
