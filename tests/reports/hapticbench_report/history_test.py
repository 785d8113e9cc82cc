"""The history across commits: each metric's first move beyond its tolerance (compare's
tolerance for accuracy, a ratio for step times, a share for instruction counts), the page
render_report.py --history draws, and bad history input. Run by CTest with Debian's
python3."""
import os
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "reports"))
from hapticbench_report import history  # noqa: E402
from hapticbench_report.inputs import ReportInputError  # noqa: E402
from fake_runs import history_run, write_history, write_run_folder  # noqa: E402

RENDER = os.path.join(os.path.dirname(__file__), "..", "..", "..", "reports", "render_report.py")

COMMITS = ["3f2a9c1d0e", "77b01de4aa", "a0c4e55f31"]


def three_commits():
    """Three commits of scenario "press": per label the force error, step p99 (ns),
    penetration (m) and instructions per step at each commit."""
    series = {
        "jumps_at_third": dict(error=[0.5, 0.5, 0.65]),           # +30 % at the third
        "improves_at_second": dict(error=[0.4, 0.3, 0.3]),       # -25 % at the second
        "drifts_3_percent": dict(error=[1.0, 1.03, 1.0609]),     # +3 % each time
        "slower_steps": dict(step=[1000, 1100, 1650]),           # +10 %, then x1.5
        "tiny_penetration": dict(pen=[1e-8, 5e-8, 9e-8]),        # within abs_tol 1e-7 m
        "counted": dict(instructions=[1000.0, 1010.0, 1040.0]),  # +1 %, then +3 %
        "turns_unstable": dict(stable=[True, True, False]),
    }
    commits = []
    for i, commit in enumerate(COMMITS):
        runs = []
        for label, values in series.items():
            runs.append(history_run(
                label, error=values.get("error", [0.2] * 3)[i],
                penetration_m=values.get("pen", [0.002] * 3)[i],
                step_p99_ns=values.get("step", [1000] * 3)[i],
                instructions=values.get("instructions", [None] * 3)[i],
                stable=values.get("stable", [True] * 3)[i]))
        commits.append((commit, {"press": runs}))
    return commits


class FirstMoveTest(unittest.TestCase):
    def setUp(self):
        scratch = tempfile.TemporaryDirectory()
        self.addCleanup(scratch.cleanup)
        self.root = scratch.name
        write_history(self.root, three_commits())
        self.history = history.read_history(self.root)
        self.moves = {(m.label, m.metric.key): m for m in self.history.first_moves()}

    def move(self, label, metric):
        return self.moves.get((label, metric))

    def test_a_30_percent_jump_at_the_third_commit_is_a_worse_move_there(self):
        move = self.move("jumps_at_third", "force_err_rms_n")
        self.assertIsNotNone(move)
        self.assertEqual(move.entry.commit, COMMITS[2])
        self.assertEqual(move.direction, "worse")
        self.assertEqual((move.before.value, move.after.value), (0.5, 0.65))

    def test_an_improvement_at_the_second_commit_is_a_better_move_there(self):
        move = self.move("improves_at_second", "force_err_rms_n")
        self.assertIsNotNone(move)
        self.assertEqual(move.entry.commit, COMMITS[1])
        self.assertEqual(move.direction, "better")

    def test_a_3_percent_change_is_not_a_move(self):
        self.assertIsNone(self.move("drifts_3_percent", "force_err_rms_n"))
        # The other labels' flat series did not move either.
        self.assertIsNone(self.move("jumps_at_third", "max_penetration_m"))

    def test_step_p99_10_percent_slower_is_not_a_move_but_1_5_times_is(self):
        move = self.move("slower_steps", "tick_p99_us")
        self.assertIsNotNone(move)
        self.assertEqual(move.entry.commit, COMMITS[2])
        self.assertEqual(move.direction, "worse")
        self.assertAlmostEqual(move.before.value, 1.1)  # shown in µs
        self.assertAlmostEqual(move.after.value, 1.65)

    def test_penetration_shown_in_mm_moves_only_beyond_the_metric_tables_abs_tol(self):
        self.assertIsNone(self.move("tiny_penetration", "max_penetration_m"))
        points = self.history.series["press"]["tiny_penetration"]["max_penetration_m"]
        self.assertAlmostEqual(points[0].value, 1e-5)  # 1e-8 m in mm

    def test_instructions_move_beyond_2_percent_and_are_absent_where_not_counted(self):
        move = self.move("counted", "instructions_per_step")
        self.assertIsNotNone(move)
        self.assertEqual(move.entry.commit, COMMITS[2])
        self.assertIsNone(self.move("jumps_at_third", "instructions_per_step"))

    def test_a_stability_verdict_that_turns_unstable_is_a_worse_move(self):
        move = self.move("turns_unstable", "stable")
        self.assertIsNotNone(move)
        self.assertEqual((move.entry.commit, move.direction), (COMMITS[2], "worse"))
        points = self.history.series["press"]["turns_unstable"]["force_err_rms_n"]
        self.assertEqual([p.unstable for p in points], [False, False, True])

    def test_a_label_missing_from_a_commit_is_compared_with_the_last_commit_that_ran_it(self):
        commits = three_commits()
        commits[1][1]["press"] = [r for r in commits[1][1]["press"]
                                  if r["label"] != "jumps_at_third"]
        scratch = tempfile.TemporaryDirectory()
        self.addCleanup(scratch.cleanup)
        write_history(scratch.name, commits)
        moves = {(m.label, m.metric.key): m for m in
                 history.read_history(scratch.name).first_moves()}
        move = moves[("jumps_at_third", "force_err_rms_n")]
        self.assertEqual((move.before.entry.commit, move.entry.commit), (COMMITS[0], COMMITS[2]))


class PageTest(unittest.TestCase):
    def render(self, *arguments):
        scratch = tempfile.TemporaryDirectory()
        self.addCleanup(scratch.cleanup)
        out = os.path.join(scratch.name, "report.html")
        result = subprocess.run([sys.executable, "-B", RENDER, "--out", out] + list(arguments),
                                capture_output=True, text=True)
        html = ""
        if os.path.exists(out):
            with open(out, encoding="utf-8") as f:
                html = f.read()
        return result, html

    def test_the_page_renders_with_history_alone(self):
        scratch = tempfile.TemporaryDirectory()
        self.addCleanup(scratch.cleanup)
        write_history(scratch.name, three_commits())
        result, html = self.render("--history", scratch.name)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn('<section id="history">', html)
        self.assertIn('data-label="jumps_at_third" data-metric="force_err_rms_n" '
                      'data-commit="%s" data-direction="worse"' % COMMITS[2], html)
        self.assertIn('data-label="improves_at_second" data-metric="force_err_rms_n" '
                      'data-commit="%s" data-direction="better"' % COMMITS[1], html)
        self.assertNotIn('data-label="drifts_3_percent"', html)
        self.assertIn('<img id="fig-history-press" alt="metrics across commits, press" '
                      'src="data:image/png;base64,', html)
        self.assertNotIn('id="verdicts"', html)  # no run folders: the history view alone

    def test_with_run_folders_the_history_section_follows_the_verdict(self):
        scratch = tempfile.TemporaryDirectory()
        self.addCleanup(scratch.cleanup)
        write_history(os.path.join(scratch.name, "history"), three_commits())
        run_folder = os.path.join(scratch.name, "run")
        write_run_folder(run_folder, {"scenario": {"name": "press"},
                                      "runs": [history_run("jumps_at_third")]})
        result, html = self.render("--history", os.path.join(scratch.name, "history"),
                                   run_folder)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertLess(html.index('id="verdicts"'), html.index('<section id="history">'))
        self.assertLess(html.index('<section id="history">'), html.index('id="summary"'))
        self.assertIn("<a href='#history'>History</a>", html)

    def test_a_missing_summary_named_in_history_json_is_exit_2_naming_the_file(self):
        scratch = tempfile.TemporaryDirectory()
        self.addCleanup(scratch.cleanup)
        entries = write_history(scratch.name, three_commits())
        missing = os.path.join(scratch.name, entries[1]["folder"], "press", "summary.json")
        os.remove(missing)
        result, html = self.render("--history", scratch.name)
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("error: %s: " % missing, result.stderr)
        self.assertIn("/entries/1/scenarios/0", result.stderr)
        self.assertEqual(html, "")
        with self.assertRaises(ReportInputError):
            history.read_history(scratch.name)

    def test_a_garbled_or_missing_history_json_is_exit_2_naming_it(self):
        scratch = tempfile.TemporaryDirectory()
        self.addCleanup(scratch.cleanup)
        path = os.path.join(scratch.name, "history.json")
        result, _ = self.render("--history", scratch.name)
        self.assertEqual(result.returncode, 2)
        self.assertIn("error: %s: cannot read" % path, result.stderr)
        with open(path, "w") as f:
            f.write('{"schema_version": 1, "entries": [{"commit": "3f2a9c1", "folder": "../x",'
                    ' "scenarios": []}]}')
        result, _ = self.render("--history", scratch.name)
        self.assertEqual(result.returncode, 2)
        self.assertIn("error: %s: /entries/0/folder: expected a folder" % path, result.stderr)
        with open(path, "w") as f:
            f.write('{"schema_version": 1, "entries": [')
        result, _ = self.render("--history", scratch.name)
        self.assertEqual(result.returncode, 2)
        self.assertIn("error: %s: line 1: not JSON" % path, result.stderr)


if __name__ == "__main__":
    unittest.main()
