// The comparison on summaries built here as JSON objects: which rows fail,
// which only inform, and why.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "hapticbench/input_error.h"
#include "harness/compare/comparison.h"
#include "harness/compare/comparison_report.h"
#include "harness/compare/run_checks.h"
#include "harness/compare/scenario_summary.h"
#include "harness/compare/summary_set.h"
#include "tests/support/scratch_dir.h"

namespace hb {
namespace {

using Json = nlohmann::ordered_json;
namespace fs = std::filesystem;

// Step times spread evenly over [800, 1200) ns times `scale`.
std::vector<int64_t> step_times(std::size_t count, double scale) {
  std::vector<int64_t> values;
  for (std::size_t i = 0; i < count; ++i)
    values.push_back(std::llround(scale * (800.0 + static_cast<double>((i * 7919) % 400))));
  return values;
}

// Nearest-rank percentile, as the summaries report it.
double percentile(std::vector<int64_t> values, double q) {
  std::sort(values.begin(), values.end());
  const std::size_t rank = static_cast<std::size_t>(std::ceil(q * values.size()));
  return static_cast<double>(values[std::max<std::size_t>(rank, 1) - 1]);
}

Json run_json(const std::string& label, const std::vector<int64_t>& steps) {
  return {{"algorithm", "penalty_analytic"},
          {"label", label},
          {"params", Json::object()},
          {"timing",
           {{"ticks", steps.size()},
            {"step_ns",
             {{"p50", percentile(steps, 0.5)},
              {"p90", percentile(steps, 0.9)},
              {"p99", percentile(steps, 0.99)},
              {"p999", percentile(steps, 0.999)},
              {"max", percentile(steps, 1.0)}}},
            {"over_budget", 0},
            {"step_ns_sample", steps}}},
          {"accuracy",
           {{"force_err_rms_n", 2.0},
            {"force_dir_err_max_deg", 1.5},
            {"torque_err_rms_nm", 0.001},
            {"penetration_max_m", 0.002},
            {"penetration_rms_m", 0.0015}}},
          {"stability",
           {{"nonfinite", 0},
            {"diverged", false},
            {"passivity_energy_min_j", -0.001},
            {"force_jump_max_n", 0.08}}},
          {"oracle", nullptr},
          {"determinism", {{"ticks_hash", "71fe1f219cab51ad"}}},
          {"budgets", Json::array()}};
}

Json summary(const std::string& commit = "a0c10976b673",
             const std::vector<int64_t>& steps = step_times(1000, 1.0)) {
  return {{"schema_version", 1},
          {"context",
           {{"commit", commit},
            {"build_type", "Release"},
            {"compiler", "g++ 12.2.0"},
            {"cpu", "AMD EPYC"},
            {"date", "2026-01-01T00:00:00Z"}}},
          {"scenario", {{"name", "sphere_press_box"}, {"hash", "779a26c9c5868102"}}},
          {"runs", Json::array({run_json("penalty_implicit", steps)})}};
}

Json& first_run(Json& document) { return document["runs"][0]; }

Comparison compare(const Json& baseline, const Json& candidate, CompareOptions options = {}) {
  SummarySet b{"baseline.json", false, {scenario_summary_from_json(baseline, "baseline.json")}};
  SummarySet c{"candidate.json", false, {scenario_summary_from_json(candidate, "candidate.json")}};
  return compare_summary_sets(b, c, options);
}

std::vector<const CheckRow*> failing(const Comparison& comparison) {
  std::vector<const CheckRow*> rows;
  for (const CheckRow& row : comparison.rows)
    if (is_failing(row.verdict)) rows.push_back(&row);
  return rows;
}

const CheckRow& row_named(const Comparison& comparison, const std::string& check,
                          const std::string& label = "penalty_implicit") {
  for (const CheckRow& row : comparison.rows)
    if (row.check == check && row.label == label) return row;
  FAIL("no row " << check << " for " << label);
  throw std::logic_error("unreachable");
}

TEST_CASE("a summary against itself passes every check") {
  const Comparison c = compare(summary(), summary());
  CHECK(c.passed());
  // scenario.hash, 5 accuracy, 4 stability, determinism, 3 timing.
  CHECK(c.rows.size() == 14);
  for (const CheckRow& row : c.rows) {
    INFO(row.check << ": " << row.note);
    CHECK(row.verdict == Verdict::kPass);
  }
  CHECK(row_named(c, "determinism.ticks_hash").note == "same forces on the same build");
  // Identical step times: no evidence of a slowdown.
  CHECK(row_named(c, "timing.step_ns.mann_whitney").detail["p_value"].get<double>() > 0.5);
}

TEST_CASE("a worse force error fails, naming the row") {
  Json candidate = summary();
  first_run(candidate)["accuracy"]["force_err_rms_n"] = 2.4;  // 20 % worse than 2.0
  const Comparison c = compare(summary(), candidate);
  CHECK_FALSE(c.passed());
  const auto rows = failing(c);
  REQUIRE(rows.size() == 1);
  CHECK(rows[0]->check == "accuracy.force_err_rms_n");
  CHECK(rows[0]->scenario == "sphere_press_box");
  CHECK(rows[0]->label == "penalty_implicit");
  CHECK(rows[0]->verdict == Verdict::kRegression);
  CHECK(rows[0]->change == "+20.0%");
  // Tolerance max(1e-6 N, 5 % of 2.0 N) = 0.1 N.
  CHECK(rows[0]->detail["tolerance"].get<double>() == Approx(0.1));
}

TEST_CASE("the accuracy tolerance is max(absolute per unit, relative to the baseline)") {
  auto verdict_for = [](const char* key, double baseline, double candidate) {
    Json b = summary(), c = summary();
    first_run(b)["accuracy"][key] = baseline;
    first_run(c)["accuracy"][key] = candidate;
    return row_named(compare(b, c), std::string("accuracy.") + key).verdict;
  };
  // Relative: 5 % of 2.0 N is 0.1 N.
  CHECK(verdict_for("force_err_rms_n", 2.0, 2.09) == Verdict::kPass);
  CHECK(verdict_for("force_err_rms_n", 2.0, 2.11) == Verdict::kRegression);
  CHECK(verdict_for("force_err_rms_n", 2.0, 1.8) == Verdict::kImproved);
  // Absolute, from a zero baseline: 1e-7 m, 0.01 deg, 1e-9 N·m.
  CHECK(verdict_for("penetration_max_m", 0.0, 0.9e-7) == Verdict::kPass);
  CHECK(verdict_for("penetration_max_m", 0.0, 1.1e-7) == Verdict::kRegression);
  CHECK(verdict_for("force_dir_err_max_deg", 0.0, 0.009) == Verdict::kPass);
  CHECK(verdict_for("force_dir_err_max_deg", 0.0, 0.011) == Verdict::kRegression);
  CHECK(verdict_for("torque_err_rms_nm", 0.0, 0.9e-9) == Verdict::kPass);
  CHECK(verdict_for("torque_err_rms_nm", 0.0, 1.1e-9) == Verdict::kRegression);
  // --rel-tol widens or narrows the relative part.
  Json b = summary(), c = summary();
  first_run(c)["accuracy"]["force_err_rms_n"] = 2.15;
  CompareOptions loose;
  loose.rel_tol = 0.1;
  CHECK(row_named(compare(b, c, loose), "accuracy.force_err_rms_n").verdict == Verdict::kPass);
  CHECK(row_named(compare(b, c), "accuracy.force_err_rms_n").verdict == Verdict::kRegression);
}

TEST_CASE("null: on both sides not applicable, disappearing fails, appearing informs") {
  Json b = summary(), c = summary();
  first_run(b)["accuracy"]["force_dir_err_max_deg"] = nullptr;
  first_run(c)["accuracy"]["force_dir_err_max_deg"] = nullptr;
  first_run(c)["accuracy"]["penetration_rms_m"] = nullptr;
  first_run(b)["accuracy"]["torque_err_rms_nm"] = nullptr;
  const Comparison comparison = compare(b, c);
  CHECK(row_named(comparison, "accuracy.force_dir_err_max_deg").verdict == Verdict::kNotApplicable);
  const CheckRow& gone = row_named(comparison, "accuracy.penetration_rms_m");
  CHECK(gone.verdict == Verdict::kFailure);
  CHECK(gone.note.find("disappeared") != std::string::npos);
  const CheckRow& appeared = row_named(comparison, "accuracy.torque_err_rms_nm");
  CHECK(appeared.verdict == Verdict::kInfo);
  CHECK(appeared.note.find("appeared") != std::string::npos);
  CHECK(failing(comparison).size() == 1);
}

TEST_CASE("the Embree oracle's penetration is compared when a side has it") {
  Json b = summary(), c = summary();
  first_run(b)["oracle"] = {{"embree", {{"penetration_max_m", 0.002}}}, {"cgal", nullptr}};
  first_run(c)["oracle"] = {{"embree", {{"penetration_max_m", 0.0025}}}, {"cgal", nullptr}};
  CHECK(row_named(compare(b, c), "oracle.embree.penetration_max_m").verdict ==
        Verdict::kRegression);
  CHECK(row_named(compare(b, b), "oracle.embree.penetration_max_m").verdict == Verdict::kPass);
  // Gone from the candidate: fails; absent on both: no row at all.
  CHECK(row_named(compare(b, summary()), "oracle.embree.penetration_max_m").verdict ==
        Verdict::kFailure);
  const Comparison without_oracle = compare(summary(), summary());
  for (const CheckRow& row : without_oracle.rows)
    CHECK(row.check != "oracle.embree.penetration_max_m");
}

TEST_CASE("stability: divergence, non-finite ticks, passivity and force jumps") {
  SECTION("diverged false -> true fails, true -> false improves") {
    Json diverged = summary();
    first_run(diverged)["stability"]["diverged"] = true;
    const Comparison c = compare(summary(), diverged);
    const auto rows = failing(c);
    REQUIRE(rows.size() == 1);
    CHECK(rows[0]->check == "stability.diverged");
    CHECK(rows[0]->change == "false -> true");
    CHECK(row_named(compare(diverged, summary()), "stability.diverged").verdict ==
          Verdict::kImproved);
    CHECK(compare(diverged, diverged).passed());
  }
  SECTION("any increase of non-finite ticks fails") {
    Json more = summary();
    first_run(more)["stability"]["nonfinite"] = 1;
    const CheckRow row = row_named(compare(summary(), more), "stability.nonfinite");
    CHECK(row.verdict == Verdict::kRegression);
    CHECK(row.change == "+1");
  }
  SECTION("any increase of tunnelling passes fails, and says what it counts") {
    Json none = summary(), once = summary();
    first_run(none)["stability"]["tunnelled"] = 0;
    first_run(once)["stability"]["tunnelled"] = 1;
    const CheckRow row = row_named(compare(none, once), "stability.tunnelled");
    CHECK(row.verdict == Verdict::kRegression);
    CHECK(row.change == "+1");
    CHECK(row.note.find("passes through the scene") != std::string::npos);
    CHECK(row_named(compare(once, none), "stability.tunnelled").verdict == Verdict::kImproved);
  }
  SECTION("a proxy that starts to chatter fails") {
    Json calm = summary(), chatters = summary();
    first_run(calm)["stability"]["chatters"] = false;
    first_run(chatters)["stability"]["chatters"] = true;
    const CheckRow row = row_named(compare(calm, chatters), "stability.chatters");
    CHECK(row.verdict == Verdict::kRegression);
    CHECK(row.note == "the candidate chatters, the baseline not");
    // A baseline from before the metric existed: informative, not a failure.
    const CheckRow appeared = row_named(compare(summary(), chatters), "stability.chatters");
    CHECK(appeared.verdict == Verdict::kInfo);
    CHECK(appeared.note == "metric appeared: null in the baseline");
  }
  SECTION("passivity energy: a decrease beyond tolerance fails") {
    // Baseline -0.001 J: tolerance max(1e-9 J, 5e-5 J) = 5e-5 J.
    Json lower = summary(), slightly = summary(), higher = summary();
    first_run(lower)["stability"]["passivity_energy_min_j"] = -0.00106;
    first_run(slightly)["stability"]["passivity_energy_min_j"] = -0.00104;
    first_run(higher)["stability"]["passivity_energy_min_j"] = 0.0;
    CHECK(row_named(compare(summary(), lower), "stability.passivity_energy_min_j").verdict ==
          Verdict::kRegression);
    CHECK(row_named(compare(summary(), slightly), "stability.passivity_energy_min_j").verdict ==
          Verdict::kPass);
    CHECK(row_named(compare(summary(), higher), "stability.passivity_energy_min_j").verdict ==
          Verdict::kImproved);
  }
  SECTION("port energy: judged by the energy generated, not by the energy absorbed") {
    // Absorbing less (a proxy freed from sticking) is no regression; from
    // absorbing to generating beyond the tolerance is; generating less is better.
    Json absorbing = summary(), absorbing_less = summary(), generating = summary();
    first_run(absorbing)["stability"]["energy_drift_j_per_s"] = 0.3;
    first_run(absorbing_less)["stability"]["energy_drift_j_per_s"] = 0.0001;
    first_run(generating)["stability"]["energy_drift_j_per_s"] = -0.01;
    const CheckRow freed =
        row_named(compare(absorbing, absorbing_less), "stability.energy_drift_j_per_s");
    CHECK(freed.verdict == Verdict::kPass);
    CHECK(freed.note == "no energy generated on either side");
    CHECK(freed.baseline == 0.3);
    CHECK(freed.candidate == 0.0001);
    CHECK(row_named(compare(absorbing, generating), "stability.energy_drift_j_per_s").verdict ==
          Verdict::kRegression);
    CHECK(row_named(compare(generating, absorbing), "stability.energy_drift_j_per_s").verdict ==
          Verdict::kImproved);
    // The minimum: from +0.5 J (the coupling's store at the start) to +0.1 J
    // nothing is generated; to -0.1 J it is.
    Json stored = summary(), stored_less = summary(), below = summary();
    first_run(stored)["stability"]["passivity_energy_min_j"] = 0.5;
    first_run(stored_less)["stability"]["passivity_energy_min_j"] = 0.1;
    first_run(below)["stability"]["passivity_energy_min_j"] = -0.1;
    CHECK(row_named(compare(stored, stored_less), "stability.passivity_energy_min_j").verdict ==
          Verdict::kPass);
    CHECK(row_named(compare(stored, below), "stability.passivity_energy_min_j").verdict ==
          Verdict::kRegression);
  }
  SECTION("force jump: an increase beyond the relative tolerance fails") {
    Json jumpy = summary(), similar = summary();
    first_run(jumpy)["stability"]["force_jump_max_n"] = 0.09;     // +12.5 %
    first_run(similar)["stability"]["force_jump_max_n"] = 0.083;  // +3.75 %
    CHECK(row_named(compare(summary(), jumpy), "stability.force_jump_max_n").verdict ==
          Verdict::kRegression);
    CHECK(row_named(compare(summary(), similar), "stability.force_jump_max_n").verdict ==
          Verdict::kPass);
  }
}

TEST_CASE("determinism: same build must give the same hash, other builds only inform") {
  Json other_hash = summary();
  first_run(other_hash)["determinism"]["ticks_hash"] = "0000000000000000";
  SECTION("same build, different hash: regression") {
    const Comparison c = compare(summary(), other_hash);
    const auto rows = failing(c);
    REQUIRE(rows.size() == 1);
    CHECK(rows[0]->check == "determinism.ticks_hash");
    CHECK(rows[0]->note.find("forces differ on the same build") != std::string::npos);
  }
  SECTION("different commit, different hash: information") {
    Json newer = summary("b1c2d3e4f5a6");
    first_run(newer)["determinism"]["ticks_hash"] = "0000000000000000";
    const Comparison c = compare(summary(), newer);
    CHECK(c.passed());
    const CheckRow& row = row_named(c, "determinism.ticks_hash");
    CHECK(row.verdict == Verdict::kInfo);
    CHECK(row.change == "differs");
    CHECK(row_named(compare(summary(), summary("b1c2d3e4f5a6")), "determinism.ticks_hash").change ==
          "equal");
  }
  SECTION("different compiler or build type: information") {
    Json debug = other_hash;
    debug["context"]["build_type"] = "Debug";
    CHECK(row_named(compare(summary(), debug), "determinism.ticks_hash").verdict == Verdict::kInfo);
    Json clang = other_hash;
    clang["context"]["compiler"] = "clang 14";
    CHECK(row_named(compare(summary(), clang), "determinism.ticks_hash").verdict == Verdict::kInfo);
  }
  SECTION("a dirty or unknown commit does not identify the build") {
    CHECK_FALSE(same_build({"a0c1097-dirty", "g++", "Release", ""},
                           {"a0c1097-dirty", "g++", "Release", ""}));
    CHECK_FALSE(same_build({"unknown", "g++", "Release", ""}, {"unknown", "g++", "Release", ""}));
    CHECK(same_build({"a0c1097", "g++", "Release", "x"}, {"a0c1097", "g++", "Release", "y"}));
    Json dirty_b = summary("a0c1097-dirty"), dirty_c = summary("a0c1097-dirty");
    first_run(dirty_c)["determinism"]["ticks_hash"] = "0000000000000000";
    CHECK(row_named(compare(dirty_b, dirty_c), "determinism.ticks_hash").verdict == Verdict::kInfo);
  }
}

TEST_CASE("timing: a regression needs a ratio above the limit and a significant shift") {
  // These summaries carry no noise floor: only --strict-timing lets their
  // wall-clock rows gate (the default is tested below).
  CompareOptions strict;
  strict.strict_timing = true;
  SECTION("1.5 times slower, 1000 step times: regression") {
    const Comparison c = compare(summary(), summary("a0c10976b673", step_times(1000, 1.5)), strict);
    CHECK_FALSE(c.passed());
    const CheckRow& p50 = row_named(c, "timing.step_ns.p50");
    CHECK(p50.verdict == Verdict::kRegression);
    CHECK(p50.change == "x1.50");
    CHECK(row_named(c, "timing.step_ns.p99").verdict == Verdict::kRegression);
    CHECK(row_named(c, "timing.step_ns.mann_whitney").detail["p_value"].get<double>() < 1e-6);
    for (const CheckRow* row : failing(c)) CHECK(row->check.rfind("timing.", 0) == 0);
  }
  SECTION("1.5 times slower on 5 overlapping step times each: not significant, passes") {
    // Baseline 100 300 150 500 200 (median 200); candidate 1.5 times each:
    // 150 450 225 750 300 (median 300). U_c = 1.5 + 4 + 3 + 5 + 3.5 = 17 of
    // 25, with two tied pairs: sd = 4.758, z = (17 - 12.5 - 0.5) / 4.758 =
    // 0.841, p = 0.20.
    const std::vector<int64_t> fast = {100, 300, 150, 500, 200};
    const std::vector<int64_t> slow = {150, 450, 225, 750, 300};
    const Comparison c =
        compare(summary("a0c10976b673", fast), summary("a0c10976b673", slow), strict);
    CHECK(c.passed());
    const CheckRow& p50 = row_named(c, "timing.step_ns.p50");
    CHECK(p50.change == "x1.50");
    CHECK(p50.verdict == Verdict::kInfo);
    CHECK(p50.note.find("not significant") != std::string::npos);
    CHECK(row_named(c, "timing.step_ns.mann_whitney").detail["p_value"].get<double>() ==
          Approx(0.200).margin(0.001));
  }
  SECTION("1.1 times slower, 1000 step times: significant but under the ratio, passes") {
    const Comparison c = compare(summary(), summary("a0c10976b673", step_times(1000, 1.1)), strict);
    CHECK(c.passed());
    CHECK(row_named(c, "timing.step_ns.p50").change == "x1.10");
    CHECK(row_named(c, "timing.step_ns.p50").verdict == Verdict::kPass);
    const CheckRow& test = row_named(c, "timing.step_ns.mann_whitney");
    CHECK(test.verdict == Verdict::kInfo);  // slower, and says so, but within the ratio
    CHECK(test.detail["p_value"].get<double>() < 0.01);
  }
  SECTION("--timing-ratio and --alpha move the line") {
    CompareOptions low_ratio = strict;
    low_ratio.timing_ratio = 1.05;
    CHECK_FALSE(
        compare(summary(), summary("a0c10976b673", step_times(1000, 1.1)), low_ratio).passed());
    CompareOptions tiny_alpha = strict;
    tiny_alpha.alpha = 1e-300;
    const Comparison c =
        compare(summary(), summary("a0c10976b673", step_times(1000, 1.5)), tiny_alpha);
    CHECK(row_named(c, "timing.step_ns.p50").verdict ==
          (row_named(c, "timing.step_ns.mann_whitney").detail["p_value"].get<double>() < 1e-300
               ? Verdict::kRegression
               : Verdict::kInfo));
  }
  SECTION("2 times faster and significant: improved") {
    const Comparison c = compare(summary(), summary("a0c10976b673", step_times(1000, 0.5)), strict);
    CHECK(row_named(c, "timing.step_ns.p50").verdict == Verdict::kImproved);
  }
  SECTION("--timing-same-cpu: a slowdown measured on another CPU informs, on the same CPU gates") {
    CompareOptions same_cpu = strict;
    same_cpu.timing_same_cpu_only = true;
    Json other_machine = summary("a0c10976b673", step_times(1000, 1.5));
    other_machine["context"]["cpu"] = "Intel Xeon";
    const Comparison across = compare(summary(), other_machine, same_cpu);
    CHECK(across.passed());
    CHECK(row_named(across, "timing.step_ns.p50").verdict == Verdict::kInfo);
    CHECK_FALSE(
        compare(summary(), summary("a0c10976b673", step_times(1000, 1.5)), same_cpu).passed());
  }
  SECTION("--no-timing: no timing rows") {
    CompareOptions no_timing;
    no_timing.timing = false;
    const Comparison c =
        compare(summary(), summary("a0c10976b673", step_times(1000, 1.5)), no_timing);
    CHECK(c.passed());
    for (const CheckRow& row : c.rows) CHECK(row.check.rfind("timing.", 0) != 0);
  }
}

using ScratchFolder = hb::test::ScratchDir;

void write_ticks(const fs::path& file, const std::vector<int64_t>& steps) {
  std::ofstream out(file);
  out << "tick,t_ns,fx,step_ns,flags\n";
  for (std::size_t k = 0; k < steps.size(); ++k)
    out << k << "," << k * 1000000 << ",0.5," << steps[k] << ",0\n";
}

TEST_CASE("run folders: the full step_ns columns of the ticks CSVs are tested") {
  const ScratchFolder scratch("ticks");
  const fs::path& root = scratch.path();
  // The summaries' samples say "identical"; the ticks say 1.5 times slower.
  for (const char* side : {"baseline", "candidate"}) {
    fs::create_directories(root / side);
    std::ofstream(root / side / "summary.json") << summary().dump(2);
  }
  write_ticks(root / "baseline/ticks_penalty_implicit.csv", step_times(1500, 1.0));
  write_ticks(root / "candidate/ticks_penalty_implicit.csv", step_times(1500, 1.5));
  const Comparison c = compare_summary_sets(load_summary_set(root / "baseline"),
                                            load_summary_set(root / "candidate"), {});
  const CheckRow& test = row_named(c, "timing.step_ns.mann_whitney");
  CHECK(test.baseline == 1500);
  CHECK(test.candidate == 1500);
  CHECK(test.note.find("ticks CSVs") != std::string::npos);
  CHECK(test.detail["p_value"].get<double>() < 1e-6);
  // The ratios come from the summaries' percentiles, which are equal here.
  CHECK(c.passed());

  SECTION("a ticks CSV with a bad step time is bad input naming file and line") {
    std::ofstream(root / "candidate/ticks_penalty_implicit.csv") << "tick,step_ns\n0,812\n1,fast\n";
    try {
      compare_summary_sets(load_summary_set(root / "baseline"),
                           load_summary_set(root / "candidate"), {});
      FAIL("expected InputError");
    } catch (const InputError& error) {
      CHECK(error.source().find("ticks_penalty_implicit.csv") != std::string::npos);
      CHECK(error.location() == "line 3");
    }
  }
  SECTION("one side without its ticks CSV: both use the summaries' samples") {
    fs::remove(root / "candidate/ticks_penalty_implicit.csv");
    const Comparison from_samples = compare_summary_sets(load_summary_set(root / "baseline"),
                                                         load_summary_set(root / "candidate"), {});
    const CheckRow& row = row_named(from_samples, "timing.step_ns.mann_whitney");
    CHECK(row.baseline == 1000);
    CHECK(row.note.find("step_ns_sample") != std::string::npos);
  }
}

TEST_CASE("runs are matched by label, suites by scenario name") {
  SECTION("a missing label fails, a new label is listed") {
    Json renamed = summary();
    first_run(renamed)["label"] = "penalty_implicit_v2";
    const Comparison c = compare(summary(), renamed);
    const auto rows = failing(c);
    REQUIRE(rows.size() == 1);
    CHECK(rows[0]->check == "run");
    CHECK(rows[0]->label == "penalty_implicit");
    CHECK(rows[0]->verdict == Verdict::kFailure);
    CHECK(row_named(c, "run", "penalty_implicit_v2").verdict == Verdict::kNew);
  }
  SECTION("suites: a missing scenario fails, an extra one is new") {
    const ScratchFolder scratch("suites");
    const fs::path& root = scratch.path();
    auto write = [&root](const std::string& suite, const std::string& folder,
                         const std::string& name) {
      Json document = summary();
      document["scenario"]["name"] = name;
      fs::create_directories(root / suite / folder);
      std::ofstream(root / suite / folder / "summary.json") << document.dump(2);
    };
    write("baseline", "a", "alpha");
    write("baseline", "b", "beta");
    write("candidate", "b", "beta");
    write("candidate", "c", "gamma");
    const Comparison c = compare_summary_sets(load_summary_set(root / "baseline"),
                                              load_summary_set(root / "candidate"), {});
    const auto rows = failing(c);
    REQUIRE(rows.size() == 1);
    CHECK(rows[0]->scenario == "alpha");
    CHECK(rows[0]->check == "scenario");
    CHECK(row_named(c, "scenario", "").verdict == Verdict::kFailure);
    bool gamma_new = false;
    for (const CheckRow& row : c.rows)
      if (row.scenario == "gamma") gamma_new = row.verdict == Verdict::kNew;
    CHECK(gamma_new);
    // beta compared in full.
    CHECK(std::count_if(c.rows.begin(), c.rows.end(),
                        [](const CheckRow& row) { return row.scenario == "beta"; }) == 14);
  }
  SECTION("two single runs of different scenarios are bad input") {
    Json other = summary();
    other["scenario"]["name"] = "box_press_box";
    try {
      compare(summary(), other);
      FAIL("expected InputError");
    } catch (const InputError& error) {
      CHECK(std::string(error.what())
                .find("different scenarios: baseline sphere_press_box, candidate box_press_box") !=
            std::string::npos);
    }
  }
}

TEST_CASE("summaries that break the contract are rejected with the JSON path") {
  auto rejection = [](const Json& document) -> std::string {
    try {
      scenario_summary_from_json(document, "summary.json");
    } catch (const InputError& error) {
      CHECK(error.source() == "summary.json");
      return error.location() + ": " + error.message();
    }
    return "accepted";
  };
  Json v2 = summary();
  v2["schema_version"] = 2;
  CHECK(rejection(v2).find("/schema_version: schema_version 2 is not supported") == 0);
  Json no_force = summary();
  first_run(no_force)["accuracy"].erase("force_err_rms_n");
  CHECK(rejection(no_force).find("/runs/0/accuracy/force_err_rms_n: missing") == 0);
  Json text_force = summary();
  first_run(text_force)["accuracy"]["force_err_rms_n"] = "2 N";
  CHECK(rejection(text_force).find("/runs/0/accuracy/force_err_rms_n: expected a number") == 0);
  Json no_commit = summary();
  no_commit["context"].erase("commit");
  CHECK(rejection(no_commit).find("/context/commit: missing") == 0);
  Json bad_sample = summary();
  first_run(bad_sample)["timing"]["step_ns_sample"][3] = -5;
  CHECK(rejection(bad_sample).find("/runs/0/timing/step_ns_sample/3: expected") == 0);
  Json twice = summary();
  twice["runs"].push_back(first_run(twice));
  CHECK(rejection(twice).find("/runs/1/label: label \"penalty_implicit\" is used") == 0);
  CHECK(rejection(summary()) == "accepted");
}

TEST_CASE("reports: JSON verdict, Markdown failures first, JUnit failure per failing row") {
  Json candidate = summary();
  first_run(candidate)["accuracy"]["force_err_rms_n"] = 2.4;
  const Comparison c = compare(summary(), candidate);

  const nlohmann::json report = comparison_json(c);
  CHECK(report["verdict"] == "regression");
  CHECK(report["failing"] == 1);
  CHECK(report["rows"].size() == c.rows.size());
  CHECK(report["counts"]["regression"] == 1);

  const std::string md = comparison_markdown(c);
  CHECK(md.rfind("**hapticbench compare: REGRESSION: 1 of 14 checks failed**", 0) == 0);
  const std::size_t details = md.find("<details>");
  REQUIRE(details != std::string::npos);
  // Before <details>: only the failing row; passing rows only inside it.
  CHECK(md.find("accuracy.force_err_rms_n") < details);
  CHECK(md.find("accuracy.penetration_max_m") > details);
  CHECK(md.find("</details>") != std::string::npos);

  const std::string junit = comparison_junit_xml(c);
  CHECK(junit.find("tests=\"14\" failures=\"1\"") != std::string::npos);
  CHECK(junit.find("name=\"accuracy.force_err_rms_n\"><failure") != std::string::npos);

  const std::string clean = comparison_markdown(compare(summary(), summary()));
  CHECK(clean.rfind("**hapticbench compare: pass: 14 checks, no regression**", 0) == 0);
  CHECK(clean.find("| accuracy") > clean.find("<details>"));
}

}  // namespace
}  // namespace hb

namespace hb {
namespace {

Json with_instructions(Json document, double step_per_tick, std::optional<double> slow_per_call) {
  document["runs"][0]["timing"]["instructions"] = {
      {"step_per_tick_mean", step_per_tick},
      {"slow_update_per_call_mean", slow_per_call ? Json(*slow_per_call) : Json(nullptr)}};
  return document;
}

Json with_noise(Json document, bool quiet, double calibration_ns) {
  document["runs"][0]["timing"]["noise"] = {{"quiet", quiet},
                                            {"cpu_share", quiet ? 1.0 : 0.6},
                                            {"calibration_before_ns", calibration_ns},
                                            {"calibration_spread", 0.01},
                                            {"load_average_1m", quiet ? 0.2 : 3.1}};
  return document;
}

TEST_CASE("instruction counts: 5 % more fails the gate, identical passes, 1 % passes") {
  const Json baseline = with_instructions(summary(), 10000, 200000);
  CompareOptions no_wall_clock;
  no_wall_clock.timing = false;  // instruction counts are compared all the same
  const Comparison same = compare(baseline, baseline, no_wall_clock);
  CHECK(same.passed());
  CHECK(row_named(same, "timing.instructions.step_per_tick_mean").verdict == Verdict::kPass);

  const Comparison step_5 =
      compare(baseline, with_instructions(summary(), 10500, 200000), no_wall_clock);
  CHECK_FALSE(step_5.passed());
  const CheckRow& row = row_named(step_5, "timing.instructions.step_per_tick_mean");
  CHECK(row.verdict == Verdict::kRegression);
  CHECK(row.change == "+5.00%");
  CHECK(failing(step_5).size() == 1);

  const Comparison slow_5 =
      compare(baseline, with_instructions(summary(), 10000, 210000), no_wall_clock);
  CHECK(row_named(slow_5, "timing.instructions.slow_update_per_call_mean").verdict ==
        Verdict::kRegression);
  CHECK(compare(baseline, with_instructions(summary(), 10100, 200000), no_wall_clock).passed());

  SECTION("another compiler: informs, never gates") {
    Json other = with_instructions(summary(), 12000, 200000);
    other["context"]["compiler"] = "clang 14";
    const Comparison c = compare(baseline, other, no_wall_clock);
    CHECK(row_named(c, "timing.instructions.step_per_tick_mean").verdict == Verdict::kInfo);
  }
  SECTION("counted on one side only: informs") {
    const Comparison c = compare(baseline, summary(), no_wall_clock);
    CHECK(c.passed());
    CHECK(row_named(c, "timing.instructions.step_per_tick_mean").verdict == Verdict::kInfo);
  }
}

TEST_CASE("timing by default: wall-clock gates only between quiet runs at one speed") {
  CompareOptions options;  // the default: not --strict-timing
  options.timing_ratio = 1.8;
  const Json baseline = with_noise(summary(), true, 10000);
  SECTION("quiet on both sides, 2 times slower: regression") {
    const Json slower = with_noise(summary("a0c10976b673", step_times(1000, 2.0)), true, 10200);
    const Comparison c = compare(baseline, slower, options);
    CHECK_FALSE(c.passed());
    CHECK(row_named(c, "timing.step_ns.p50").verdict == Verdict::kRegression);
  }
  SECTION("the candidate's machine was busy: informs") {
    const Json busy = with_noise(summary("a0c10976b673", step_times(1000, 3.5)), false, 10000);
    const Comparison c = compare(baseline, busy, options);
    CHECK(c.passed());
    const CheckRow& p99 = row_named(c, "timing.step_ns.p99");
    CHECK(p99.verdict == Verdict::kInfo);
    CHECK_THAT(p99.note, Catch::Contains("not quiet"));
  }
  SECTION("quiet, but the calibration ran 1.5 times slower: informs") {
    const Json slower_machine =
        with_noise(summary("a0c10976b673", step_times(1000, 2.0)), true, 15000);
    const Comparison c = compare(baseline, slower_machine, options);
    CHECK(c.passed());
    CHECK_THAT(row_named(c, "timing.step_ns.p50").note, Catch::Contains("calibration"));
  }
  SECTION("no noise floor in the baseline: informs") {
    const Json slower = with_noise(summary("a0c10976b673", step_times(1000, 2.0)), true, 10000);
    CHECK(compare(summary(), slower, options).passed());
  }
  SECTION("both machines busy, 1.3 times slower: informs; --strict-timing gates") {
    const Json busy_baseline = with_noise(summary(), false, 10000);
    const Json busy_slower =
        with_noise(summary("a0c10976b673", step_times(1000, 1.3)), false, 10000);
    CompareOptions defaults;
    const Comparison c = compare(busy_baseline, busy_slower, defaults);
    CHECK(c.passed());
    CHECK(row_named(c, "timing.step_ns.p50").verdict == Verdict::kInfo);
    CHECK_THAT(row_named(c, "timing.step_ns.p50").note, Catch::Contains("not gated"));
    CompareOptions strict = defaults;
    strict.strict_timing = true;
    CHECK_FALSE(compare(busy_baseline, busy_slower, strict).passed());
  }
}

}  // namespace
}  // namespace hb
