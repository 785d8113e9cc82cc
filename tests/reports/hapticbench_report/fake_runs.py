"""Runs built from summary entries alone (no folder on disk), a fake sweep's
jobs and run folders written to disk, for the report's tests."""
import json
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


def fake_sweep(root, key, values, labels=("penalty",), extra_jobs=()):
    """The job folders of a sweep over one grid key and the sweep.json beside them, the jobs
    listed in the order of `values`: force error 1000 / value N and step time p99
    1000 + value / 100 ns, so every job is on the Pareto front. extra_jobs: sweep.json
    entries of jobs without a run folder."""
    jobs, folders = [], []
    for value in values:
        name = "press__%s=%s" % (key.split("/")[-1], value)
        jobs.append({"name": name, "scenario": "../smoke/press.json", "grid": {key: value},
                     "status": "ok"})
        folder = FakeFolder(name, path=os.path.join(root, name))
        for label in labels:
            run = FakeRun(name, label, 1000.0 / value, 1000 + value // 100)
            run.folder = folder
            folder.runs.append(run)
        folders.append(folder)
    with open(os.path.join(root, "sweep.json"), "w") as f:
        json.dump({"name": "stiffness", "scenarios": ["../smoke/press.json"],
                   "grid": {key: list(values)}, "jobs": jobs + list(extra_jobs)}, f)
    return folders


TICKS_HEADER = ["t_ns", "fx", "fy", "fz", "tx", "ty", "tz", "penetration_m", "step_ns",
                "ref_fx", "ref_fy", "ref_fz", "ref_tx", "ref_ty", "ref_tz"]


def write_run_folder(path, summary):
    """A run folder on disk: the summary.json given and, per run, a ticks CSV of a few
    ticks with a force reference."""
    os.makedirs(path, exist_ok=True)
    with open(os.path.join(path, "summary.json"), "w", encoding="utf-8") as f:
        json.dump(dict(summary, schema_version=1), f)
    for run in summary["runs"]:
        with open(os.path.join(path, "ticks_%s.csv" % run["label"]), "w") as f:
            f.write(",".join(TICKS_HEADER) + "\n")
            for tick in range(5):
                f.write("%d,0,0,%g,0,0,0,,900,0,0,%g,0,0,0\n" % (tick * 1000000, tick, tick))
    return inputs.load_run_folder(path)


# The metric table entries a history's summaries carry (as `hapticbench run` writes them).
HISTORY_METRIC_TABLE = [
    {"name": "force_err_rms_n", "pointer": "/accuracy/force_err_rms_n", "unit": "N",
     "better": "lower", "compare": "tolerance", "abs_tol": 1e-6},
    {"name": "max_penetration_m", "pointer": "/accuracy/penetration_max_m", "unit": "m",
     "better": "lower", "compare": "tolerance", "abs_tol": 1e-7},
    {"name": "tick_p99_us", "pointer": "/timing/step_ns/p99", "unit": "ns", "better": "lower",
     "compare": "none", "abs_tol": 0.0},
]


def history_run(label, error=0.1, penetration_m=0.002, step_p99_ns=1000, instructions=None,
                stable=True):
    """A summary.json run entry with the metrics a history follows."""
    return {"label": label, "algorithm": label,
            "accuracy": {"force_err_rms_n": error, "penetration_max_m": penetration_m},
            "timing": {"step_ns": {"p99": step_p99_ns},
                       "instructions": ({"step_per_tick_mean": instructions}
                                        if instructions is not None else None)},
            "stability": {"verdict": {"stable": stable, "pass": stable}}}


def write_history(root, commits):
    """A history folder as `hapticbench history add` stores it: history.json listing one
    entry per (commit, {scenario: [summary run entries]}), oldest first, and each
    scenario's summary.json under the entry's folder."""
    entries = []
    for number, (commit, scenarios) in enumerate(commits, start=1):
        folder = "%04d-%s" % (number, commit[:7])
        for scenario, runs in scenarios.items():
            os.makedirs(os.path.join(root, folder, scenario), exist_ok=True)
            with open(os.path.join(root, folder, scenario, "summary.json"), "w",
                      encoding="utf-8") as f:
                json.dump({"schema_version": 1, "scenario": {"name": scenario},
                           "metric_table": HISTORY_METRIC_TABLE, "runs": list(runs)}, f)
        entries.append({"commit": commit, "date": "2026-12-%02dT10:00:00Z" % number,
                        "folder": folder, "scenarios": list(scenarios)})
    with open(os.path.join(root, "history.json"), "w", encoding="utf-8") as f:
        json.dump({"schema_version": 1, "entries": entries}, f)
    return entries
