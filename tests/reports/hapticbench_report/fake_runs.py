"""Runs built from summary entries alone (no folder on disk), for the
report's tests."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "reports"))
from hapticbench_report import inputs  # noqa: E402


class FakeFolder:
    """A run folder's summary alone: its scenario block (name and the keys
    given) and its runs; `path` where a test reads files beside it."""

    def __init__(self, scenario, runs=(), path=None, **scenario_keys):
        self.scenario = scenario
        self.path = path
        self.summary = {"scenario": dict(name=scenario, **scenario_keys)}
        self.runs = list(runs)


class FakeRun(inputs.Run):
    """A run built from a summary entry alone (no folder on disk)."""

    def __init__(self, scenario, label, error, step_p99_ns, cpu_p99_ns=None, diverged=False,
                 nonfinite=0):
        self.folder = FakeFolder(scenario)
        self.label = label
        self.ticks = None
        timing = {"step_ns": {"p99": step_p99_ns}}
        if cpu_p99_ns is not None:
            timing["cpu_per_tick_ns"] = {"p99": cpu_p99_ns}
        self.summary = {"label": label, "timing": timing,
                        "accuracy": {"force_err_rms_n": error},
                        "stability": {"diverged": diverged, "nonfinite": nonfinite}}
