"""A sweep is read as a sweep: its jobs share one accuracy-cost panel per base scenario,
the metrics are drawn against the swept value, and one table runs across the jobs, always
in numeric order of the grid values (1000, 2000, 10000, not as text). Run by CTest with
Debian's python3."""
import os
import re
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "reports"))
from hapticbench_report import figures, page, sweeps, tables  # noqa: E402
from fake_runs import FakeFolder, fake_sweep  # noqa: E402

KEY = "/algorithms/1/params/contact_stiffness"


class SweepTest(unittest.TestCase):
    def setUp(self):
        scratch = tempfile.TemporaryDirectory()
        self.addCleanup(scratch.cleanup)
        # Listed as hapticbench report finds the folders: in text order.
        self.folders = fake_sweep(scratch.name, KEY, [1000, 10000, 100000, 2000],
                                  labels=("implicit", "explicit"),
                                  extra_jobs=[{"name": "press__contact_stiffness=5000",
                                               "scenario": "../smoke/press.json",
                                               "grid": {KEY: 5000}, "status": "crashed"}])
        self.runs = [run for folder in self.folders for run in folder.runs]
        self.jobs = list(sweeps.sweep_jobs(self.folders).values())[0]

    def test_one_accuracy_cost_panel_per_base_scenario_in_numeric_order(self):
        panels, left_out = figures.pareto_panels(self.runs)
        self.assertEqual(left_out, [])
        self.assertEqual([title for title, _, _ in panels], ["press (sweep stiffness)"])
        values = [(p[2].label, sweeps.sweep_job(p[2].folder).values[KEY]) for p in panels[0][2]]
        self.assertEqual(values, [("implicit", 1000), ("implicit", 2000), ("implicit", 10000),
                                  ("implicit", 100000), ("explicit", 1000), ("explicit", 2000),
                                  ("explicit", 10000), ("explicit", 100000)])
        uri, fronts, _, _ = figures.pareto_figure(self.runs)
        self.assertTrue(uri.startswith("data:image/png;base64,"))
        self.assertEqual(list(fronts), ["press (sweep stiffness)"])
        self.assertIn("implicit (contact_stiffness=100000)", fronts["press (sweep stiffness)"])

    def test_metrics_against_the_swept_value_in_numeric_order(self):
        lines = figures.sweep_metric_lines(self.jobs, KEY)
        self.assertEqual(sorted(lines), [("explicit", ""), ("implicit", "")])
        self.assertEqual([x for x, _ in lines[("implicit", "")]], [1000, 2000, 10000, 100000])
        self.assertTrue(figures.sweep_metrics_figure(self.jobs, KEY).startswith("data:image/png"))
        html = page.sweeps_html(self.folders)
        self.assertIn('id="fig-sweep-0-press-contact_stiffness"', html)

    def test_the_table_across_the_jobs_is_in_numeric_order(self):
        html = tables.sweep_table_html(self.jobs[0].sweep, self.jobs)
        self.assertEqual(re.findall(r'data-key="contact_stiffness">(\d+)<', html),
                         ["1000", "2000", "5000", "10000", "100000"])
        self.assertIn("no run folder: crashed", html)
        self.assertEqual(html.count('<th class="label" colspan="6">'), 2)  # one per label
        self.assertIn("<th>force error RMS (N)</th>", html)

    def test_the_pages_scenarios_come_in_numeric_order(self):
        alone = FakeFolder("other")
        ordered = sweeps.numeric_folder_order([alone] + self.folders)
        self.assertEqual([f.scenario for f in ordered],
                         ["other", "press__contact_stiffness=1000",
                          "press__contact_stiffness=2000", "press__contact_stiffness=10000",
                          "press__contact_stiffness=100000"])

    def test_values_that_are_not_numbers_keep_their_place_in_the_grid(self):
        listed = ["voxmap", "signed_distance"]
        self.assertLess(sweeps.value_sort_key(100000), sweeps.value_sort_key(2e5))
        self.assertLess(sweeps.value_sort_key("voxmap", listed),
                        sweeps.value_sort_key("signed_distance", listed))
        self.assertEqual(sweeps.value_text(100000), "100000")
        self.assertEqual(sweeps.value_text(0.0005), "0.0005")


if __name__ == "__main__":
    unittest.main()
