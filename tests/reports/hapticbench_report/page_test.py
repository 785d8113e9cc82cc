"""The report page: captions come from the metric table's own definitions, not from a
second copy (the stability figure once described a same-tick observer the metric no longer
is); a scenario's section shows its scene when the summary outlines it and, in closed loop,
the device against the intent. Run by CTest with Debian's python3."""
import os
import re
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "reports"))
from hapticbench_report import page  # noqa: E402
from hapticbench_report.inputs import headline, use_headline_metrics  # noqa: E402
from fake_runs import (  # noqa: E402
    FakeRun, outline, outline_object, press, write_run_folder)

TEMPLATE = os.path.join(os.path.dirname(__file__), "..", "..", "..", "reports",
                        "report_template.html")


class StabilityCaptionTest(unittest.TestCase):
    def test_the_passivity_caption_is_the_metric_tables_definition(self):
        run = FakeRun("press", "god_object", 0.1, 1000)
        run.summary["stability"]["passivity_energy_min_j"] = -0.002
        folder = tempfile.TemporaryDirectory()
        self.addCleanup(folder.cleanup)
        run.folder.path = folder.name
        table = [{"name": "passivity_energy_min_mj", "pointer": "/stability/passivity_energy_min_j",
                  "description": "minimum over time of the port energy: the held wrench's work"}]
        html = page.stability_html([run.folder], [run], table)
        self.assertIn("minimum over time of the port energy: the held wrench", html)
        self.assertNotIn("Σ (F·v", html)

    def test_the_headline_accuracy_is_the_one_the_metric_table_names(self):
        run = FakeRun("press", "god_object", 0.1, 1000)
        self.assertEqual(0.1, headline(run.summary))
        use_headline_metrics([{"name": "other", "pointer": "/accuracy/other_n",
                               "headline": "accuracy"}])
        self.addCleanup(use_headline_metrics, [{"name": "force_err_rms_n",
                                                "pointer": "/accuracy/force_err_rms_n",
                                                "headline": "accuracy"}])
        run.summary["accuracy"]["other_n"] = 7.5
        self.assertEqual(7.5, headline(run.summary))



class ReferenceWordingTest(unittest.TestCase):
    """On a mesh scene the force reference is the mesh force reference (summary.json's
    force_reference), never "analytic"."""

    def page(self, reference, force_reference):
        scratch = tempfile.TemporaryDirectory()
        self.addCleanup(scratch.cleanup)
        summary = {"scenario": {"name": "bunny", "scene_friction": [0.0]},
                   "force_reference": force_reference,
                   "runs": [{"label": "god_object", "algorithm": "god_object",
                             "accuracy": {"force_err_rms_n": 0.1, "reference": reference},
                             "timing": {"step_ns": {"p99": 1000}}}]}
        folder = write_run_folder(os.path.join(scratch.name, "bunny"), summary)
        with open(TEMPLATE, encoding="utf-8") as f:
            return page.render([folder], f.read(), [])

    def test_a_mesh_scene_is_against_the_mesh_force_reference(self):
        html = self.page("mesh reference: rigid proxy ...", {"method": "rigid proxy ..."})
        self.assertIn("dashed: the ideal rigid contact (the mesh force reference)", html)
        self.assertIn("errors are against the mesh force reference", html)
        self.assertNotIn("(the analytic reference)", html)

    def test_an_analytic_scene_is_against_the_analytic_reference(self):
        html = self.page("ideal rigid contact: sphere tool on box", None)
        self.assertIn("dashed: the ideal rigid contact (the analytic reference)", html)
        self.assertIn("errors are against the analytic reference", html)
        self.assertNotIn("mesh force reference)", html)


class SceneSectionTest(unittest.TestCase):
    """The scene figure (summary.json's scenario.outline) and the closed-loop figure
    (intent.csv) are drawn when their data is there; a summary without them renders the
    section as before."""

    BOX = outline_object("box", [-0.2, -0.2, -0.02], [0.2, 0.2, 0.0])

    def page(self, scenario_keys, intent=None, device=press()):
        scratch = tempfile.TemporaryDirectory()
        self.addCleanup(scratch.cleanup)
        summary = {"scenario": dict(name="press", description="A sphere pressed into a box.",
                                    **scenario_keys),
                   "runs": [{"label": label, "algorithm": label,
                             "timing": {"step_ns": {"p99": 1000}}}
                            for label in ("god_object", "penalty")]}
        folder = write_run_folder(os.path.join(scratch.name, "press"), summary, device, intent)
        with open(TEMPLATE, encoding="utf-8") as f:
            return page.render([folder], f.read(), [])

    @staticmethod
    def figures(html):
        return re.findall(r'<img id="([^"]*)"', html)

    def test_an_older_summary_renders_as_before(self):
        for keys in ({}, {"outline": None}):
            self.assertEqual(self.figures(self.page(keys)),
                             ["fig-force-scenario-press", "fig-torque-scenario-press",
                              "fig-timing-scenario-press"])

    def test_an_outline_draws_the_scene_after_the_description(self):
        html = self.page({"outline": outline([self.BOX], 0.02)})
        self.assertEqual(self.figures(html)[0], "fig-scene-scenario-press")
        self.assertLess(html.index("A sphere pressed into a box."),
                        html.index('id="fig-scene-scenario-press"'))
        self.assertIn("<code>god_object</code>'s ticks", html)
        # A 400 mm box under a 20 mm press: zoomed, and the caption says so.
        self.assertIn("Zoomed to the motion with a margin: the scene spans 400 × 400 × 20 mm.",
                      html)
        self.assertNotIn("fig-intent", html)  # open loop: no intent

    def test_without_the_devices_position_the_scene_is_drawn_alone(self):
        html = self.page({"outline": outline([self.BOX], 0.02)}, device=None)
        self.assertIn('id="fig-scene-scenario-press"', html)
        self.assertIn("No ticks with the device's position: the scene alone.", html)
        self.assertNotIn("Zoomed", html)

    def test_closed_loop_draws_the_device_against_the_intent(self):
        intent = [(0.01 * k, 0.0, 0.0, 0.03 - 0.0002 * k) for k in range(20)]
        html = self.page({"outline": outline([self.BOX], 0.02)}, intent=intent)
        self.assertEqual(self.figures(html)[:2], ["fig-scene-scenario-press",
                                                  "fig-intent-scenario-press"])
        self.assertIn("device z − intent z", html)
        self.assertIn("In closed loop each label's device takes its own path", html)
        # The intent alone, without an outline, still draws its figure.
        self.assertEqual(self.figures(self.page({}, intent=intent))[0],
                         "fig-intent-scenario-press")

    def test_an_intent_without_the_devices_position_is_a_note(self):
        html = self.page({}, intent=[(0.0, 0.0, 0.0, 0.03)], device=None)
        self.assertNotIn("fig-intent", html)
        self.assertIn("no figure of the device against the intent", html)


if __name__ == "__main__":
    unittest.main()
