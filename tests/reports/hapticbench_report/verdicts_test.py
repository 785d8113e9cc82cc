"""The page leads with the answer: a card per label saying whether it stayed stable, and
the best label by accuracy and by cost among the stable labels that render contact; a
baseline that renders no contact is marked and never ranked, on the cards or on the
Pareto front. Run by CTest with Debian's python3."""
import os
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "reports"))
from hapticbench_report import figures, verdicts  # noqa: E402
from fake_runs import FakeRun  # noqa: E402


def run(label, error, p99_ns, algorithm="penalty_analytic", stable=True, expected=None):
    result = FakeRun("press", label, error, p99_ns)
    result.summary["algorithm"] = algorithm
    result.summary["stability"]["verdict"] = {
        "stable": stable, "expected_unstable": expected,
        "reason": "pen 1 mm" if stable else "passivity -3 mJ"}
    return result


class VerdictTest(unittest.TestCase):
    def setUp(self):
        self.runs = [
            # The cheapest and most accurate on paper: the coupling alone renders no contact.
            run("coupling_only", 0.001, 100, algorithm="coupling_only"),
            run("wobbly", 0.002, 300, stable=False),
            run("fast", 1.0, 800),
            run("exact", 0.05, 9000),
            run("explicit", 0.01, 200, stable=False, expected="past its limit on purpose"),
        ]

    def test_an_unstable_label_is_shown_unstable(self):
        html = verdicts.verdicts_html(self.runs)
        self.assertIn('data-label="wobbly" data-state="unstable"', html)
        self.assertIn('data-label="exact" data-state="stable"', html)
        self.assertIn('data-label="explicit" data-state="expected"', html)
        self.assertIn("unstable, as expected", html)
        self.assertIn('data-label="coupling_only" data-state="stable"><h4>', html)
        self.assertIn('<span class="tag">baseline</span>', html)

    def test_best_by_accuracy_and_by_cost_among_stable_labels_rendering_contact(self):
        accurate, cheap = verdicts.best_runs(self.runs)["press"]
        self.assertEqual((accurate.label, cheap.label), ("exact", "fast"))
        html = verdicts.verdicts_html(self.runs)
        self.assertIn('best-accuracy" data-label="exact"', html)
        self.assertIn('best-cost" data-label="fast"', html)

    def test_a_label_over_the_tick_is_said_to_be(self):
        html = verdicts.verdict_card("slow", [run("slow", 0.1, 1500000)])
        self.assertIn('<span class="fail">over the 1 ms tick</span>', html)

    def test_a_coupling_only_run_is_never_on_the_pareto_front(self):
        _, fronts, _, _ = figures.pareto_figure(self.runs)
        # Without the baseline mark it would beat every run and be the whole front.
        self.assertEqual(fronts["press"], ["explicit", "wobbly"])


if __name__ == "__main__":
    unittest.main()
