"""The report's figures: the accuracy-cost figure has one front per scenario, over
runs that stayed stable, with cost = CPU time per tick of both loops; coupling stiffness
sweeps are found by their sweep.json. Run by CTest with Debian's python3."""
import json
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "reports"))
from hapticbench_report import figures  # noqa: E402
from fake_runs import FakeFolder, FakeRun  # noqa: E402


class ParetoTest(unittest.TestCase):
    def setUp(self):
        self.runs = [
            FakeRun("press", "fast_rough", 2.0, 1000),
            FakeRun("press", "slow_exact", 0.1, 5000),
            # Cheapest and most accurate on paper, but it diverged.
            FakeRun("press", "explicit", 0.01, 500, diverged=True),
            FakeRun("press", "nan", 0.02, 400, nonfinite=3),
            # Its haptic step is tiny; its slow loop is not.
            FakeRun("press", "god_object", 0.5, 200, cpu_p99_ns=20000),
            FakeRun("rub", "only", 9.0, 800),
        ]

    def test_diverged_and_nonfinite_runs_are_never_on_a_front(self):
        uri, fronts, left_out, failed = figures.pareto_figure(self.runs)
        self.assertIsNotNone(uri)
        self.assertEqual(left_out, [])
        self.assertNotIn("explicit", fronts["press"])
        self.assertNotIn("nan", fronts["press"])
        self.assertEqual(sorted(r.label for r, _ in failed), ["explicit", "nan"])
        self.assertEqual(dict((r.label, why) for r, why in failed),
                         {"explicit": "diverged", "nan": "non-finite"})

    def test_one_front_per_scenario_on_cpu_per_tick(self):
        _, fronts, _, _ = figures.pareto_figure(self.runs)
        self.assertEqual(set(fronts), {"press", "rub"})
        self.assertEqual(fronts["rub"], ["only"])
        # god_object costs 20 µs per tick with its slow loop: more than slow_exact's 5 µs
        # and less accurate, so it is not on the front despite its 0.2 µs step.
        self.assertEqual(fronts["press"], ["fast_rough", "slow_exact"])
        self.assertEqual(figures.cost_us(self.runs[4]), 20.0)



class CouplingSweepTest(unittest.TestCase):
    """A coupling stiffness sweep is found by the sweep.json beside its run folders, with
    k_t from each summary; folder and scenario names are never parsed."""

    def setUp(self):
        self.scratch = tempfile.TemporaryDirectory()
        root = self.scratch.name
        jobs = []
        for k in (1000, 8000):
            for b in (2, 5):
                name = "job%d" % len(jobs)  # says nothing of k_t
                jobs.append({"name": name, "scenario": "../smoke/pose_jump.json",
                             "grid": {"/coupling/k_t": k, "/coupling/b_t": b}})
        with open(os.path.join(root, "sweep.json"), "w") as f:
            json.dump({"grid": {"/coupling/k_t": [1000, 8000], "/coupling/b_t": [2, 5],
                                "/trace/duration_s": [5]}, "jobs": jobs}, f)
        self.folders = [FakeFolder(job["name"], path=os.path.join(root, job["name"]),
                                   coupling={"k_t": job["grid"]["/coupling/k_t"]})
                        for job in jobs]

    def tearDown(self):
        self.scratch.cleanup()

    def test_scene_is_the_scenario_with_the_other_varied_keys(self):
        points = [figures.coupling_stiffness(f) for f in self.folders]
        self.assertEqual(points, [("pose_jump (/coupling/b_t=2)", 1000.0),
                                  ("pose_jump (/coupling/b_t=5)", 1000.0),
                                  ("pose_jump (/coupling/b_t=2)", 8000.0),
                                  ("pose_jump (/coupling/b_t=5)", 8000.0)])

    def test_a_folder_outside_a_sweep_is_no_sweep_point(self):
        alone = FakeFolder("stability_k5000",
                           path=os.path.join(self.scratch.name, "elsewhere", "stability_k5000"),
                           coupling={"k_t": 5000})
        self.assertIsNone(figures.coupling_stiffness(alone))


if __name__ == "__main__":
    unittest.main()
