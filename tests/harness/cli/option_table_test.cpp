// A command's option table: what it parses, what it refuses and with which
// message, and the help and Markdown it writes from the same rows.
#include "harness/cli/option_table.h"

#include <catch2/catch.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace hb {
namespace {

struct Limits {
  double ratio = 1.25;
};

struct Arguments {
  std::string input;
  std::vector<std::string> more;
  bool gate = false;
  std::optional<std::string> out;
  std::vector<std::string> algos;
  double alpha = 0.01;
  long long jobs = 1;
  std::string label;
  double low = 0, high = 0;
  Limits limits;
  std::optional<ProgressStyle> progress;
};

using Table = OptionTable<Arguments>;

const Table& table() {
  static const Table made(
      {"demo", {"Does what a demo does."}, {"A note after the options."}, {"--explain"}},
      {Table::positional("INPUT", "the input", 1, 1, &Arguments::input),
       Table::positional("MORE", "more inputs", 0, 2, &Arguments::more),
       Table::flag("--gate", "exit 1 on a regression", &Arguments::gate),
       Table::value("--out", "DIR", "where to write", &Arguments::out).with_default("out/"),
       Table::value("--algo", "NAME", "only this algorithm", &Arguments::algos),
       Table::number("--alpha", "X", "significance level", probability(), &Arguments::alpha),
       Table::whole("--jobs", "N", "jobs at a time", {1, 8, ""}, &Arguments::jobs),
       Table::number("--ratio", "X", "a ratio of the limits", at_least(1),
                     member_of(&Arguments::limits, &Limits::ratio)),
       Table::value("--label", "LABEL", "the label|its pipe", &Arguments::label).required(),
       Table::values("--range", "LO HI", "the range",
                     [](Arguments& parsed, const std::vector<std::string>& values) {
                       parsed.low = number_in("--range LO", values[0], any_number());
                       parsed.high = number_in("--range HI", values[1], any_number());
                     }),
       Table::progress(&Arguments::progress), Table::quiet(&Arguments::progress)});
  return made;
}

std::vector<std::string> with_label(std::vector<std::string> args) {
  args.insert(args.end(), {"--label", "L"});
  return args;
}

// The message of the UsageError parsing `args` throws; empty when none.
std::string refusal(const std::vector<std::string>& args) {
  try {
    table().parse(args);
  } catch (const UsageError& error) {
    return error.message;
  }
  return "";
}

TEST_CASE("an option table reads flags, values, numbers and positionals into the arguments") {
  const Arguments parsed =
      table().parse({"in", "--gate",  "--out",   "folder",  "--algo", "a", "--algo",
                     "b",  "m1",      "--alpha", "0.5",     "--jobs", "8", "--ratio",
                     "2",  "--label", "L",       "--range", "-1",     "3", "--quiet"});
  CHECK(parsed.input == "in");
  CHECK(parsed.more == std::vector<std::string>{"m1"});
  CHECK(parsed.gate);
  CHECK(parsed.out == "folder");
  CHECK(parsed.algos == std::vector<std::string>{"a", "b"});  // repeatable: each kept
  CHECK(parsed.alpha == 0.5);
  CHECK(parsed.jobs == 8);
  CHECK(parsed.limits.ratio == 2);
  CHECK(parsed.label == "L");
  CHECK(parsed.low == -1);
  CHECK(parsed.high == 3);
  CHECK(parsed.progress == ProgressStyle::kNone);
}

TEST_CASE("an option table leaves what is not given at the arguments' defaults") {
  const Arguments parsed = table().parse(with_label({"in"}));
  CHECK_FALSE(parsed.gate);
  CHECK_FALSE(parsed.out);
  CHECK(parsed.algos.empty());
  CHECK(parsed.alpha == 0.01);
  CHECK(parsed.limits.ratio == 1.25);
  CHECK_FALSE(parsed.progress);
}

TEST_CASE("an option table refuses numbers outside their range, naming the option and the value") {
  CHECK(refusal(with_label({"in", "--alpha", "0"})) ==
        "--alpha: expected a probability in (0, 1], got \"0\"");
  CHECK(refusal(with_label({"in", "--alpha", "x"})) ==
        "--alpha: expected a probability in (0, 1], got \"x\"");
  CHECK(refusal(with_label({"in", "--jobs", "9"})) ==
        "--jobs: expected a whole number in [1, 8], got \"9\"");
  CHECK(refusal(with_label({"in", "--jobs", "1.5"})) ==
        "--jobs: expected a whole number in [1, 8], got \"1.5\"");
  CHECK(refusal(with_label({"in", "--ratio", "0.5"})) ==
        "--ratio: expected a number >= 1, got \"0.5\"");
  CHECK(refusal(with_label({"in", "--range", "1", "inf"})) ==
        "--range HI: expected a number, got \"inf\"");
  CHECK(refusal(with_label({"in", "--progress", "fancy"})) ==
        "--progress: expected bar, plain or none, got \"fancy\"");
}

TEST_CASE("an option table refuses unknown options, missing values and missing arguments") {
  CHECK(refusal(with_label({"in", "--bogus"})) == "unknown option --bogus");
  CHECK(refusal(with_label({"in", "-x"})) == "unknown option -x");
  CHECK(refusal({"in", "--label"}) == "--label needs a value");
  // A forgotten value is not taken from the next option.
  CHECK(refusal(with_label({"in", "--out", "--quiet"})) ==
        "--out needs a value, got the option --quiet");
  CHECK(refusal({"in", "--label", "L", "--range", "1"}) == "--range needs a value");
  CHECK(refusal(with_label({"in", "--range", "1"})) ==
        "--range needs a value, got the option --label");
  CHECK(refusal(with_label({})) == "missing INPUT");
  CHECK(refusal({"in"}) == "missing --label LABEL");
  CHECK(refusal(with_label({"in", "m1", "m2", "m3"})) == "unexpected argument \"m3\"");
  CHECK(refusal(with_label({"in", "m1", "m2"})).empty());
}

TEST_CASE("an option table asks for help at -h or --help, not in a value") {
  CHECK_THROWS_AS(table().parse({"--help"}), HelpRequested);
  CHECK_THROWS_AS(table().parse({"in", "-h", "--bogus"}), HelpRequested);
  CHECK(table().parse(with_label({"in", "--algo", "-h"})).algos == std::vector<std::string>{"-h"});
}

TEST_CASE("an option table's help has the synopsis and the aligned rows") {
  const std::string usage = table().usage();
  INFO(usage);
  // Positionals first, then the options a run needs, then the others.
  CHECK(usage.rfind("usage: hapticbench demo INPUT [MORE...] --label LABEL [--gate] [--out DIR]",
                    0) == 0);
  CHECK(usage.find("[--algo NAME]...") != std::string::npos);
  CHECK(usage.find("\n       hapticbench demo --explain\n") != std::string::npos);
  CHECK(usage.find("\n  Does what a demo does.\n") != std::string::npos);
  CHECK(usage.find("\n  --out DIR         where to write (default out/)\n") != std::string::npos);
  CHECK(usage.find("\n  --algo NAME       only this algorithm (repeatable)\n") !=
        std::string::npos);
  CHECK(usage.find("\n  A note after the options.\n") != std::string::npos);
  std::istringstream lines(usage);
  for (std::string line; std::getline(lines, line);) CHECK(line.size() <= 92);
}

TEST_CASE("an option table's reference is Markdown of the same rows") {
  const std::string markdown = reference_markdown(table().syntax(), "a demo command");
  INFO(markdown);
  CHECK(markdown.rfind("## hapticbench demo\n\nA demo command.\n\n```text\nhapticbench demo INPUT",
                       0) == 0);
  CHECK(markdown.find("| `--out DIR` | where to write | out/ |\n") != std::string::npos);
  CHECK(markdown.find("| `--label LABEL` | the label\\|its pipe (required) |  |\n") !=
        std::string::npos);
  CHECK(markdown.find("| `--algo NAME` | only this algorithm (repeatable) |  |\n") !=
        std::string::npos);
  CHECK(markdown.find("\n\nA note after the options.\n") != std::string::npos);
}

}  // namespace
}  // namespace hb
