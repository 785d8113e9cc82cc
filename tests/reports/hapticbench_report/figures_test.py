"""The report's figures: the accuracy-cost figure has one front per scenario, over
runs that stayed stable, with cost = CPU time per tick of both loops. Run by CTest with
Debian's python3."""
import os
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "reports"))
from hapticbench_report import figures  # noqa: E402
from fake_runs import FakeRun  # noqa: E402


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


if __name__ == "__main__":
    unittest.main()
