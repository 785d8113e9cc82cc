"""The report page: captions come from the metric table's own definitions, not from a
second copy (the stability figure once described a same-tick observer the metric no longer
is). Run by CTest with Debian's python3."""
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "reports"))
from hapticbench_report import page  # noqa: E402
from fake_runs import FakeRun  # noqa: E402


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


if __name__ == "__main__":
    unittest.main()
