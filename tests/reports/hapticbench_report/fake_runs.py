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


# The device's and the proxy's position, as the ticks CSV of `hapticbench run` has them.
POSE_HEADER = ["dev_px", "dev_py", "dev_pz", "proxy_px", "proxy_py", "proxy_pz"]


def write_run_folder(path, summary, device=None, intent=None):
    """A run folder on disk: the summary.json given and, per run, a ticks CSV of a few
    ticks with a force reference (one tick per ms). device: the device's positions (m),
    one (x, y, z) per tick, for every label (the proxy's 1 mm above); intent: (t_s, x, y,
    z) rows of an intent.csv, as a closed-loop run writes it."""
    os.makedirs(path, exist_ok=True)
    with open(os.path.join(path, "summary.json"), "w", encoding="utf-8") as f:
        json.dump(dict(summary, schema_version=1), f)
    positions = list(device) if device is not None else [None] * 5
    for run in summary["runs"]:
        with open(os.path.join(path, "ticks_%s.csv" % run["label"]), "w") as f:
            f.write(",".join(TICKS_HEADER + (POSE_HEADER if device is not None else [])) + "\n")
            for tick, p in enumerate(positions):
                pose = ",%r,%r,%r,%r,%r,%r" % (*p, p[0], p[1], p[2] + 0.001) if p else ""
                f.write("%d,0,0,%g,0,0,0,,900,0,0,%g,0,0,0%s\n"
                        % (tick * 1000000, tick, tick, pose))
    if intent is not None:
        with open(os.path.join(path, "intent.csv"), "w") as f:
            f.write("t_s,px,py,pz\n")
            f.writelines("%r,%r,%r,%r\n" % tuple(row) for row in intent)
    return inputs.load_run_folder(path)


def outline_object(kind, lo, hi, name="scene[0]", distance_only=False):
    """A scene object of summary.json's scenario.outline: its world-frame bounds (m)."""
    return {"name": name, "type": kind, "min": list(lo), "max": list(hi),
            "distance_only": distance_only}


def outline(scene, tool_half=0.01, tool_type="sphere"):
    """summary.json's scenario.outline: the scene objects given and a tool whose bounds
    span ± tool_half (m) about its frame's origin."""
    return {"scene": list(scene), "tool": {"type": tool_type, "min": [-tool_half] * 3,
                                           "max": [tool_half] * 3}}


def press(start_z=0.03, depth=0.02, ticks=200):
    """The device's positions of a press along -z from start_z, down by depth and back."""
    half = ticks // 2
    down = [start_z - depth * k / half for k in range(half)]
    return [(0.0, 0.0, z) for z in down + down[::-1]]


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
