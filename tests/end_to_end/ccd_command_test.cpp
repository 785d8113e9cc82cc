// End-to-end: `hapticbench ccd` on every sample query file (tests/data/) (no missed
// contact anywhere), its JSON lines, and its answers to bad input.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"

namespace {

using hb::test::write_file;

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kQueryDir = fs::path(HAPTICBENCH_SOURCE_DIR) / "tests/data/ccd-sample-queries";

std::vector<fs::path> all_query_files() {
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(kQueryDir))
    if (entry.path().extension() == ".csv") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

/// Queries and true collisions of a file, counted here from its rows.
struct FileCounts {
  int queries = 0;
  int collisions = 0;
};

FileCounts count_rows(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  int rows = 0, true_rows = 0;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    ++rows;
    true_rows += line.substr(line.rfind(',') + 1).rfind('1', 0) == 0;
  }
  return {rows / 8, true_rows / 8};
}

std::vector<json> json_lines(const std::string& text) {
  std::vector<json> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.push_back(json::parse(line));
  return lines;
}

// One vertex-face query: the vertex drops through the middle of a triangle
// in the plane z = 0, a contact; its truth column set to `truth`. As rows.
std::vector<std::string> crossing_query_rows(int truth) {
  const char* coordinates[8] = {"0,1,0,1,1,1",  "-1,1,-1,1,0,1", "1,1,-1,1,0,1", "0,1,1,1,0,1",
                                "0,1,0,1,-1,1", "-1,1,-1,1,0,1", "1,1,-1,1,0,1", "0,1,1,1,0,1"};
  std::vector<std::string> rows;
  for (const char* row : coordinates)
    rows.push_back(std::string(row).append(",").append(std::to_string(truth)));
  return rows;
}

/// The rows as file text, one per line.
std::string file_text(const std::vector<std::string>& rows) {
  std::string text;
  for (const std::string& row : rows) text.append(row).append("\n");
  return text;
}

TEST_CASE("ccd on all shared sample queries misses no contact") {
  REQUIRE(fs::is_directory(kQueryDir));
  const std::vector<fs::path> files = all_query_files();
  REQUIRE(files.size() >= 32);
  std::string args;
  for (const fs::path& f : files) args += " '" + f.string() + "'";

  const hb::test::ScratchDir work("e2e_ccd_all");
  const hb::test::CommandResult result = hb::test::run_hapticbench("ccd" + args + " --json", work);
  INFO(result.stderr_text);
  REQUIRE(result.exit_code == 0);
  const std::vector<json> lines = json_lines(result.stdout_text);
  REQUIRE(lines.size() == files.size());

  const std::set<std::string> expected_keys{
      "file",    "kind",      "queries", "collisions", "false_negatives", "false_positives",
      "ns_mean", "ns_median", "ns_max"};
  int queries = 0, collisions = 0;
  for (std::size_t i = 0; i < files.size(); ++i) {
    const json& line = lines[i];
    INFO(line.dump());
    std::set<std::string> keys;
    for (const auto& item : line.items()) keys.insert(item.key());
    CHECK(keys == expected_keys);
    CHECK(line.at("file") == files[i].string());
    const std::string folder = files[i].parent_path().filename().string();
    CHECK(line.at("kind") == (folder == "vertex-face" ? "vertex_face" : "edge_edge"));
    const FileCounts counts = count_rows(files[i]);
    CHECK(line.at("queries") == counts.queries);
    CHECK(line.at("collisions") == counts.collisions);
    CHECK(line.at("false_negatives") == 0);
    const int false_positives = line.at("false_positives");
    CHECK(false_positives <= counts.queries - counts.collisions);
    const double ns_mean = line.at("ns_mean");
    const int ns_median = line.at("ns_median"), ns_max = line.at("ns_max");
    CHECK(ns_median > 0);
    CHECK(ns_median <= ns_max);
    CHECK(ns_mean <= ns_max);
    queries += counts.queries;
    collisions += counts.collisions;
  }
  // The data set as its README describes it.
  CHECK(queries > 3500);
  CHECK(collisions > 300);
}

TEST_CASE("ccd prints a table with a line per file and a total") {
  const hb::test::ScratchDir work("e2e_ccd_table");
  const fs::path vf = kQueryDir / "unit-tests/vertex-face/data_0_0.csv";
  const fs::path ee = kQueryDir / "unit-tests/edge-edge/data_0_0.csv";
  const hb::test::CommandResult result =
      hb::test::run_hapticbench("ccd '" + vf.string() + "' '" + ee.string() + "'", work);
  INFO(result.stderr_text);
  REQUIRE(result.exit_code == 0);
  CHECK(result.stdout_text.find("false_neg") != std::string::npos);
  CHECK(result.stdout_text.find("vertex_face") != std::string::npos);
  CHECK(result.stdout_text.find("edge_edge") != std::string::npos);
  CHECK(result.stdout_text.find("(all files)") != std::string::npos);
}

TEST_CASE("ccd exits 1 when a contact is missed against the truth column") {
  // Truth says no contact where there is one: a false positive, exit 0.
  const hb::test::ScratchDir work("e2e_ccd_fn");
  write_file(work / "vertex-face/contact.csv", file_text(crossing_query_rows(0)));
  const hb::test::CommandResult fp = hb::test::run_hapticbench(
      "ccd --json '" + (work / "vertex-face/contact.csv").string() + "'", work);
  REQUIRE(fp.exit_code == 0);
  CHECK(json_lines(fp.stdout_text).at(0).at("false_positives") == 1);

  // Truth says contact where the vertex passes 5 m to the side: a false
  // negative against that (wrong) truth, exit 1.
  std::vector<std::string> apart = crossing_query_rows(1);
  apart[0] = "5,1,0,1,1,1,1";
  apart[4] = "5,1,0,1,-1,1,1";
  write_file(work / "vertex-face/apart.csv", file_text(apart));
  const hb::test::CommandResult fn = hb::test::run_hapticbench(
      "ccd --json '" + (work / "vertex-face/apart.csv").string() + "'", work);
  CHECK(fn.exit_code == 1);
  CHECK(json_lines(fn.stdout_text).at(0).at("false_negatives") == 1);
}

TEST_CASE("ccd rejects bad input with exit 2 naming the file and line") {
  const hb::test::ScratchDir work("e2e_ccd_bad");
  struct Case {
    std::string name;
    std::vector<std::string> rows;
    std::string expected;
  };
  const std::vector<std::string> good = crossing_query_rows(1);
  auto with_row = [&good](int index, const std::string& row) {
    std::vector<std::string> rows = good;
    rows[index] = row;
    return rows;
  };
  const std::vector<Case> cases = {
      {"vertex-face/short.csv", std::vector<std::string>(good.begin(), good.end() - 1),
       "line 1: expected 8 rows per query"},
      {"vertex-face/word.csv", with_row(0, "0,1,x,1,1,1,1"), "line 1: field ynum"},
      {"vertex-face/zero.csv", with_row(1, "-1,1,-1,0,0,1,1"), "line 2: field yden"},
      {"vertex-face/fields.csv", with_row(0, "0,1,0,1,1,1"), "line 1: expected 7"},
      {"vertex-face/truth.csv", with_row(7, "0,1,1,1,0,1,0"), "line 8: field truth"},
      {"queries/data.csv", good, "cannot tell the query kind"},
  };
  for (const Case& c : cases) {
    write_file(work / c.name, file_text(c.rows));
    const hb::test::CommandResult result =
        hb::test::run_hapticbench("ccd '" + (work / c.name).string() + "'", work);
    INFO(c.name << ": " << result.stderr_text);
    CHECK(result.exit_code == 2);
    CHECK(result.stderr_text.find((work / c.name).string()) != std::string::npos);
    CHECK(result.stderr_text.find(c.expected) != std::string::npos);
    CHECK(result.stdout_text.empty());
  }
  const hb::test::CommandResult missing =
      hb::test::run_hapticbench("ccd '" + (work / "edge-edge/none.csv").string() + "'", work);
  CHECK(missing.exit_code == 2);
  CHECK(missing.stderr_text.find("none.csv") != std::string::npos);
  CHECK(hb::test::run_hapticbench("ccd", work).exit_code == 2);
  CHECK(hb::test::run_hapticbench("ccd --bogus", work).exit_code == 2);
}

}  // namespace
