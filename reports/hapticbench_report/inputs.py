"""Reading what the report draws: run folders (summary.json, the ticks
logs and in closed loop intent.csv), stability.json and zwidth.json results; bad input is a
ReportInputError naming the file and the place in it. Also the progress
lines `hapticbench report` shows."""
import json
import math
import os

import numpy as np



class ReportInputError(Exception):
    """Bad input: a file, a place in it, and what was expected."""

    def __init__(self, path, location, message):
        super().__init__("%s: %s: %s" % (path, location, message) if location
                         else "%s: %s" % (path, message))


def dig(mapping, *keys):
    """mapping[k0][k1]... or None where a key is missing or a value is null."""
    value = mapping
    for key in keys:
        if not isinstance(value, dict) or key not in value:
            return None
        value = value[key]
    return value


def finite_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def number_or_none(value):
    return value if finite_number(value) else None


class Run:
    """One algorithm label of one run folder: its summary entry and ticks."""

    def __init__(self, folder, summary_run):
        self.folder = folder
        self.summary = summary_run
        self.label = str(summary_run.get("label", summary_run.get("algorithm", "?")))
        # A name inside the run folder only (hapticbench checks it too).
        ticks_name = os.path.basename(str(summary_run.get("ticks_file")
                                          or "ticks_%s.csv" % self.label))
        self.ticks_path = os.path.join(folder.path, ticks_name)
        self.ticks = read_ticks(self.ticks_path) if os.path.isfile(self.ticks_path) else None

    @property
    def name(self):
        return "%s/%s" % (self.folder.scenario, self.label)

    def step_us(self):
        """Step times (µs) from the ticks, else the summary's evenly spaced sample."""
        if self.ticks is not None:
            return self.ticks["step_ns"] / 1000.0, "ticks"
        sample = dig(self.summary, "timing", "step_ns_sample")
        if isinstance(sample, list) and sample:
            return np.asarray(sample, dtype=float) / 1000.0, "summary sample"
        return None, None

    def p99_us(self):
        return microseconds(dig(self.summary, "timing", "step_ns", "p99"))


class RunFolder:
    """A run folder: summary.json and the runs it lists."""

    def __init__(self, path, summary):
        self.path = path
        self.summary = summary
        self.scenario = str(dig(summary, "scenario", "name") or os.path.basename(path))
        self.slug = ""
        self.runs = [Run(self, run) for run in summary["runs"]]
        # Closed loop only: the operator's intent (the trace) every few ticks.
        intent_path = os.path.join(path, INTENT_FILE)
        self.intent = (read_columns(intent_path, INTENT_COLUMNS, [])
                       if os.path.isfile(intent_path) else None)

    @property
    def outline(self):
        """summary.json's scenario.outline (read_summary checked its shape), or None."""
        outline = dig(self.summary, "scenario", "outline")
        return outline if isinstance(outline, dict) else None


# The summary fields of the headline metrics, by role, as the metric table
# names them ("headline": "accuracy", "accuracy_fallback"); these defaults
# hold for a table without the key.
HEADLINE_FIELDS = {"accuracy": ("accuracy", "force_err_rms_n"),
                   "accuracy_fallback": ("accuracy", "penetration_max_m")}


def use_headline_metrics(metric_table):
    """Takes the headline metrics' summary fields from the metric table (each row's
    "headline" role and "pointer"), so that every figure and table asks the same place."""
    for metric in metric_table or []:
        role, pointer = metric.get("headline"), metric.get("pointer")
        if isinstance(role, str) and isinstance(pointer, str) and pointer.startswith("/"):
            HEADLINE_FIELDS[role] = tuple(pointer[1:].split("/"))


def headline(run_summary, role="accuracy"):
    """A run's headline metric of this role (in the summary's unit), or None."""
    return dig(run_summary, *HEADLINE_FIELDS[role])


def read_json_object(path):
    """A JSON file holding an object; bad input names the file and the line."""
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
    except OSError as error:
        raise ReportInputError(path, "", "cannot read: %s" % error.strerror)
    except json.JSONDecodeError as error:
        raise ReportInputError(path, "line %d" % error.lineno, "not JSON: %s" % error.msg)
    if not isinstance(data, dict):
        raise ReportInputError(path, "", "expected a JSON object")
    return data


def read_summary(folder):
    path = os.path.join(folder, "summary.json")
    summary = read_json_object(path)
    version = summary.get("schema_version")
    if type(version) is not int or version != 1:  # neither true nor 1.0 is version 1
        raise ReportInputError(path, "/schema_version", "expected 1, got %s"
                               % json.dumps(summary.get("schema_version")))
    if not isinstance(summary.get("runs"), list):
        raise ReportInputError(path, "/runs", "expected an array of runs")
    for index, run in enumerate(summary["runs"]):
        if not isinstance(run, dict) or not isinstance(run.get("label"), str):
            raise ReportInputError(path, "/runs/%d/label" % index, "expected a string")
    check_outline(path, dig(summary, "scenario", "outline"))
    return summary


# The shapes an outline names; another name is drawn as its bounds, as a mesh.
OUTLINE_TYPES = ("box", "sphere", "capsule", "box_with_hole", "mesh")


def check_outline(path, outline):
    """scenario.outline, when there is one (null: none), as hapticbench writes it: scene
    objects and the tool, each with a type and min <= max bounds of three numbers."""
    if outline is None:
        return
    where = "/scenario/outline"
    if not isinstance(outline, dict):
        raise ReportInputError(path, where, "expected an object or null")
    if not isinstance(outline.get("scene"), list):
        raise ReportInputError(path, where + "/scene", "expected an array of scene objects")
    objects = [("%s/scene/%d" % (where, i), o) for i, o in enumerate(outline["scene"])]
    for place, item in objects + [(where + "/tool", outline.get("tool"))]:
        if not isinstance(item, dict):
            raise ReportInputError(path, place, "expected an object")
        if not isinstance(item.get("type"), str):
            raise ReportInputError(path, place + "/type", "expected a string")
        for key in ("min", "max"):
            value = item.get(key)
            if not (isinstance(value, list) and len(value) == 3
                    and all(finite_number(v) for v in value)):
                raise ReportInputError(path, "%s/%s" % (place, key),
                                       "expected an array of three numbers (m)")
        if any(lo > hi for lo, hi in zip(item["min"], item["max"])):
            raise ReportInputError(path, place, "expected min <= max on every axis")
        for key, kind, name in (("name", str, "a string"),
                                ("distance_only", bool, "true or false")):
            if key in item and not isinstance(item[key], kind):
                raise ReportInputError(path, "%s/%s" % (place, key), "expected " + name)


def read_ticks(path):
    """The plotted columns of a ticks CSV as float arrays (empty field -> NaN)."""
    return read_columns(path, REQUIRED_TICKS_COLUMNS, OPTIONAL_TICKS_COLUMNS,
                        BACKEND_PEN_SUFFIX)


def read_columns(path, required, optional, optional_suffix=None):
    """The required columns of a CSV and those of the optional ones (or ending with
    optional_suffix) it has, as float arrays (empty field -> NaN); an optional column
    with no number at all is left out."""
    with open(path, encoding="utf-8") as f:
        header = f.readline().rstrip("\r\n").split(",")
        index = {name: i for i, name in enumerate(header)}
        missing = [name for name in required if name not in index]
        if missing:
            raise ReportInputError(path, "line 1", "expected columns %s in the header"
                                   % ", ".join(missing))
        optional = list(optional) + [c for c in header if optional_suffix
                                     and c.endswith(optional_suffix)]
        wanted = list(required) + [c for c in dict.fromkeys(optional) if c in index]
        positions = [index[name] for name in wanted]
        rows = []
        for line_number, line in enumerate(f, start=2):
            fields = line.rstrip("\r\n").split(",")
            if len(fields) != len(header):
                raise ReportInputError(path, "line %d" % line_number, "expected %d fields, got %d"
                                       % (len(header), len(fields)))
            try:
                rows.append([float(fields[p]) if fields[p] else math.nan for p in positions])
            except ValueError:
                bad = next(name for name, p in zip(wanted, positions)
                           if fields[p] and not is_float(fields[p]))
                raise ReportInputError(path, "line %d, column %s" % (line_number, bad),
                                       "expected a number, got \"%s\"" % fields[index[bad]])
    table = np.asarray(rows, dtype=float).reshape(len(rows), len(wanted))
    columns = {name: table[:, i] for i, name in enumerate(wanted)}
    for name in wanted[len(required):]:  # empty fields say "not measured"
        if not np.isfinite(columns[name]).any():
            del columns[name]
    return columns


def is_float(text):
    try:
        float(text)
        return True
    except ValueError:
        return False


def read_json_or_none(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def read_stability_result(path):
    """A stability.json as `hapticbench stability` writes it."""
    data = read_json_object(path)
    for key in ("scenario", "label", "param"):
        if not isinstance(data.get(key), str):
            raise ReportInputError(path, "/" + key, "expected a string")
    if not isinstance(data.get("runs"), list):
        raise ReportInputError(path, "/runs", "expected an array of runs")
    return data


def read_zwidth_result(path):
    """A zwidth.json as `hapticbench zwidth` writes it."""
    data = read_json_object(path)
    for key in ("scenario", "label", "x_param", "y_param"):
        if not isinstance(data.get(key), str):
            raise ReportInputError(path, "/" + key, "expected a string")
    points = data.get("points")
    if not isinstance(points, list) or not points:
        raise ReportInputError(path, "/points", "expected a non-empty array of points")
    for i, point in enumerate(points):
        if not isinstance(point, dict) or not finite_number(point.get("x")):
            raise ReportInputError(path, "/points/%d/x" % i, "expected a number")
        for key in ("largest_stable", "smallest_unstable"):
            if point.get(key) is not None and not finite_number(point.get(key)):
                raise ReportInputError(path, "/points/%d/%s" % (i, key),
                                       "expected a number or null")
    return data


def load_run_folder(path):
    """A run folder's summary and ticks; a file that is not as hapticbench
    writes it (unreadable, not UTF-8, wrong shape) is bad input naming it."""
    try:
        return RunFolder(path, read_summary(path))
    except ReportInputError:
        raise
    except (OSError, UnicodeDecodeError, ValueError, KeyError, TypeError, IndexError) as error:
        raise ReportInputError(path, "", "not a run folder as hapticbench writes it (%s: %s)"
                               % (type(error).__name__, error))


# Algorithms that render no contact (the proxy on the virtual coupling alone): a
# baseline to compare with, never ranked among the algorithms that render contact.
BASELINE_ALGORITHMS = ("coupling_only",)


def is_baseline(run):
    return run.summary.get("algorithm") in BASELINE_ALGORITHMS


def reference_kind(run):
    """What the run's force error is measured against: "mesh" (the mesh force reference,
    summary.json's force_reference), "analytic" (the closed forms of an analytic scene,
    accuracy.reference naming the ideal contact) or None (no force reference)."""
    reference = dig(run.summary, "accuracy", "reference")
    if (isinstance(run.summary.get("force_reference"), dict)
            or isinstance(dig(run.folder.summary, "force_reference"), dict)
            or (isinstance(reference, str) and reference.startswith("mesh reference"))):
        return "mesh"
    return "analytic" if isinstance(reference, str) and reference else None


REFERENCE_NAMES = {"analytic": "the analytic reference", "mesh": "the mesh force reference"}


def reference_wording(runs):
    """The reference the runs' force errors are against, in words for the page."""
    kinds = sorted({reference_kind(run) for run in runs} - {None})
    if len(kinds) == 2:
        return ("the analytic reference on analytic scenes, the mesh force reference on "
                "mesh scenes")
    return REFERENCE_NAMES[kinds[0]] if kinds else "the reference"


def scenario_description(folder):
    """(description, where it comes from) of the run's scenario, or None: the summary's
    own (the scenario as it ran), else for older summaries the scenario.json a sweep
    writes into each job's folder, else the scenario file the summary names, when it is
    still there under the same name."""
    summary_path = dig(folder.summary, "scenario", "path")
    recorded = dig(folder.summary, "scenario", "description")
    if isinstance(recorded, str) and recorded:
        return recorded, summary_path if isinstance(summary_path, str) else "summary.json"
    candidates = [os.path.join(str(folder.path), "scenario.json")] if folder.path else []
    candidates += [summary_path] if isinstance(summary_path, str) else []
    for path in candidates:
        scenario = read_json_or_none(path)
        if (isinstance(scenario, dict) and isinstance(scenario.get("description"), str)
                and scenario.get("name") in (folder.scenario, None)):
            return scenario["description"], path
    return None


def microseconds(ns):
    """ns / 1000, or None: divided, not multiplied by 1e-3, so that 8935 ns prints 8.94 µs
    the way C's printf("%.2f", ns / 1000.0) does."""
    return ns / 1000.0 if finite_number(ns) else None


class Progress:
    """Where rendering is, for `hapticbench report`'s progress display: one
    line per step, "<done> <total> <unit> <phase>" (unit "-": none), on the
    file descriptor it passes with --progress-fd. Silent without one."""

    def __init__(self, fd=None):
        self.out = os.fdopen(fd, "w", buffering=1) if fd is not None else None

    def step(self, phase, done=0, total=0, unit="-"):
        if self.out is None:
            return
        try:
            self.out.write("%d %d %s %s\n" % (done, total, unit, phase))
        except OSError:  # the reader went away: rendering goes on
            self.out = None


REQUIRED_TICKS_COLUMNS = ["t_ns", "fx", "fy", "fz", "tx", "ty", "tz", "penetration_m", "step_ns"]


# The device's pose (the tool frame's origin and orientation) and the proxy's position,
# drawn in the scene figure and, in closed loop, against the intent.
OPTIONAL_TICKS_COLUMNS = ["ref_fx", "ref_fy", "ref_fz", "ref_tx", "ref_ty", "ref_tz",
                          "dev_px", "dev_py", "dev_pz", "dev_qw", "dev_qx", "dev_qy", "dev_qz",
                          "proxy_px", "proxy_py", "proxy_pz"]


# A closed-loop run folder's intent: the operator's (the trace's) position every
# few ticks, s and m, world frame.
INTENT_FILE = "intent.csv"


INTENT_COLUMNS = ["t_s", "px", "py", "pz"]


# Each oracle backend's penetration column is "<backend>_pen_m" (the backends
# are listed in summary.json's oracle_backends).
BACKEND_PEN_SUFFIX = "_pen_m"
