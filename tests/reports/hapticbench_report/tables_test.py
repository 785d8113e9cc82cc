"""The report's tables: numbers as text, work counters, the stress matrix (the
runs' stability verdicts), stability margins, Z-width results and friction. Run by CTest with
Debian's python3."""
import json
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "reports"))
from hapticbench_report import inputs, tables  # noqa: E402
from fake_runs import FakeFolder, FakeRun  # noqa: E402


class NumberTextTest(unittest.TestCase):
    def test_microseconds_print_as_c_printf_does(self):
        # printf("%.2f", 8935 / 1000.0) prints 8.94; 8935 * 1e-3 would print 8.93.
        self.assertEqual(tables.fmt(8935, "%.2f", 1e-3), "8.94")
        self.assertEqual(tables.fmt(1234567, "%.2f", 1e-3), "1234.57")
        self.assertEqual(tables.fmt(0.0012, "%.3f", 1e3), "1.200")
        self.assertIsNone(tables.fmt(float("nan"), "%.2f", 1e-3))


class WorkCountersTest(unittest.TestCase):
    def test_one_row_per_counter_one_column_per_label(self):
        class ScenarioFolder:
            slug = "press"
            runs = [FakeRun("press", "god_object", 0.5, 200),
                    FakeRun("press", "penalty", 0.5, 200)]
        ScenarioFolder.runs[0].summary["contacts"] = {
            "work": {"ccd_budget_hits": 3, "ccd_bound_tests": 1200}}
        html = tables.work_counters_html(ScenarioFolder)
        self.assertIn("<code>ccd_budget_hits</code></td><td>3</td><td class=\"na\"", html)
        self.assertIn("<code>ccd_bound_tests</code></td><td>1200</td>", html)
        self.assertLess(html.index("ccd_bound_tests"), html.index("ccd_budget_hits"))
        ScenarioFolder.runs[0].summary["contacts"] = {"work": {}}
        self.assertEqual(tables.work_counters_html(ScenarioFolder), "")


class StressRun:
    """A run whose summary carries hapticbench's stability verdict."""
    def __init__(self, label, stable=True, reason="pen 1.9 mm", failed=None):
        self.label = label
        verdict = {"stable": stable, "failed": failed, "reason": reason}
        self.summary = {"label": label, "stability": {"verdict": verdict},
                        "accuracy": {"penetration_max_m": 0.0019}}


class StressMatrixTest(unittest.TestCase):
    def test_a_cell_is_the_runs_verdict(self):
        # The checks and their order are hapticbench's
        # (tests/harness/metrics/stability_verdict_test.cpp); the report
        # shows what the summary says.
        verdict = tables.stress_verdict
        self.assertEqual(verdict(StressRun("a", False, "tunnelled 9×", "tunnelled")),
                         (False, "tunnelled 9×"))
        self.assertEqual(verdict(StressRun("a")), (True, "pen 1.9 mm"))
        old = StressRun("a")
        old.summary["stability"] = {"diverged": True}  # written before verdicts
        self.assertEqual(verdict(old), (None, "no verdict"))

    def test_only_scenarios_tagged_stress_make_the_matrix(self):
        stress = FakeFolder("thin_wall", [StressRun("coupling_only", False, "tunnelled 1×",
                                                    "tunnelled"), StressRun("god_object")],
                            tags=["stress"])
        # The folder a scenario came from does not matter, only its tag.
        other = FakeFolder("press", [StressRun("other")], tags=["smoke"])
        other.summary["scenario"]["path"] = "/x/scenarios/stress/press.json"
        page = tables.stress_matrix_html([stress, other])
        self.assertIn("thin_wall", page)
        self.assertNotIn(">other<", page)
        self.assertIn('data-pass="false">✗ tunnelled 1×', page)
        self.assertIn('data-pass="true">✓ pen 1.9 mm', page)
        self.assertIn("1 of the cells fail", page)
        self.assertEqual(tables.stress_matrix_html([other]), "")


class StabilityMarginsTest(unittest.TestCase):
    def result(self, label, param, largest, smallest, **unstable):
        runs = [{"value": 100.0, "stable": True}]
        if smallest is not None:
            runs.append(dict({"value": smallest, "stable": False, "diverged": False,
                              "nonfinite": 0, "passivity_energy_min_j": 0.0,
                              "chatters": False}, **unstable))
        return ("/m/%s%s/stability.json" % (label, param.replace("/", "_")),
                {"scenario": "box", "label": label, "param": param, "algorithm": "penalty_analytic",
                 "integrator": "explicit_euler", "epsilon_j": 1e-6, "range": [100.0, 1e6],
                 "largest_stable": largest, "smallest_unstable": smallest, "runs": runs,
                 "criterion": "stable: ..."})

    def test_one_row_per_label_one_column_per_quantity(self):
        page = tables.stability_margins_html([
            self.result("explicit", "/coupling/k_t", 3924.19, 3995.42, chatters=True),
            self.result("explicit", "/algorithms/0/params/contact_stiffness", 4946.9, 5002.9,
                        passivity_energy_min_j=-0.002),
            self.result("implicit", "/coupling/k_t", 1e6, None),
            self.result("vps", "/algorithms/3/params/point_stiffness", None, 100.0,
                        diverged=True)])
        self.assertIn("coupling stiffness k_t (N/m)", page)
        self.assertIn("contact stiffness (N/m)", page)
        self.assertIn("3924<br><span class=\"small\">unstable at 3995 (chatter)", page)
        self.assertIn("4947<br><span class=\"small\">unstable at 5003 (passivity -2 mJ)", page)
        self.assertIn("1e+06 (the range&#x27;s top)", page)
        self.assertIn("none ≥ 100<br><span class=\"small\">unstable at 100 (diverged)", page)
        self.assertEqual(page.count("<tr>"), 4)  # the header and three labels
        self.assertEqual(tables.stability_margins_html([]), "")

    def test_closed_loop_reasons_are_named(self):
        page = tables.stability_margins_html([
            self.result("wall", "/coupling/k_t", 9991.4, 10064.7, display_energy_min_j=-2e-5),
            self.result("hold", "/coupling/b_t", 14067.0, 14193.7, limit_cycle=True)])
        self.assertIn("unstable at 1.006e+04 (display passivity -0.02 mJ)", page)
        self.assertIn("unstable at 1.419e+04 (limit cycle)", page)


class ZwidthTest(unittest.TestCase):
    def result(self, scenario, label, points):
        return ("/z/%s/zwidth.json" % label,
                {"scenario": scenario, "label": label, "x_param": "/coupling/b_t",
                 "y_param": "/coupling/k_t", "y_range": [1e3, 1e5], "criterion": "stable: ...",
                 "points": [{"x": x, "largest_stable": lo, "smallest_unstable": hi}
                            for x, lo, hi in points]})

    def test_one_figure_per_scenario_with_every_label(self):
        page = tables.zwidth_html([
            self.result("wall", "god_object", [(0, 14002, 14167), (5, 23160, 23432)]),
            self.result("wall", "penalty", [(0, 9000, 9100), (5, 1e5, None)]),
            self.result("slab", "god_object", [(0, 3000, 3100)])])
        self.assertEqual(page.count("<figure>"), 2)
        self.assertIn('id="fig-zwidth-wall"', page)
        self.assertIn('id="fig-zwidth-slab"', page)
        self.assertIn("god_object (god_object), penalty (penalty)", page)
        self.assertEqual(tables.zwidth_html([]), "")

    def test_a_map_without_points_is_bad_input_naming_the_field(self):
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "zwidth.json")
            with open(path, "w") as f:
                json.dump({"scenario": "s", "label": "l", "x_param": "/a", "y_param": "/b",
                           "points": []}, f)
            with self.assertRaises(inputs.ReportInputError) as raised:
                inputs.read_zwidth_result(path)
            self.assertIn("/points", str(raised.exception))


class FrictionRun:
    def __init__(self, label, algorithm, error):
        self.label = label
        # What the registry says, as hapticbench writes it; the report keeps no list.
        self.summary = {"label": label, "algorithm": algorithm,
                        "renders_friction": algorithm == "constrained_dynamics",
                        "accuracy": {"force_err_rms_n": error, "penetration_max_m": 0.0}}


class FrictionTest(unittest.TestCase):
    def test_rough_scenes_list_each_run_and_whether_it_renders_friction(self):
        rough = FakeFolder("press_drag", [FrictionRun("cd", "constrained_dynamics", 0.098),
                                          FrictionRun("penalty", "penalty_analytic", 3.58)],
                           scene_friction=[0.0, 0.8])
        smooth = FakeFolder("press", [FrictionRun("other", "god_object", 0.1)],
                            scene_friction=[0.0])
        page = tables.friction_html([rough, smooth])
        self.assertIn("<td>0.8</td><td class=\"text\">cd</td>"
                      "<td class=\"text\" data-friction=\"true\">Coulomb μ</td><td>0.098</td>",
                      page)
        self.assertIn('data-friction="false">frictionless</td><td>3.58</td>', page)
        self.assertNotIn(">other<", page)
        self.assertEqual(tables.friction_html([smooth]), "")
        # Summaries written before scenes had friction have no field: no section.
        self.assertEqual(tables.friction_html([FakeFolder("old", scene_friction=None)]), "")


if __name__ == "__main__":
    unittest.main()
