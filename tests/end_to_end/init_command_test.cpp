// End-to-end: `hapticbench init` writes a scenario that validates and runs
// as written, for primitives and for a mesh, and never overwrites a file.
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"

namespace {

namespace fs = std::filesystem;
using hb::test::kSource;

TEST_CASE("init writes a commented scenario that validates, reaches the scene and runs") {
  const hb::test::ScratchDir work_dir("e2e_init");
  const fs::path& work = work_dir.path();
  const hb::test::CommandResult made = hb::test::run_hapticbench("init press.json", work);
  INFO(made.stderr_text);
  REQUIRE(made.exit_code == 0);
  const std::string text = hb::test::read_text_file(work / "press.json");
  CHECK(text.rfind("// A scenario made by `hapticbench init`", 0) == 0);

  // It validates, and its press reaches 2 mm into the box.
  const hb::test::CommandResult validated = hb::test::run_hapticbench("validate press.json", work);
  INFO(validated.stdout_text << validated.stderr_text);
  REQUIRE(validated.exit_code == 0);
  CHECK(validated.stdout_text.find("least -2.000 mm") != std::string::npos);
  CHECK(validated.stderr_text.find("warning") == std::string::npos);
  // ... and runs: every algorithm it lists is stable or expected not to be.
  const hb::test::CommandResult ran =
      hb::test::run_hapticbench("run press.json --out run --quiet", work);
  INFO(ran.stdout_text << ran.stderr_text);
  CHECK(ran.exit_code == 0);
  CHECK(fs::exists(work / "run/ticks_god_object.csv"));

  // A mesh scene: placed with the top of its middle at the origin.
  const std::string bunny = (kSource / "models/bunny00.off").string();
  REQUIRE(
      hb::test::run_hapticbench("init on_bunny.json --scene '" + bunny + "' --tool capsule", work)
          .exit_code == 0);
  const hb::test::CommandResult mesh = hb::test::run_hapticbench("validate on_bunny.json", work);
  INFO(mesh.stdout_text << mesh.stderr_text);
  CHECK(mesh.exit_code == 0);
  CHECK(mesh.stdout_text.find("least -") != std::string::npos);  // the press reaches it

  // Never over a file; a shape it does not know is named.
  const hb::test::CommandResult again = hb::test::run_hapticbench("init press.json", work);
  CHECK(again.exit_code == 2);
  CHECK(again.stderr_text.find("exists already") != std::string::npos);
  CHECK(hb::test::read_text_file(work / "press.json") == text);
  const hb::test::CommandResult unknown =
      hb::test::run_hapticbench("init other.json --tool cone", work);
  CHECK(unknown.exit_code == 2);
  CHECK(unknown.stderr_text.find("--tool: expected sphere, box, capsule") != std::string::npos);
  CHECK_FALSE(fs::exists(work / "other.json"));
}

}  // namespace
