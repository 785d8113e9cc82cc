// The progress display: a live line redrawn at most 10 times a second with
// done/total, elapsed and ETA; plain lines only for phases still running
// after a second; nothing with style none or before the quiet period. The
// clock is the test's; timed phases draw only from advance(), so their
// output does not depend on the background thread.
#include "harness/progress/progress_display.h"

#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

using hb::ProgressDisplay;
using hb::ProgressSettings;
using hb::ProgressStyle;

constexpr const char* kErase = "\r\033[K";

struct FakeClock {
  std::atomic<double> now{0};
  std::function<double()> function() {
    return [this] { return now.load(); };
  }
};

ProgressSettings settings_of(ProgressStyle style, FakeClock& clock, std::size_t width = 200,
                             double quiet_for_s = 0) {
  ProgressSettings settings;
  settings.style = style;
  settings.line_width = width;
  settings.quiet_for_s = quiet_for_s;
  settings.clock = clock.function();
  return settings;
}

std::size_t count_of(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1))
    ++count;
  return count;
}

// The lines drawn in place: the text between erase sequences.
std::vector<std::string> drawn_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t at = 0;
  while ((at = text.find(kErase, at)) != std::string::npos) {
    at += 4;
    const std::size_t end = text.find('\r', at);
    const std::string line = text.substr(at, end == std::string::npos ? end : end - at);
    if (!line.empty()) lines.push_back(line);
  }
  return lines;
}

// A timed phase of `ticks` ticks, `tick_s` seconds of the clock each.
void replay_ticks(ProgressDisplay& display, FakeClock& clock, int64_t ticks, double tick_s) {
  for (int64_t tick = 1; tick <= ticks; ++tick) {
    clock.now = clock.now + tick_s;
    display.advance(tick);
  }
}

}  // namespace

TEST_CASE("ETA text is mm:ss, h:mm:ss from an hour on, seconds rounded up") {
  CHECK(hb::format_eta(0) == "00:00");
  CHECK(hb::format_eta(-4) == "00:00");
  CHECK(hb::format_eta(0.2) == "00:01");
  CHECK(hb::format_eta(59.2) == "01:00");
  CHECK(hb::format_eta(125) == "02:05");
  CHECK(hb::format_eta(3599) == "59:59");
  CHECK(hb::format_eta(3600) == "1:00:00");
  CHECK(hb::format_eta(3725) == "1:02:05");
  // Time spent so far is rounded down.
  CHECK(hb::format_elapsed(0.9) == "00:00");
  CHECK(hb::format_elapsed(61.9) == "01:01");
}

TEST_CASE("counts are grouped by thousands, the time left extrapolates the rate so far") {
  CHECK(hb::with_thousands(0) == "0");
  CHECK(hb::with_thousands(999) == "999");
  CHECK(hb::with_thousands(1000) == "1,000");
  CHECK(hb::with_thousands(3600000) == "3,600,000");
  CHECK(hb::with_thousands(-12345) == "-12,345");
  CHECK(hb::remaining_seconds(10, 0, 100) < 0);
  CHECK(hb::remaining_seconds(10, 25, 100) == Approx(30));
  CHECK(hb::remaining_seconds(10, 100, 100) == 0);
}

TEST_CASE("a timed phase is redrawn from advance(), at most every 0.1 s, with ticks, ETA") {
  FakeClock clock;
  std::ostringstream out;
  {
    ProgressDisplay display(out, settings_of(ProgressStyle::kBar, clock));
    display.set_prefix("[1/2] ");
    display.task("press / god_object");
    display.phase("timing pass", 1000, true);
    replay_ticks(display, clock, 1000, 0.001);  // 1 s of ticks
  }
  const std::string text = out.str();
  const std::vector<std::string> lines = drawn_lines(text);
  // The phase's first line, then one every 128 ticks (0.1 s is 100 ticks,
  // and the clock is read every 64): never more than 10 a second.
  REQUIRE(lines.size() >= 5);
  CHECK(lines.size() <= 11);
  CHECK(lines.front().rfind("[1/2] press / god_object: timing pass 0/1,000 ticks 0%", 0) == 0);
  CHECK(count_of(text, "[1/2] press / god_object: timing pass 640/1,000 ticks 64% elapsed 00:00, "
                       "ETA 00:01") == 1);
  // Closing erases the line: the text ends with the erase sequence.
  CHECK(text.size() >= 4);
  CHECK(text.substr(text.size() - 4) == kErase);
}

TEST_CASE("plain lines: one for a phase still running after a second, none for quick ones") {
  FakeClock clock;
  std::ostringstream out;
  {
    ProgressDisplay display(out, settings_of(ProgressStyle::kPlain, clock));
    display.task("press / penalty");
    display.phase("timing pass", 1000, true);
    replay_ticks(display, clock, 1000, 0.0005);  // 0.5 s: no line
    display.phase("evaluation pass", 3000, true);
    replay_ticks(display, clock, 3000, 0.001);  // 3 s: one line
    display.finish_task();
  }
  const std::string text = out.str();
  CHECK(text.find('\r') == std::string::npos);
  CHECK(count_of(text, "\n") == 1);
  CHECK(count_of(text, "press / penalty: evaluation pass (3,000 ticks)\n") == 1);
  CHECK(text.find("timing pass") == std::string::npos);
}

TEST_CASE("in untimed work the background thread writes the line of a long stage") {
  FakeClock clock;
  std::ostringstream out;
  ProgressDisplay display(out, settings_of(ProgressStyle::kPlain, clock));
  display.task("meshes / sensation_preserving");
  display.phase("preprocessing");
  {
    const hb::ScopedBuildProgressListener listener(&display);
    hb::announce_cached_build("convex hierarchy of bunny", false);
    hb::announce_build_progress(3, 4);
  }
  clock.now = 2.0;  // the stage has run for 2 s; the thread looks every 0.1 s
  for (int wait = 0; wait < 50 && out.tellp() == 0; ++wait)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  display.close();
  CHECK(out.str() ==
        "[00:02] meshes / sensation_preserving: preprocessing, convex hierarchy of bunny: "
        "building\n");
}

TEST_CASE("style none writes nothing, a quiet period keeps quick commands silent") {
  FakeClock clock;
  std::ostringstream none_out;
  {
    ProgressDisplay display(none_out, settings_of(ProgressStyle::kNone, clock));
    display.task("t");
    display.phase("timing pass", 1000, true);
    replay_ticks(display, clock, 1000, 0.01);
    display.print_above(none_out, "table\n");
  }
  CHECK(none_out.str() == "table\n");

  clock.now = 0;
  std::ostringstream quiet_out;
  ProgressDisplay display(quiet_out, settings_of(ProgressStyle::kBar, clock, 200, 1.0));
  display.task("t");
  display.phase("comparing", 1000, true, "scenarios");
  replay_ticks(display, clock, 900, 0.001);  // 0.9 s: still quiet
  CHECK(quiet_out.str().empty());
  replay_ticks(display, clock, 100, 0.002);
  CHECK(quiet_out.str().find("t: comparing") != std::string::npos);
  CHECK(quiet_out.str().find("/1,000 scenarios") != std::string::npos);
}

TEST_CASE("a narrow terminal shortens the names, never the numbers") {
  FakeClock clock;
  std::ostringstream out;
  {
    ProgressDisplay display(out, settings_of(ProgressStyle::kBar, clock, 70));
    display.task("a_scenario_with_a_really_long_name_indeed / sensation_preserving_measured");
    display.phase("evaluation pass + oracle", 2000, true);
    replay_ticks(display, clock, 2000, 0.001);
  }
  const std::vector<std::string> lines = drawn_lines(out.str());
  REQUIRE(lines.size() >= 2);
  for (const std::string& line : lines) {
    CHECK(line.size() <= 69);
    CHECK(line.find("ETA ") != std::string::npos);
    CHECK(line.find("/2,000 ticks") != std::string::npos);
  }
  CHECK(lines.back().rfind("a_s", 0) == 0);  // both ends of the name stay
  CHECK(lines.back().find("elapsed") == std::string::npos);  // dropped before the ETA
  CHECK(lines.back().find("...") != std::string::npos);
}

TEST_CASE("text printed above the live line erases it first and redraws it after") {
  FakeClock clock;
  std::ostringstream out;
  ProgressDisplay display(out, settings_of(ProgressStyle::kBar, clock));
  display.task("t");
  display.phase("timing pass", 100, true);
  display.print_above(out, "scenario t -> out/t/\n");
  display.close();
  const std::string text = out.str();
  const std::string line = "t: timing pass 0/100 ticks 0% elapsed 00:00, ETA --:--";
  CHECK(text == std::string(kErase) + line + kErase + "scenario t -> out/t/\n" + kErase + line +
                    kErase);
}
