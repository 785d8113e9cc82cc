"""Reading the report's inputs: the progress lines hapticbench report shows. Run by CTest with
Debian's python3."""
import os
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "reports"))
from hapticbench_report import inputs  # noqa: E402


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


if __name__ == "__main__":
    unittest.main()
