// Progress lines: one per finished job off a terminal, one redrawn line on
// a terminal; ETA from the rate so far. The clock is the test's.
#include "harness/sweep/sweep_progress.h"

#include <catch2/catch.hpp>
#include <sstream>
#include <string>

namespace {
std::size_t count_of(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1))
    ++count;
  return count;
}
}  // namespace

TEST_CASE("the remaining time extrapolates the rate of the finished jobs") {
  // 2 of 5 done in 10 s: 3 left at 5 s each.
  CHECK(hb::estimate_remaining_seconds(10, 2, 5) == Approx(15));
  CHECK(hb::estimate_remaining_seconds(10, 5, 5) == 0);
  CHECK(hb::estimate_remaining_seconds(10, 0, 5) < 0);
}

TEST_CASE("off a terminal, each finished job gets one line and nothing is redrawn") {
  std::ostringstream out;
  double now = 0;
  hb::SweepProgress progress(out, 3, /*terminal=*/false, 100, [&] { return now; });
  progress.started("a__k=1");
  progress.started("a__k=2");
  now = 4;
  progress.finished("a__k=1", "ok", 3.96, true);
  progress.refresh();
  progress.finished("a__k=2", "budgets failed", 4.0, true);
  progress.close();
  CHECK(out.str() == "[1/3] a__k=1: ok (4.0 s)\n[2/3] a__k=2: budgets failed (4.0 s)\n");
}

TEST_CASE("on a terminal, one line is redrawn with the job and the ETA") {
  std::ostringstream out;
  double now = 0;
  hb::SweepProgress progress(out, 3, /*terminal=*/true, 100, [&] { return now; });
  progress.started("first");
  CHECK(out.str() == "\r\033[K[0/3] first ... ETA --:--");
  now = 10;
  progress.started("second");
  progress.finished("first", "ok", 10, true);
  // One job in 10 s, two to go: 20 s.
  const std::string after_first = out.str();
  CHECK(after_first.substr(after_first.rfind('\r')) == "\r\033[K[1/3] second ... ETA 00:20");
  CHECK(count_of(after_first, "\n") == 0);  // an ok job leaves no line behind

  progress.finished("second", "CRASHED (exit code 3)", 2, false);
  CHECK(count_of(out.str(), "[2/3] second: CRASHED (exit code 3) (2.0 s)\n") == 1);

  // refresh() redraws at most once a second.
  const std::size_t before = out.str().size();
  progress.refresh();
  CHECK(out.str().size() == before);
  now = 11.5;
  progress.refresh();
  CHECK(out.str().size() > before);
  progress.close();
  CHECK(out.str().substr(out.str().rfind('\r')) == "\r\033[K[2/3] done in 00:12\n");
}

TEST_CASE("a long job name is cut from the front to keep the line within its width") {
  std::ostringstream out;
  hb::SweepProgress progress(out, 9, /*terminal=*/true, 40, [] { return 0.0; });
  const std::string name = "a_rather_long_scenario_name__contact_stiffness=100000";
  progress.started(name);
  const std::string line = out.str().substr(std::string("\r\033[K").size());
  CHECK(line.size() <= 40);
  CHECK(line.find("...") != std::string::npos);
  CHECK(line.find("stiffness=100000 ... ETA --:--") != std::string::npos);
}
