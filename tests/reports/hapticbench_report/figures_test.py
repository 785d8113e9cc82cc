"""The report's figures: the accuracy-cost figure has one front per scenario, over
runs that stayed stable, with cost = CPU time per tick of both loops; coupling stiffness
sweeps are found by their sweep.json; the scene figure zooms to the motion when the scene
is far larger. Run by CTest with Debian's python3."""
import json
import math
import os
import sys
import tempfile
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "reports"))
from hapticbench_report import figures  # noqa: E402
from fake_runs import (  # noqa: E402
    FakeFolder, FakeRun, outline, outline_object, press, write_run_folder)


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


class SceneViewTest(unittest.TestCase):
    """What the scene figure shows: the whole scene with the motion, or the motion (the
    device's path and the tool at its start and deepest poses) when the scene is far
    larger, so that a 2 cm press is not a dot in a 3 m scene."""

    def path(self, scene, tool_half=0.01):
        scratch = tempfile.TemporaryDirectory()
        self.addCleanup(scratch.cleanup)
        summary = {"scenario": {"name": "press", "outline": outline(scene, tool_half)},
                   "runs": [{"label": "god_object"}, {"label": "penalty"}]}
        # A 2 cm press from z = 3 cm with a tool of ± 1 cm: the motion spans z 0 to 4 cm.
        folder = write_run_folder(os.path.join(scratch.name, "press"), summary,
                                  device=press(start_z=0.03, depth=0.02))
        return folder, figures.DevicePath.of(folder.runs)

    def test_a_scene_far_larger_than_the_motion_is_zoomed_to_the_motion(self):
        folder, path = self.path([outline_object("box", [-1.5, -1.5, -0.1], [1.5, 1.5, 0.0])])
        lo, hi, zoomed = figures.scene_view(folder.outline, path)
        self.assertTrue(zoomed)
        self.assertLess(max(hi - lo), 0.1)  # centimetres, not the scene's 3 m
        # The motion is all in view: the tool's bounds from z 0 to 4 cm, x and y ± 1 cm.
        for axis, (low, high) in enumerate([(-0.01, 0.01), (-0.01, 0.01), (0.0, 0.04)]):
            self.assertLess(lo[axis], low)
            self.assertGreater(hi[axis], high)
        uri, facts = figures.scene_figure(folder.outline, folder.runs)
        self.assertTrue(uri.startswith("data:image/png;base64,"))
        self.assertTrue(facts["zoomed"])
        self.assertEqual(facts["path_label"], "god_object")  # the first label's path
        self.assertEqual([round(v) for v in facts["scene_extent_mm"]], [3000, 3000, 100])

    def test_a_scene_of_the_motions_size_is_shown_whole(self):
        folder, path = self.path([outline_object("box", [-0.05, -0.05, -0.02], [0.05, 0.05, 0]),
                                  outline_object("sphere", [0.06, -0.01, 0], [0.08, 0.01, 0.02],
                                                 name="scene[1]", distance_only=True)])
        lo, hi, zoomed = figures.scene_view(folder.outline, path)
        self.assertFalse(zoomed)
        self.assertTrue((lo <= [-0.05, -0.05, -0.02]).all() and (hi >= [0.08, 0.05, 0.04]).all())
        self.assertLess(max(hi - lo), 0.2)

    def test_the_deepest_point_is_the_lowest_z_and_the_path_is_downsampled(self):
        _, path = self.path([outline_object("box", [-1, -1, -1], [1, 1, 0])])
        self.assertAlmostEqual(path.position[path.deepest][2], 0.0102, places=6)
        long_path = figures.DevicePath.__new__(figures.DevicePath)
        long_path.position = np.column_stack([np.zeros(10001), np.zeros(10001),
                                              np.cos(np.linspace(0, 3, 10001))])
        long_path.deepest = 10000
        shown = long_path.shown()
        self.assertLessEqual(len(shown), figures.MAX_PATH_POINTS + 1)
        self.assertEqual(shown[0].tolist(), long_path.position[0].tolist())
        self.assertEqual(shown[-1].tolist(), long_path.position[-1].tolist())

    def test_a_turned_tool_is_drawn_by_its_bounds_turned(self):
        _, path = self.path([outline_object("box", [-1, -1, -1], [1, 1, 0])])
        # A quarter turn about z: the tool's 4 cm along x lies along y.
        path.orientation = np.tile([math.cos(math.pi / 4), 0, 0, math.sin(math.pi / 4)],
                                   (len(path.position), 1))
        tool = {"type": "mesh", "min": [-0.02, -0.01, -0.01], "max": [0.02, 0.01, 0.01]}
        corners = path.tool_corners(tool, 0)
        np.testing.assert_allclose(corners.max(axis=0) - corners.min(axis=0), [0.02, 0.04, 0.02],
                                   atol=1e-12)
        self.assertTrue(path.rotated(0))
        hull = figures.convex_hull(corners[:, [0, 1]])
        self.assertEqual(len(hull), 4)


if __name__ == "__main__":
    unittest.main()
