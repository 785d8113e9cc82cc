// End-to-end: `hapticbench report` on the smoke suite, opened in headless
// Chromium; on a coupling stiffness sweep of summary-only run folders; and on
// bad input.
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"
#include "tests/support/scratch_dir.h"

namespace {

using hb::test::CommandResult;

using hb::test::kSource;
using hb::test::listing;

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kChromium = "/usr/bin/chromium";

// Runs a shell command in `work`; its output goes to files outside `work`'s
// listing checks (stdout.txt and stderr.txt are named in them).
CommandResult shell(const std::string& command, const fs::path& work) {
  const fs::path out = work / "stdout.txt";
  const fs::path err = work / "stderr.txt";
  const std::string line = "cd '" + work.string() + "' && " + command + " > '" + out.string() +
                           "' 2> '" + err.string() + "'";
  const int status = std::system(line.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, hb::test::read_text_file(out),
          hb::test::read_text_file(err)};
}

CommandResult hapticbench(const std::string& args, const fs::path& work,
                          const std::string& environment = "") {
  return shell(environment + " '" + hb::test::hapticbench_bin() + "' " + args, work);
}

// Whether any tick of a ticks CSV has a penetration value (column penetration_m).
bool has_penetration(const fs::path& ticks) {
  std::ifstream in(ticks);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream header(line);
  for (std::string name; std::getline(header, name, ',');) names.push_back(name);
  std::size_t column = names.size();
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == "penetration_m") column = i;
  REQUIRE(column < names.size());
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string field;
    for (std::size_t i = 0; i <= column; ++i) std::getline(row, field, ',');
    if (!field.empty() && std::isfinite(std::stod(field))) return true;
  }
  return false;
}

// Value of an attribute of the first element matching `tag_pattern` (regex) in `html`.
std::string attribute(const std::string& html, const std::string& tag_pattern,
                      const std::string& name) {
  std::smatch tag;
  if (!std::regex_search(html, tag, std::regex(tag_pattern))) return "";
  std::smatch value;
  const std::string text = tag.str();
  if (!std::regex_search(text, value, std::regex(name + "=\"([^\"]*)\""))) return "";
  return value[1];
}

// The text of the table row whose opening tag contains `opening`, up to </tr>.
std::string row_with(const std::string& html, const std::string& opening) {
  const std::size_t at = html.find(opening);
  if (at == std::string::npos) return "";
  return html.substr(at, html.find("</tr>", at) - at);
}

// How a table cell holding exactly `value` appears in the page: ">value<".
std::string cell_text(const std::string& value) {
  std::string text = ">";
  text.append(value).append("<");
  return text;
}

std::string microseconds(double ns) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", ns / 1000.0);
  return text;
}

TEST_CASE("the smoke suite's report opens offline in a browser with every figure decoded") {
  const hb::test::ScratchDir work_dir("e2e_report_smoke");
  const fs::path& work = work_dir.path();
  const CommandResult run =
      hapticbench("run " + (kSource / "scenarios/smoke").string() + "/*.json --out runs", work);
  INFO(run.stderr_text);
  REQUIRE(run.exit_code == 0);

  const CommandResult report = hapticbench("report runs", work);
  INFO(report.stderr_text);
  REQUIRE(report.exit_code == 0);
  CHECK(report.stdout_text.find("report.html") != std::string::npos);
  // The default page name, and no temporary file left beside it.
  CHECK(listing(work) == std::set<std::string>{"report.html", "runs"});
  const std::string html = hb::test::read_text_file(work / "report.html");
  // The explicit integrator that diverges on the stiff coupling is expected
  // to: the summary table says so, and the banner passes.
  CHECK(html.find("(expected)</td>") != std::string::npos);
  CHECK(html.find("runs are stable (or unstable where the scenario expects it) and within "
                  "their budgets.") != std::string::npos);

  // Self-contained: no external resource, every figure an inline PNG.
  for (const char* external : {"src=\"http", "href=\"http", "<link", "<script src", "url(http",
                               "@import", "src=\"file:", "src=\"/"})
    CHECK(html.find(external) == std::string::npos);
  std::size_t inline_images = 0;
  for (std::size_t at = html.find("<img"); at != std::string::npos;
       at = html.find("<img", at + 1)) {
    const std::size_t src = html.find("src=\"", at);
    CHECK(html.compare(src, 27, "src=\"data:image/png;base64,") == 0);
    ++inline_images;
  }

  // The figures each scenario must have, worked out from the run folders.
  std::vector<std::string> expected_figures = {"fig-pareto", "fig-passivity"};
  std::vector<json> summaries;
  for (const auto& entry : fs::directory_iterator(work / "runs")) {
    const json summary = json::parse(hb::test::read_text_file(entry.path() / "summary.json"));
    summaries.push_back(summary);
    const std::string slug = "scenario-" + summary.at("scenario").at("name").get<std::string>();
    bool penetration = false;
    for (const json& run : summary.at("runs"))
      penetration |=
          has_penetration(entry.path() / ("ticks_" + run.at("label").get<std::string>() + ".csv"));
    for (const char* kind : {"force", "torque", "timing"})
      expected_figures.push_back(std::string("fig-") + kind + "-" + slug);
    if (penetration) expected_figures.push_back("fig-penetration-" + slug);
  }
  REQUIRE(summaries.size() >= 4);
  CHECK(inline_images >= expected_figures.size());

  // Load it in headless Chromium, offline, and read the DOM after the load event.
  if (!fs::exists(kChromium))
    FAIL("headless Chromium is needed at " << kChromium
                                           << ": scripts/setup installs it (package chromium)");
  const hb::test::ScratchDir profile_dir("e2e_report_chromium_profile");
  const fs::path& profile = profile_dir.path();  // fresh: nothing cached from before
  const CommandResult browser =
      shell("timeout 180 '" + kChromium.string() +
                "' --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
                "--disable-background-networking --disable-component-update --disable-sync "
                "--user-data-dir='" +
                profile.string() + "' --dump-dom 'file://" + (work / "report.html").string() + "'",
            work);
  INFO(browser.stderr_text);
  REQUIRE(browser.exit_code == 0);
  const std::string dom = browser.stdout_text;
  fs::remove_all(profile);
  REQUIRE(dom.find("</body>") != std::string::npos);

  // The page's own script counted the images after load: all decoded.
  const std::string figures = attribute(dom, "<body[^>]*>", "data-figures");
  const std::string loaded = attribute(dom, "<body[^>]*>", "data-loaded");
  REQUIRE_FALSE(figures.empty());
  CHECK(loaded == figures);
  CHECK(std::stoul(figures) == inline_images);

  // The same run, its instability no longer expected: the banner fails and
  // names it, the summary table marks it.
  const fs::path stiff = work / "unexpected" / "stiff_coupling_explicit_vs_implicit";
  fs::create_directories(stiff.parent_path());
  fs::copy(work / "runs" / "stiff_coupling_explicit_vs_implicit", stiff);
  json summary = json::parse(hb::test::read_text_file(stiff / "summary.json"));
  for (json& run : summary.at("runs")) {
    json& verdict = run.at("stability").at("verdict");
    if (verdict.at("stable") == true) continue;
    verdict["expected_unstable"] = nullptr;
    verdict["pass"] = false;
  }
  std::ofstream(stiff / "summary.json") << summary.dump(2);
  const CommandResult failing = hapticbench("report unexpected --out unexpected.html", work);
  INFO(failing.stderr_text);
  REQUIRE(failing.exit_code == 0);
  const std::string failing_html = hb::test::read_text_file(work / "unexpected.html");
  CHECK(failing_html.find("runs are unstable where that is not expected: "
                          "stiff_coupling_explicit_vs_implicit/explicit_euler (diverged") !=
        std::string::npos);
  CHECK(failing_html.find("<td class=\"text fail\">✗ diverged") != std::string::npos);
  CHECK(std::stoul(figures) >= expected_figures.size());
  for (const std::string& id : expected_figures) {
    INFO(id);
    CHECK(dom.find("<img id=\"" + id + "\"") != std::string::npos);
  }

  // One summary table row per scenario and label, with the summary's numbers and verdict.
  for (const json& summary : summaries) {
    const std::string scenario = summary.at("scenario").at("name");
    for (const json& run : summary.at("runs")) {
      const std::string label = run.at("label");
      bool pass = true;
      for (const json& budget : run.at("budgets")) pass &= budget.at("pass").get<bool>();
      INFO(scenario << "/" << label);
      const std::string row =
          row_with(dom, "<tr data-scenario=\"" + scenario + "\" data-label=\"" + label +
                            "\" data-verdict=\"" + (pass ? "pass" : "fail") + "\"");
      REQUIRE_FALSE(row.empty());
      CHECK(row.find(cell_text(std::to_string(run.at("timing").at("ticks").get<int>()))) !=
            std::string::npos);
      CHECK(row.find(cell_text(microseconds(run.at("timing").at("step_ns").at("p99")))) !=
            std::string::npos);
      CHECK(row.find(run.at("stability").at("diverged").get<bool>() ? ">yes<" : ">no<") !=
            std::string::npos);
    }
  }
}

// A summary-only run folder of the stiffness sweep: two integrators at k_t,
// explicit Euler diverged above b_t / dt = 5000 N/m, implicit never.
json sweep_summary(double k_t) {
  auto run = [&](const std::string& integrator, bool diverged) {
    return json{{"algorithm", "coupling_only"},
                {"label", integrator},
                {"params", {{"integrator", integrator}, {"proxy_mass_kg", 0.2}}},
                {"timing",
                 {{"ticks", 5000},
                  {"step_ns", {{"p50", 600}, {"p90", 700}, {"p99", 900}, {"max", 2000}}},
                  {"over_budget", 0},
                  {"step_ns_sample", {500, 600, 650, 700, 900, 2000}}}},
                {"accuracy", {{"force_err_rms_n", nullptr}, {"penetration_max_m", nullptr}}},
                {"stability",
                 {{"nonfinite", 0},
                  {"diverged", diverged},
                  {"passivity_energy_min_j", 0.0},
                  {"max_proxy_separation_m", diverged ? 1e30 : 0.01},
                  {"verdict",
                   {{"stable", !diverged},
                    {"failed", diverged ? json("diverged") : json(nullptr)},
                    {"reason", diverged ? "diverged at tick 40" : "E_min 0 mJ"}}}}},
                {"budgets", json::array()}};
  };
  const std::string name = "stiff__k_t=" + std::to_string(static_cast<int>(k_t));
  return json{{"schema_version", 1},
              {"context",
               {{"commit", "abc"},
                {"build_type", "Release"},
                {"compiler", "g++"},
                {"cpu", "cpu"},
                {"date", "2026-01-01T00:00:00Z"}}},
              {"scenario",
               {{"name", name},
                {"hash", "0"},
                {"coupling", {{"k_t", k_t}, {"b_t", 5}, {"k_r", 5}, {"b_r", 0.05}}}}},
              {"runs", {run("explicit_euler", k_t > 5000), run("implicit_euler", false)}}};
}

TEST_CASE("a coupling stiffness sweep gives each integrator's largest stable k_t") {
  const hb::test::ScratchDir work_dir("e2e_report_sweep");
  const fs::path& work = work_dir.path();
  // The folders of a sweep over /coupling/k_t, with the sweep.json that
  // `hapticbench sweep` writes beside them; k_t is read from the summaries.
  const std::vector<double> stiffnesses = {1000.0, 3000.0, 4950.0, 5050.0, 8000.0};
  json jobs = json::array();
  for (double k_t : stiffnesses) {
    const json summary = sweep_summary(k_t);
    const std::string name = summary.at("scenario").at("name").get<std::string>();
    fs::create_directories(work / "sweep" / name);
    std::ofstream(work / "sweep" / name / "summary.json") << summary.dump(2);
    jobs.push_back({{"index", jobs.size()},
                    {"name", name},
                    {"scenario", "../smoke/stiff.json"},
                    {"grid", {{"/coupling/k_t", k_t}, {"/trace/duration_s", 5}}},
                    {"status", "ok"}});
  }
  std::ofstream(work / "sweep" / "sweep.json") << json{
      {"name", "stiff"},
      {"scenarios", {"../smoke/stiff.json"}},
      {"grid", {{"/coupling/k_t", stiffnesses}, {"/trace/duration_s", {5}}}},
      {"jobs", jobs}}.dump(2);
  const CommandResult report = hapticbench("report sweep --out pages/sweep.html", work);
  INFO(report.stderr_text);
  REQUIRE(report.exit_code == 0);
  const std::string html = hb::test::read_text_file(work / "pages/sweep.html");

  const std::string explicit_row = row_with(html, "<tr data-integrator=\"explicit_euler\"");
  const std::string implicit_row = row_with(html, "<tr data-integrator=\"implicit_euler\"");
  CHECK(explicit_row.find("class=\"largest-stable\">4950<") != std::string::npos);
  CHECK(explicit_row.find("class=\"smallest-unstable\">5050<") != std::string::npos);
  CHECK(implicit_row.find("class=\"largest-stable\">8000<") != std::string::npos);
  CHECK(implicit_row.find("class=\"smallest-unstable\">none<") != std::string::npos);
  CHECK(html.find("id=\"fig-stiffness-sweep-0\"") != std::string::npos);

  // Summary-only folders: no time series, said on the page; step times from the sample.
  CHECK(html.find("id=\"fig-force-") == std::string::npos);
  CHECK(html.find("No ticks CSV") != std::string::npos);
  CHECK(html.find("data-sweep=\"stiff\"") != std::string::npos);
  CHECK(html.find("id=\"fig-timing-scenario-stiff__k_t-5050\"") != std::string::npos);
  for (const char* k : {"1000", "3000", "4950", "5050", "8000"})
    for (const char* label : {"explicit_euler", "implicit_euler"})
      CHECK(html.find(std::string("data-scenario=\"stiff__k_t=") + k + "\" data-label=\"" + label +
                      "\"") != std::string::npos);

  // Without the sweep's index the folders are separate scenarios: no sweep.
  fs::remove(work / "sweep" / "sweep.json");
  REQUIRE(hapticbench("report sweep --out pages/alone.html", work).exit_code == 0);
  CHECK(hb::test::read_text_file(work / "pages/alone.html").find("fig-stiffness-sweep") ==
        std::string::npos);
}

TEST_CASE("stress runs and stability results make the stress matrix and the margin table") {
  const hb::test::ScratchDir work_dir("e2e_report_stress");
  const fs::path& work = work_dir.path();
  json summary = sweep_summary(8000);  // explicit Euler diverged, implicit did not
  summary["scenario"]["name"] = "thin_wall";
  summary["scenario"]["tags"] = {"stress"};
  summary["runs"][1]["stability"]["tunnelled"] = 0;
  fs::create_directories(work / "stress/runs/thin_wall");
  std::ofstream(work / "stress/runs/thin_wall/summary.json") << summary.dump(2);
  // Run the search for real: a margin folder holds only stability.json.
  const CommandResult search = hapticbench(
      "stability " + (kSource / "scenarios/margins/sphere_on_box.json").string() +
          " --label penalty_explicit --param /coupling/k_t --range 1000 100000 --tolerance 0.1"
          " --out stress/margins/k_t",
      work);
  REQUIRE(search.exit_code == 0);

  // Given the margins folder alone, and given both.
  const CommandResult alone = hapticbench("report stress/margins --out margins.html", work);
  INFO(alone.stderr_text);
  REQUIRE(alone.exit_code == 0);
  CHECK(alone.stdout_text.find("1 stability margin") != std::string::npos);
  const CommandResult report = hapticbench("report stress --out stress.html", work);
  INFO(report.stderr_text);
  REQUIRE(report.exit_code == 0);
  const std::string html = hb::test::read_text_file(work / "stress.html");
  CHECK(html.find("id='stress-matrix'") != std::string::npos);
  CHECK(html.find("data-pass=\"false\">✗ diverged at tick 40") != std::string::npos);
  CHECK(html.find("data-pass=\"true\">") != std::string::npos);
  const std::string margins = row_with(html, "<tr><td class=\"text\">margin_sphere_on_box");
  CHECK(margins.find("penalty_explicit") != std::string::npos);
  CHECK(margins.find("explicit_euler") != std::string::npos);
  CHECK(margins.find("unstable at") != std::string::npos);
}

TEST_CASE("report rejects bad input with exit code 2 and writes nothing") {
  SECTION("a folder without any summary.json") {
    const hb::test::ScratchDir work_dir("e2e_report_no_summary");
    const fs::path& work = work_dir.path();
    fs::create_directories(work / "empty/nested");
    std::ofstream(work / "empty/nested/ticks_x.csv") << "tick\n";
    const CommandResult result = hapticbench("report empty", work);
    CHECK(result.exit_code == 2);
    CHECK(result.stderr_text.find("empty") != std::string::npos);
    CHECK(result.stderr_text.find("summary.json") != std::string::npos);
    CHECK(listing(work) == std::set<std::string>{"empty"});
  }
  SECTION("a summary of another schema version, beside a good one") {
    const hb::test::ScratchDir work_dir("e2e_report_schema");
    const fs::path& work = work_dir.path();
    fs::create_directories(work / "runs/a");
    fs::create_directories(work / "runs/b");
    json good = sweep_summary(1000);
    std::ofstream(work / "runs/a/summary.json") << good.dump();
    good["schema_version"] = 2;
    std::ofstream(work / "runs/b/summary.json") << good.dump();
    const CommandResult result = hapticbench("report runs --out report.html", work);
    CHECK(result.exit_code == 2);
    CHECK(result.stderr_text.find("runs/b/summary.json") != std::string::npos);
    CHECK(result.stderr_text.find("/schema_version") != std::string::npos);
    CHECK(listing(work) == std::set<std::string>{"runs"});
  }
  SECTION("a summary that is not JSON") {
    const hb::test::ScratchDir work_dir("e2e_report_malformed");
    const fs::path& work = work_dir.path();
    fs::create_directories(work / "run");
    std::ofstream(work / "run/summary.json") << "{ \"schema_version\": 1,\n  \"runs\": [\n";
    const CommandResult result = hapticbench("report run", work);
    CHECK(result.exit_code == 2);
    CHECK(result.stderr_text.find("run/summary.json") != std::string::npos);
    CHECK(result.stderr_text.find("line") != std::string::npos);
    CHECK(listing(work) == std::set<std::string>{"run"});
  }
  SECTION("a ticks CSV with a field that is not a number") {
    const hb::test::ScratchDir work_dir("e2e_report_bad_ticks");
    const fs::path& work = work_dir.path();
    fs::create_directories(work / "run");
    std::ofstream(work / "run/summary.json") << sweep_summary(1000).dump();
    std::ofstream(work / "run/ticks_explicit_euler.csv")
        << "tick,t_ns,fx,fy,fz,tx,ty,tz,penetration_m,step_ns\n"
        << "0,0,0,0,0,0,0,0,0,800\n"
        << "1,1000000,0,oops,0,0,0,0,0,800\n";
    const CommandResult result = hapticbench("report run", work);
    CHECK(result.exit_code == 2);
    CHECK(result.stderr_text.find("ticks_explicit_euler.csv") != std::string::npos);
    CHECK(result.stderr_text.find("line 3") != std::string::npos);
    CHECK(listing(work) == std::set<std::string>{"run"});
  }
  SECTION("a Python without matplotlib") {
    const hb::test::ScratchDir work_dir("e2e_report_no_matplotlib");
    const fs::path& work = work_dir.path();
    fs::create_directories(work / "run");
    std::ofstream(work / "run/summary.json") << sweep_summary(1000).dump();
    const CommandResult result = hapticbench("report run", work, "HAPTICBENCH_PYTHON=/bin/false");
    CHECK(result.exit_code == 2);
    CHECK(result.stderr_text.find("python3-matplotlib") != std::string::npos);
    CHECK(listing(work) == std::set<std::string>{"run"});
  }
  SECTION("usage mistakes") {
    const hb::test::ScratchDir work_dir("e2e_report_usage");
    const fs::path& work = work_dir.path();
    CHECK(hapticbench("report", work).exit_code == 2);
    CHECK(hapticbench("report --bogus x", work).exit_code == 2);
    CHECK(hapticbench("report no_such_folder", work).exit_code == 2);
    CHECK(listing(work).empty());
  }
}

// A renderer standing in for render_report.py: runs `body` (shell) and
// exits with `exit_code`, writing no page.
fs::path fake_renderer(const fs::path& folder, int exit_code) {
  fs::create_directories(folder);
  std::ofstream(folder / "render_report.py") << "import sys\nsys.exit(" << exit_code << ")\n";
  return folder;
}

TEST_CASE("report writes through no planted name and leaves nothing when no page was drawn") {
  const hb::test::ScratchDir work_dir("e2e_report_planted");
  const fs::path& work = work_dir.path();
  fs::create_directories(work / "run");
  std::ofstream(work / "run/summary.json") << sweep_summary(1000).dump();
  std::ofstream(work / "victim.txt") << "the user's file\n";
  for (const int renderer_exit : {0, 1}) {
    CAPTURE(renderer_exit);
    const fs::path renderer = fake_renderer(work / "renderer", renderer_exit);
    // `exec` keeps the shell's process id, so the names the tool would take
    // from its id are known in advance: symlinks to the victim wait there.
    const std::string plant =
        "sh -c 'for n in \"\" -0 -1 -2; do ln -s victim.txt .r.html.tmp-$$$n; done; "
        "HAPTICBENCH_REPORTS_DIR=renderer exec \"$0\" report run --out r.html' '" +
        hb::test::hapticbench_bin() + "'";
    const CommandResult result = shell(plant, work);
    CHECK(result.exit_code == 3);
    CHECK(result.stderr_text.find("render_report.py") != std::string::npos);
    CHECK(hb::test::read_text_file(work / "victim.txt") == "the user's file\n");
    CHECK_FALSE(fs::exists(work / "r.html"));
    for (const auto& entry : fs::directory_iterator(work))
      if (entry.path().filename().string().rfind(".r.html.tmp-", 0) == 0) fs::remove(entry.path());
  }
}

TEST_CASE("a copied binary runs no renderer that another user could have put beside it") {
  // The copy in bin/ would find share/hapticbench/reports/ beside it; that
  // folder is writable by every user, as a shared /tmp would make it.
  const hb::test::ScratchDir work_dir("e2e_report_beside_copy");
  const fs::path& work = work_dir.path();
  fs::create_directories(work / "bin");
  fs::copy_file(hb::test::hapticbench_bin(), work / "bin/hapticbench");
  const fs::path planted = work / "share/hapticbench/reports";
  fs::create_directories(planted / "hapticbench_report");
  std::ofstream(planted / "render_report.py")
      << "open('" << (work / "mark.txt").string() << "', 'w').write('ran')\n";
  fs::permissions(planted, fs::perms::others_write, fs::perm_options::add);
  fs::create_directories(work / "run");
  std::ofstream(work / "run/summary.json") << sweep_summary(1000).dump();
  const CommandResult result = shell("bin/hapticbench report run --out r.html", work);
  CHECK(result.exit_code == 2);
  CHECK(result.stderr_text.find("writable by every user") != std::string::npos);
  CHECK(result.stderr_text.find("HAPTICBENCH_REPORTS_DIR") != std::string::npos);
  CHECK_FALSE(fs::exists(work / "mark.txt"));
  CHECK_FALSE(fs::exists(work / "r.html"));
}

}  // namespace
