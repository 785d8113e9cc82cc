// The plugin loader's process-wide refusal: a program that reads untrusted
// scenarios (the fuzz targets) opens no shared library they name.
#include "harness/plugins/plugin_loader.h"

#include <catch2/catch.hpp>
#include <string>

#include "hapticbench/input_error.h"

TEST_CASE("after refuse_plugins no file is loaded, an existing library included") {
  hb::refuse_plugins("plugins are not loaded by this test");
  // A shared library every process here has: refused before it is opened.
  const std::string library = "/proc/self/exe";
  try {
    hb::load_plugin(library, "/plugins/0");
    FAIL("the plugin was not refused");
  } catch (const hb::InputError& error) {
    const std::string message = error.what();
    CHECK(message.find(library) != std::string::npos);
    CHECK(message.find("/plugins/0") != std::string::npos);
    CHECK(message.find("plugins are not loaded by this test") != std::string::npos);
  }
  CHECK(hb::loaded_plugins().empty());
}
