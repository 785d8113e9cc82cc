"""Reading the report's inputs: the progress lines hapticbench report shows; a summary's
scenario.outline and a closed-loop run's intent.csv. Run by CTest with Debian's python3."""
import os
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "reports"))
from hapticbench_report import inputs  # noqa: E402
from fake_runs import outline, outline_object, press, write_run_folder  # noqa: E402

RENDER_REPORT = os.path.join(os.path.dirname(__file__), "..", "..", "..", "reports",
                             "render_report.py")


class ProgressTest(unittest.TestCase):
    def test_steps_are_lines_of_done_total_unit_and_phase_on_the_descriptor(self):
        read_fd, write_fd = os.pipe()
        progress = inputs.Progress(write_fd)
        progress.step("reading run folders", 2, 5, "folders")
        progress.step("drawing the summary figures")
        progress.out.close()
        with os.fdopen(read_fd) as lines:
            self.assertEqual(lines.read(), "2 5 folders reading run folders\n"
                                           "0 0 - drawing the summary figures\n")

    def test_without_a_descriptor_or_once_the_reader_is_gone_nothing_fails(self):
        inputs.Progress().step("anything", 1, 2, "units")
        read_fd, write_fd = os.pipe()
        progress = inputs.Progress(write_fd)
        os.close(read_fd)
        progress.step("after the reader left", 1, 2, "units")  # EPIPE is swallowed
        self.assertIsNone(progress.out)


class OutlineTest(unittest.TestCase):
    """scenario.outline is optional (older summaries have none, null is none); one that is
    not as hapticbench writes it is bad input like any malformed summary: exit 2 naming
    the file and the place, never an internal error."""

    BOX = outline_object("box", [-0.2, -0.2, -0.02], [0.2, 0.2, 0.0])

    def folder(self, scenario_outline, intent=None):
        scratch = tempfile.TemporaryDirectory()
        self.addCleanup(scratch.cleanup)
        path = os.path.join(scratch.name, "press")
        summary = {"scenario": {"name": "press", "outline": scenario_outline},
                   "runs": [{"label": "god_object"}]}
        try:
            return path, write_run_folder(path, summary, press(), intent)
        except inputs.ReportInputError as error:
            return path, error

    def test_an_outline_as_hapticbench_writes_it_is_read(self):
        _, folder = self.folder(outline([self.BOX], 0.02))
        self.assertEqual(folder.outline["scene"][0]["type"], "box")
        self.assertIsNone(folder.intent)
        self.assertIn("dev_pz", folder.runs[0].ticks)
        _, folder = self.folder(None)
        self.assertIsNone(folder.outline)
        # A shape this reader does not know yet is drawn as its bounds, not refused.
        _, folder = self.folder(outline([outline_object("cylinder", [0, 0, 0], [1, 1, 1])]))
        self.assertEqual(folder.outline["scene"][0]["type"], "cylinder")

    def test_a_malformed_outline_names_the_file_and_the_place(self):
        tool = outline([])["tool"]
        cases = [
            ([], "/scenario/outline: expected an object or null"),
            ({"tool": tool}, "/scenario/outline/scene: expected an array"),
            ({"scene": [dict(self.BOX, min="-0.2,-0.2,-0.02")], "tool": tool},
             "/scenario/outline/scene/0/min: expected an array of three numbers"),
            ({"scene": [dict(self.BOX, max=[0.2, 0.2])], "tool": tool},
             "/scenario/outline/scene/0/max: expected an array of three numbers"),
            ({"scene": [dict(self.BOX, type=3)], "tool": tool},
             "/scenario/outline/scene/0/type: expected a string"),
            ({"scene": [dict(self.BOX, distance_only="no")], "tool": tool},
             "/scenario/outline/scene/0/distance_only: expected true or false"),
            ({"scene": [self.BOX, dict(self.BOX, min=[0.3, 0, 0])], "tool": tool},
             "/scenario/outline/scene/1: expected min <= max"),
            ({"scene": [self.BOX]}, "/scenario/outline/tool: expected an object"),
        ]
        for bad, message in cases:
            path, error = self.folder(bad)
            self.assertIsInstance(error, inputs.ReportInputError, bad)
            self.assertIn(os.path.join(path, "summary.json") + ": " + message, str(error))

    def test_the_renderer_exits_2_on_a_malformed_outline(self):
        path, _ = self.folder({"scene": [dict(self.BOX, min=None)], "tool": outline([])["tool"]})
        result = subprocess.run([sys.executable, RENDER_REPORT, "--out",
                                 os.path.join(path, "report.html"), path],
                                capture_output=True, text=True)
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn(os.path.join(path, "summary.json") + ": /scenario/outline/scene/0/min",
                      result.stderr)
        self.assertNotIn("internal error", result.stderr)

    def test_a_closed_loop_runs_intent_is_read_and_checked(self):
        _, folder = self.folder(None, intent=[(0.0, 0.0, 0.0, 0.03), (0.01, 0.0, 0.0, 0.029)])
        self.assertEqual(folder.intent["pz"].tolist(), [0.03, 0.029])
        path, _ = self.folder(None)
        with open(os.path.join(path, "intent.csv"), "w") as f:
            f.write("t_s,px,py,pz\n0,0,0,0.03\n0.01,0,0,high\n")
        with self.assertRaises(inputs.ReportInputError) as raised:
            inputs.load_run_folder(path)
        self.assertIn("intent.csv: line 3, column pz: expected a number", str(raised.exception))


if __name__ == "__main__":
    unittest.main()
