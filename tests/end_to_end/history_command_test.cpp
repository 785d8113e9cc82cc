// End-to-end: runs kept by commit. Three synthetic commits of one run (the
// force error of one label 30 % worse at the third) are stored with
// `history add`; `history show` names the third as where it first moved,
// and `report --history` draws the trend.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"

namespace {

namespace fs = std::filesystem;
using hb::test::kSource;
using nlohmann::json;

// A copy of run folder `from` as `to` with one label's force error scaled.
void copy_run(const fs::path& from, const fs::path& to, const std::string& label, double scale) {
  fs::create_directories(to);
  json summary = json::parse(hb::test::read_text_file(from / "summary.json"));
  for (json& run : summary["runs"])
    if (run["label"] == label)
      run["accuracy"]["force_err_rms_n"] = run["accuracy"]["force_err_rms_n"].get<double>() * scale;
  std::ofstream(to / "summary.json") << summary.dump(2);
}

TEST_CASE("history keeps runs by commit and finds the commit where a metric first moved") {
  const hb::test::ScratchDir work_dir("e2e_history");
  const fs::path& work = work_dir.path();
  const hb::test::CommandResult ran = hb::test::run_hapticbench(
      "run '" + (kSource / "scenarios/smoke/sphere_press_box.json").string() +
          "' --algo penalty_implicit --algo penalty_explicit --out c1 --quiet",
      work);
  REQUIRE(ran.exit_code == 0);
  copy_run(work / "c1", work / "c2", "penalty_implicit", 1.01);  // within tolerance
  copy_run(work / "c1", work / "c3", "penalty_implicit", 1.3);   // moved
  for (const char* commit : {"c1", "c2", "c3"}) {
    const hb::test::CommandResult added = hb::test::run_hapticbench(
        std::string("history add store ") + commit + " --commit " + commit, work);
    INFO(added.stderr_text);
    REQUIRE(added.exit_code == 0);
  }
  const json index = json::parse(hb::test::read_text_file(work / "store/history.json"));
  REQUIRE(index.at("entries").size() == 3);
  CHECK(index.at("entries").at(2).at("commit") == "c3");
  CHECK(fs::exists(work / "store" / index.at("entries").at(2).at("folder").get<std::string>() /
                   "sphere_press_box/summary.json"));

  const hb::test::CommandResult shown = hb::test::run_hapticbench("history show store", work);
  INFO(shown.stdout_text << shown.stderr_text);
  REQUIRE(shown.exit_code == 0);
  const std::size_t move =
      shown.stdout_text.find("c3  sphere_press_box penalty_implicit  accuracy.force_err_rms_n");
  CHECK(move != std::string::npos);
  CHECK(shown.stdout_text.find("regression", move) != std::string::npos);
  CHECK(shown.stdout_text.find("c2  sphere_press_box") == std::string::npos);
  CHECK(shown.stdout_text.find("penalty_explicit  accuracy") == std::string::npos);

  // The same commit again replaces its entry where it stands.
  REQUIRE(hb::test::run_hapticbench("history add store c1 --commit c2", work).exit_code == 0);
  const json replaced = json::parse(hb::test::read_text_file(work / "store/history.json"));
  CHECK(replaced.at("entries").size() == 3);
  CHECK(replaced.at("entries").at(1).at("commit") == "c2");

  // A folder that is not a history is never written into.
  fs::create_directories(work / "notes");
  std::ofstream(work / "notes/todo.txt") << "mine\n";
  const hb::test::CommandResult foreign =
      hb::test::run_hapticbench("history add notes c1 --commit c1", work);
  CHECK(foreign.exit_code == 2);
  CHECK(foreign.stderr_text.find("not a history folder") != std::string::npos);
  CHECK_FALSE(fs::exists(work / "notes/history.json"));
  // Nor over a folder in it that history.json does not list.
  fs::create_directories(work / "store/0004-c4");
  const hb::test::CommandResult unlisted =
      hb::test::run_hapticbench("history add store c1 --commit c4", work);
  CHECK(unlisted.exit_code == 2);
  CHECK(unlisted.stderr_text.find("history.json does not list it") != std::string::npos);
  CHECK(json::parse(hb::test::read_text_file(work / "store/history.json")).at("entries").size() ==
        3);

  // The report draws the history alone.
  const hb::test::CommandResult report =
      hb::test::run_hapticbench("report --history store --out history.html --quiet", work);
  INFO(report.stderr_text);
  CHECK(report.exit_code == 0);
  CHECK(hb::test::read_text_file(work / "history.html").find("History") != std::string::npos);
}

}  // namespace
