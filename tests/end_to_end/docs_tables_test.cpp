// End-to-end: the tables the docs repeat from the code are what `hapticbench
// list` prints from it, so they cannot drift: the generators' parameters in
// traces/README.md, the algorithms' parameters in docs/algorithms/README.md,
// the plausible ranges in docs/limits.md, every command's reference in
// docs/command-line.md (the metric table: metric_table_doc_test.cpp); and
// the generators' motion table names every generator once.
#include <catch2/catch.hpp>
#include <filesystem>
#include <set>
#include <string>

#include "harness/trace/generators.h"
#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"

namespace {

using hb::test::kSource;

namespace fs = std::filesystem;

// The doc holds `listed` verbatim, starting at its header line.
void check_doc_holds(const fs::path& doc_path, const std::string& listed) {
  const std::string doc = hb::test::read_text_file(doc_path);
  const std::string header = listed.substr(0, listed.find('\n') + 1);
  const std::size_t at = doc.find(header);
  INFO(doc_path.string() << " should hold, from its line \"" << header
                         << "\", the output of hapticbench list");
  REQUIRE(at != std::string::npos);
  CHECK(doc.substr(at, listed.size()) == listed);
}

TEST_CASE("traces/README.md holds the generators' parameters as list --generators prints them") {
  const hb::test::ScratchDir work("e2e_generator_table");
  const auto listed = hb::test::run_hapticbench("list --generators", work.path());
  REQUIRE(listed.exit_code == 0);
  check_doc_holds(kSource / "traces/README.md", listed.stdout_text);
  // Every generator has parameters listed.
  for (const hb::GeneratorEntry& entry : hb::generator_table())
    CHECK(listed.stdout_text.find("| `" + std::string(entry.name) + "` |") != std::string::npos);
}

TEST_CASE("docs/algorithms/README.md holds the algorithms' parameters as list --params prints") {
  const hb::test::ScratchDir work("e2e_parameter_table");
  const auto listed = hb::test::run_hapticbench("list --params", work.path());
  REQUIRE(listed.exit_code == 0);
  check_doc_holds(kSource / "docs/algorithms/README.md", listed.stdout_text);
  // Every algorithm `list` names ("  <name>  -  <summary>" lines up to
  // "generators:") has parameters listed.
  const std::string names = hb::test::run_hapticbench("list", work.path()).stdout_text;
  const std::size_t end = names.find("generators:");
  int algorithms = 0;
  for (std::size_t at = names.find("\n  "); at < end; at = names.find("\n  ", at + 1)) {
    const std::string name = names.substr(at + 3, names.find("  -  ", at) - at - 3);
    CHECK(listed.stdout_text.find("| `" + name + "` |") != std::string::npos);
    ++algorithms;
  }
  CHECK(algorithms >= 7);
}

TEST_CASE("docs/limits.md holds the plausible ranges as list --limits prints them") {
  const hb::test::ScratchDir work("e2e_limits_table");
  const auto listed = hb::test::run_hapticbench("list --limits", work.path());
  REQUIRE(listed.exit_code == 0);
  CHECK(listed.stdout_text.find("`/coupling/k_t`") != std::string::npos);
  // Two tables, the settings' and the trace files', with prose between.
  const std::size_t gap = listed.stdout_text.find("\n\n");
  REQUIRE(gap != std::string::npos);
  check_doc_holds(kSource / "docs/limits.md", listed.stdout_text.substr(0, gap + 1));
  check_doc_holds(kSource / "docs/limits.md", listed.stdout_text.substr(gap + 2));
  CHECK(listed.stdout_text.find("| speed between consecutive samples |") != std::string::npos);
}

TEST_CASE("docs/command-line.md holds every command's reference as list --commands prints it") {
  const hb::test::ScratchDir work("e2e_command_reference");
  const auto listed = hb::test::run_hapticbench("list --commands", work.path());
  REQUIRE(listed.exit_code == 0);
  check_doc_holds(kSource / "docs/command-line.md", listed.stdout_text);
  // Every command the top-level usage lists ("  <name> <synopsis>" lines)
  // has its section, whose synopsis is the one its --help prints.
  const std::string usage = hb::test::run_hapticbench("--help", work.path()).stdout_text;
  int commands = 0;
  for (std::size_t at = usage.find("\n  "); at != std::string::npos;
       at = usage.find("\n  ", at + 1)) {
    const std::string name = usage.substr(at + 3, usage.find(' ', at + 3) - at - 3);
    if (name.empty() || name[0] == '-' || name[0] == ' ') continue;
    INFO(name);
    CHECK(listed.stdout_text.find("\n## hapticbench " + name + "\n") != std::string::npos);
    const auto help = hb::test::run_hapticbench(name + " --help", work.path());
    CHECK(help.exit_code == 0);
    const std::string synopsis = help.stdout_text.substr(0, help.stdout_text.find('\n'));
    REQUIRE(synopsis.rfind("usage: ", 0) == 0);
    CHECK(listed.stdout_text.find("```text\n" + synopsis.substr(7)) != std::string::npos);
    ++commands;
  }
  CHECK(commands >= 13);
}

TEST_CASE("traces/README.md describes the motion of every generator, once") {
  const std::string doc = hb::test::read_text_file(kSource / "traces/README.md");
  const std::size_t table = doc.find("| generator | motion |");
  REQUIRE(table != std::string::npos);
  const std::size_t end = doc.find("\n\n", table);
  const std::string rows = doc.substr(table, end - table);
  std::set<std::string> described;
  for (std::size_t at = rows.find("\n| `"); at != std::string::npos;
       at = rows.find("\n| `", at + 1)) {
    const std::size_t close = rows.find('`', at + 4);
    CHECK(described.insert(rows.substr(at + 4, close - at - 4)).second);
  }
  std::set<std::string> generators;
  for (const hb::GeneratorEntry& entry : hb::generator_table())
    generators.insert(std::string(entry.name));
  CHECK(described == generators);
}

}  // namespace
