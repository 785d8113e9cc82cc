"""Results across commits, as `hapticbench history add` stores them: reading a history folder,
each metric's series per scenario and label over its entries, and the first entry at which
the metric moved beyond its tolerance.

A history folder:

    HISTORY_DIR/history.json   {"schema_version": 1, "entries": [{"commit", "date", "folder",
                                "scenarios": [name, ...]}, ...]}  (commit order, oldest first)
    HISTORY_DIR/<folder>/<scenario name>/summary.json   a run folder's summary.json, verbatim

Bad input is a ReportInputError naming the file and the place in it."""
import json
import os

from .inputs import ReportInputError, dig, finite_number, read_json_object, read_summary

# compare's default tolerance relative to the baseline (hapticbench compare --rel-tol).
RELATIVE_TOLERANCE = 0.05

# Wall-clock step times are noisy: a move is a ratio beyond this (either way).
STEP_TIME_RATIO = 1.25

# Instruction counts are nearly exact: a move is a change beyond this share.
INSTRUCTIONS_SHARE = 0.02


class Metric:
    """A metric the history follows: where it is in a summary's run, how it is shown and
    which rule says it moved ("tolerance", "ratio", "share" or "verdict")."""

    def __init__(self, key, title, unit, path, rule, scale=1.0):
        self.key = key
        self.title = title
        self.unit = unit
        self.path = path
        self.rule = rule
        self.scale = scale

    @property
    def pointer(self):
        return "/" + "/".join(self.path)

    def value(self, run):
        """The metric of one summary run, in the unit shown, or None."""
        value = dig(run, *self.path)
        if self.rule == "verdict":
            return value if isinstance(value, bool) else None
        return value * self.scale if finite_number(value) else None

    def heading(self):
        return "%s (%s)" % (self.title, self.unit) if self.unit else self.title


METRICS = [
    Metric("force_err_rms_n", "force error RMS", "N", ("accuracy", "force_err_rms_n"),
           "tolerance"),
    Metric("max_penetration_m", "max penetration", "mm", ("accuracy", "penetration_max_m"),
           "tolerance", 1e3),
    Metric("tick_p99_us", "step time p99", "µs", ("timing", "step_ns", "p99"), "ratio", 1e-3),
    Metric("instructions_per_step", "instructions per step", "",
           ("timing", "instructions", "step_per_tick_mean"), "share"),
    Metric("stable", "stability verdict", "", ("stability", "verdict", "stable"), "verdict"),
]

METRICS_BY_KEY = {metric.key: metric for metric in METRICS}


class Entry:
    """One stored commit: its place in the history, commit, date, folder and the summaries
    of the scenarios it holds ({scenario: summary})."""

    def __init__(self, index, commit, date, folder, summaries):
        self.index = index
        self.commit = commit
        self.date = date
        self.folder = folder
        self.summaries = summaries

    @property
    def short_commit(self):
        return short_commit(self.commit)


def short_commit(commit):
    """The commit as an axis shows it: its first 7 characters, "-dirty" kept."""
    dirty = commit.endswith("-dirty")
    bare = commit[:-len("-dirty")] if dirty else commit
    return bare[:7] + ("-dirty" if dirty else "")


class Point:
    """One entry of a series: the value (None: not measured or the label not run), whether
    the label was unstable there, and the summary's metric table entry of the metric (its
    `better` and `abs_tol`), None when the table has none."""

    def __init__(self, entry, value, unstable, rule):
        self.entry = entry
        self.value = value
        self.unstable = unstable
        self.rule = rule


class Move:
    """A series' first move: the entry where it moved, the value before (at the last entry
    that measured it) and after, and whether that is "worse" or "better"."""

    def __init__(self, scenario, label, metric, before, after, direction, why):
        self.scenario = scenario
        self.label = label
        self.metric = metric
        self.before = before    # Point
        self.after = after      # Point
        self.direction = direction
        self.why = why

    @property
    def entry(self):
        return self.after.entry


class History:
    """A history folder read: its entries, and per scenario and label each metric's series
    ({scenario: {label: {metric key: [Point per entry]}}}, labels in order first met)."""

    def __init__(self, path, entries):
        self.path = path
        self.entries = entries
        self.series = {}
        for entry in entries:
            for scenario, summary in entry.summaries.items():
                labels = self.series.setdefault(scenario, {})
                for run in summary["runs"]:
                    labels.setdefault(run["label"], None)
        for scenario, labels in self.series.items():
            for label in labels:
                labels[label] = {metric.key: [self.point(entry, scenario, label, metric)
                                              for entry in entries] for metric in METRICS}

    @staticmethod
    def point(entry, scenario, label, metric):
        summary = entry.summaries.get(scenario)
        run = next((r for r in (summary or {}).get("runs", []) if r.get("label") == label), None)
        if run is None:
            return Point(entry, None, False, None)
        rule = next((m for m in summary.get("metric_table") or []
                     if isinstance(m, dict) and m.get("pointer") == metric.pointer), None)
        return Point(entry, metric.value(run),
                     dig(run, "stability", "verdict", "stable") is False, rule)

    def labels(self):
        """Every label in the order first met (for the page's label colours)."""
        return list(dict.fromkeys(label for labels in self.series.values() for label in labels))

    def measured(self, scenario, metric_key):
        """Whether any label of the scenario has a value of the metric."""
        return any(point.value is not None for metrics in self.series[scenario].values()
                   for point in metrics[metric_key])

    def first_moves(self):
        """The first move of every series that moved, in the order of scenarios, labels and
        METRICS."""
        moves = []
        for scenario, labels in self.series.items():
            for label, metrics in labels.items():
                for metric in METRICS:
                    move = first_move(metric, metrics[metric.key])
                    if move:
                        moves.append(Move(scenario, label, metric, *move))
        return moves


def better_of(point, default="lower"):
    better = (point.rule or {}).get("better") if point.rule else None
    return better if better in ("lower", "higher") else default


def abs_tol_of(point, unit_scale):
    """The metric table's abs_tol (in the summary's unit) in the unit shown, else 0."""
    tol = (point.rule or {}).get("abs_tol")
    return tol * unit_scale if finite_number(tol) and tol >= 0 else 0.0


def moved(metric, before, after):
    """(direction, why) when `after` moved from `before` beyond the metric's tolerance, else
    None. Direction: "worse" or "better" by the metric's `better` in the metric table."""
    b, a = before.value, after.value
    if metric.rule == "verdict":
        if a == b:
            return None
        return ("better" if a else "worse"), "stability verdict changed"
    if metric.rule == "tolerance":
        tolerance = max(abs_tol_of(before, metric.scale), RELATIVE_TOLERANCE * abs(b))
        if abs(a - b) <= tolerance:
            return None
        why = "beyond tolerance %.3g %s" % (tolerance, metric.unit)
        up = a > b
    elif metric.rule == "ratio":
        if b <= 0:
            return None
        ratio = a / b
        if 1 / STEP_TIME_RATIO <= ratio <= STEP_TIME_RATIO:
            return None
        why = "×%.2f, beyond ×%.2f" % (ratio, STEP_TIME_RATIO)
        up = ratio > 1
    else:  # "share"
        if b <= 0:
            return None
        share = a / b - 1
        if abs(share) <= INSTRUCTIONS_SHARE:
            return None
        why = "%+.1f %%, beyond %.0f %%" % (100 * share, 100 * INSTRUCTIONS_SHARE)
        up = share > 0
    lower_is_better = better_of(before) == "lower"
    return ("worse" if up == lower_is_better else "better"), why


def first_move(metric, points):
    """(before, after, direction, why) of the first entry whose value moved from the last
    earlier entry that measured the metric, or None. An entry that did not measure it (the
    label not run, a null value) is skipped, not taken for a move."""
    before = None
    for point in points:
        if point.value is None:
            continue
        if before is not None:
            found = moved(metric, before, point)
            if found:
                return before, point, found[0], found[1]
        before = point
    return None


def value_text(metric, value):
    if value is None:
        return "—"
    if metric.rule == "verdict":
        return "stable" if value else "unstable"
    return "%.4g" % value


def checked_name(path, location, value, what):
    """A folder or scenario name from history.json: one path component inside the history."""
    if (not isinstance(value, str) or not value or value in (".", "..")
            or "/" in value or "\\" in value or "\0" in value):
        raise ReportInputError(path, location, "expected %s (one folder name), got %s"
                               % (what, json.dumps(value)))
    return value


def read_history(directory):
    """A history folder: history.json and the summary of every scenario its entries list."""
    path = os.path.join(directory, "history.json")
    data = read_json_object(path)
    version = data.get("schema_version")
    if type(version) is not int or version != 1:
        raise ReportInputError(path, "/schema_version", "expected 1, got %s"
                               % json.dumps(version))
    listed = data.get("entries")
    if not isinstance(listed, list):
        raise ReportInputError(path, "/entries", "expected an array of entries")
    entries = []
    for index, item in enumerate(listed):
        where = "/entries/%d" % index
        if not isinstance(item, dict):
            raise ReportInputError(path, where, "expected an object")
        commit = item.get("commit")
        if not isinstance(commit, str) or not commit:
            raise ReportInputError(path, where + "/commit", "expected a string")
        date = item.get("date")
        if date is not None and not isinstance(date, str):
            raise ReportInputError(path, where + "/date", "expected a string")
        folder = checked_name(path, where + "/folder", item.get("folder"), "a folder")
        scenarios = item.get("scenarios")
        if not isinstance(scenarios, list):
            raise ReportInputError(path, where + "/scenarios", "expected an array of names")
        summaries = {}
        for n, scenario in enumerate(scenarios):
            place = "%s/scenarios/%d" % (where, n)
            name = checked_name(path, place, scenario, "a scenario")
            summaries[name] = read_stored_summary(os.path.join(directory, folder, name),
                                                  "history.json's %s lists it" % place)
        entries.append(Entry(index, commit, date or "", folder, summaries))
    return History(directory, entries)


def read_stored_summary(folder, listed_by):
    summary_path = os.path.join(folder, "summary.json")
    if not os.path.isfile(summary_path):
        raise ReportInputError(summary_path, "", "no such file (%s)" % listed_by)
    try:
        return read_summary(folder)
    except ReportInputError:
        raise
    except (OSError, UnicodeDecodeError, ValueError) as error:
        raise ReportInputError(summary_path, "", "cannot read: %s" % error)
