"""The report page: captions come from the metric table's own definitions, not from a
second copy (the stability figure once described a same-tick observer the metric no longer
is). Run by CTest with Debian's python3."""
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "reports"))
from hapticbench_report import page  # noqa: E402
from fake_runs import FakeRun, write_run_folder  # noqa: E402

TEMPLATE = os.path.join(os.path.dirname(__file__), "..", "..", "..", "reports",
                        "report_template.html")


class StabilityCaptionTest(unittest.TestCase):
    def test_the_passivity_caption_is_the_metric_tables_definition(self):
        run = FakeRun("press", "god_object", 0.1, 1000)
        run.summary["stability"]["passivity_energy_min_j"] = -0.002
        folder = tempfile.TemporaryDirectory()
        self.addCleanup(folder.cleanup)
        run.folder.path = folder.name
        table = [{"name": "passivity_energy_min_j",
                  "description": "minimum over time of the port energy: the held wrench's work"}]
        html = page.stability_html([run.folder], [run], table)
        self.assertIn("minimum over time of the port energy: the held wrench", html)
        self.assertNotIn("Σ (F·v", html)



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


if __name__ == "__main__":
    unittest.main()
