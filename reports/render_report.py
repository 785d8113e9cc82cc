#!/usr/bin/env python3
"""Renders hapticbench run folders into one self-contained HTML report.

usage: render_report.py --out REPORT.html [--template FILE] RUN_FOLDER...

Each RUN_FOLDER holds a summary.json (schema_version 1) and, unless it is a
summary-only baseline, one ticks_<label>.csv per algorithm label. The page
has a summary table per scenario and label, error against tick time (Pareto
front) across all runs, passivity and stiffness-sweep stability figures, and
per scenario the displayed force and torque against time (with the analytic
reference when there is one), penetration against time (with each oracle
backend's column when present) and the distribution of step times.

Every figure is an inline PNG, the style sheet is inline and the only script
is a few lines that count the decoded figures: the file opens offline.
`hapticbench report` calls this script; it checks the run folders first.

Exit codes: 0 written, 2 bad input (the message names the file and where).
"""
import argparse
import base64
import datetime
import html
import io
import json
import math
import os
import re
import string
import sys

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter, NullLocator  # noqa: E402

DPI = 80
ONE_MS_US = 1000.0
# Long runs are drawn from at most this many points per series, chosen as
# the minimum and maximum of each time bucket so spikes stay visible.
MAX_PLOT_POINTS = 3000
# The passivity figure shows at most this many runs (the lowest energies).
MAX_PASSIVITY_BARS = 60
# Beyond this many points the Pareto figure labels only the front.
MAX_PARETO_LABELS = 40
# Wrench panels span at least ± this (well below what a device can display),
# so rounding noise of 1e-15 N on an axis that carries nothing stays flat.
FORCE_PANEL_FLOOR_N = 1e-3
TORQUE_PANEL_FLOOR_NM = 1e-5

REQUIRED_TICKS_COLUMNS = ["t_ns", "fx", "fy", "fz", "tx", "ty", "tz", "penetration_m", "step_ns"]
OPTIONAL_TICKS_COLUMNS = ["ref_fx", "ref_fy", "ref_fz", "ref_tx", "ref_ty", "ref_tz"]
# Each oracle backend's penetration column is "<backend>_pen_m" (the backends
# are listed in summary.json's oracle_backends).
BACKEND_PEN_SUFFIX = "_pen_m"
# How the backends' columns are drawn, in the order summary.json lists them.
BACKEND_STYLES = [dict(ls=":"), dict(ls="none", marker="x"), dict(ls="-."), dict(ls="--")]
# Run folders of one scene at several coupling stiffnesses k_t (N/m), by name:
# scripts/stability-sweep writes "<scene>_k<k_t>", `hapticbench sweep` writes
# "<scene>__k_t=<k_t>__<other grid keys>".
NUMBER = r"[0-9]+(?:\.[0-9]+)?(?:[eE][+-]?[0-9]+)?"
STIFFNESS_NAMES = [re.compile(r"^(?P<head>.+)_k(?P<k>%s)(?P<tail>)$" % NUMBER),
                   re.compile(r"^(?P<head>.+)__k_t=(?P<k>%s)(?P<tail>(?:__.*)?)$" % NUMBER)]


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


def microseconds(ns):
    """ns / 1000, or None: divided, not multiplied by 1e-3, so that 8935 ns prints 8.94 µs
    the way C's printf("%.2f", ns / 1000.0) does."""
    return ns / 1000.0 if finite_number(ns) else None


# ---------------------------------------------------------------- input


class Run:
    """One algorithm label of one run folder: its summary entry and ticks."""

    def __init__(self, folder, summary_run):
        self.folder = folder
        self.summary = summary_run
        self.label = str(summary_run.get("label", summary_run.get("algorithm", "?")))
        self.ticks_path = os.path.join(folder.path, summary_run.get("ticks_file")
                                       or "ticks_%s.csv" % self.label)
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
    return summary


def read_ticks(path):
    """The plotted columns of a ticks CSV as float arrays (empty field -> NaN)."""
    with open(path, encoding="utf-8") as f:
        header = f.readline().rstrip("\r\n").split(",")
        index = {name: i for i, name in enumerate(header)}
        missing = [name for name in REQUIRED_TICKS_COLUMNS if name not in index]
        if missing:
            raise ReportInputError(path, "line 1", "expected columns %s in the header"
                                   % ", ".join(missing))
        optional = OPTIONAL_TICKS_COLUMNS + [c for c in header if c.endswith(BACKEND_PEN_SUFFIX)]
        wanted = REQUIRED_TICKS_COLUMNS + [c for c in optional if c in index]
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
    for name in wanted[len(REQUIRED_TICKS_COLUMNS):]:  # empty fields say "not measured"
        if not np.isfinite(columns[name]).any():
            del columns[name]
    return columns


def is_float(text):
    try:
        float(text)
        return True
    except ValueError:
        return False


# ---------------------------------------------------------------- figures


def png_data_uri(fig):
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=DPI)
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


def sparse_minor_ticks(axis, label_minor=False):
    """Ticks of a log axis: plain numbers (1, 10, 100) at decades, minor ticks at 2 and 5
    (labelled too when the axis spans less than two decades): readable, and cheap to draw."""
    plain = FuncFormatter(lambda value, _: "%g" % value)
    axis.set_major_formatter(plain)
    axis.set_minor_locator(LogLocator(subs=(2.0, 5.0)))
    axis.set_minor_formatter(plain if label_minor else NullFormatter())


def spans_under_two_decades(values):
    values = [v for v in values if v > 0]
    return bool(values) and max(values) < 100 * min(values)


def run_colours(runs):
    palette = matplotlib.colormaps["tab10" if len(runs) <= 10 else "tab20"]
    return {id(run): palette(i % palette.N) for i, run in enumerate(runs)}


def envelope(t, y):
    """At most MAX_PLOT_POINTS points of (t, y): each bucket's minimum and maximum."""
    n = len(t)
    if n <= MAX_PLOT_POINTS:
        return t, y
    size = -(-n // (MAX_PLOT_POINTS // 2))
    buckets = -(-n // size)
    padded = np.full(buckets * size, np.nan)
    padded[:n] = np.where(np.isfinite(y), y, np.nan)
    grid = padded.reshape(buckets, size)
    missing = np.isnan(grid)
    lowest = np.where(missing, np.inf, grid).argmin(axis=1)
    highest = np.where(missing, -np.inf, grid).argmax(axis=1)
    start = np.arange(buckets) * size
    keep = np.sort(np.column_stack([start + lowest, start + highest]), axis=1).ravel()
    keep = np.unique(keep[keep < n])
    return t[keep], y[keep]


def plot_series(ax, t, y, **style):
    y = np.where(np.isfinite(y), y, np.nan)
    ax.plot(*envelope(t, y), **style)


def same_series(arrays):
    first = arrays[0]
    return all(a.shape == first.shape and np.allclose(a, first, rtol=1e-9, atol=1e-12,
                                                      equal_nan=True) for a in arrays[1:])


def wrench_figure(runs, kind):
    """Force (kind "force") or torque ("torque") components and magnitude against time."""
    names = ("fx", "fy", "fz") if kind == "force" else ("tx", "ty", "tz")
    unit = "N" if kind == "force" else "N·m"
    symbol = "F" if kind == "force" else "τ"
    colours = run_colours(runs)
    fig = Figure(figsize=(10, 7.2))
    axes = fig.subplots(4, 1, sharex=True)
    with_ticks = [run for run in runs if run.ticks is not None]
    references = [run for run in with_ticks if all("ref_" + n in run.ticks for n in names)]
    shared_reference = len(references) == len(with_ticks) and references and same_series(
        [np.column_stack([run.ticks["ref_" + n] for n in names]) for run in references])
    for run in with_ticks:
        t = run.ticks["t_ns"] * 1e-9
        components = [run.ticks[n] for n in names]
        magnitude = np.sqrt(sum(c * c for c in components))
        for ax, y in zip(axes, components + [magnitude]):
            plot_series(ax, t, y, color=colours[id(run)], lw=1.2, label=run.label)
    for position, run in enumerate(references):
        if shared_reference and position > 0:
            break
        t = run.ticks["t_ns"] * 1e-9
        components = [run.ticks["ref_" + n] for n in names]
        magnitude = np.sqrt(sum(c * c for c in components))
        style = (dict(color="black", lw=1.0, ls="--", label="analytic reference")
                 if shared_reference else
                 dict(color=colours[id(run)], lw=0.9, ls="--", label=run.label + " reference"))
        for ax, y in zip(axes, components + [magnitude]):
            plot_series(ax, t, y, **style)
    # Rounding noise must not fill a panel: every panel spans at least a few
    # percent of the figure's peak, and at least the floor.
    peak = max([np.nanmax(np.abs(line.get_ydata())) for ax in axes for line in ax.get_lines()
                if np.isfinite(line.get_ydata()).any()] + [0.0])
    floor = max(0.02 * peak, FORCE_PANEL_FLOOR_N if kind == "force" else TORQUE_PANEL_FLOOR_NM)
    for ax, name in zip(axes, list(names) + ["|%s|" % symbol]):
        lo, hi = ax.get_ylim()
        ax.set_ylim(min(lo, -floor), max(hi, floor))
        ax.set_ylabel("%s (%s)" % (name, unit))
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("time (s)")
    axes[0].legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    fig.suptitle("displayed %s against time" % kind, fontsize=11)
    fig.subplots_adjust(left=0.08, right=0.80, top=0.94, bottom=0.07, hspace=0.12)
    return png_data_uri(fig), bool(references)


def backend_names(runs):
    """The oracle backends' names, as summary.json's oracle_backends lists
    them; for a summary without that list, the backends whose
    <name>_pen_m column a ticks log has."""
    names = []
    for run in runs:
        for entry in dig(run.folder.summary, "oracle_backends") or []:
            name = entry.get("name") if isinstance(entry, dict) else None
            if isinstance(name, str) and name not in names:
                names.append(name)
    if names:
        return names
    for run in runs:
        for column in (run.ticks or {}):
            if column.endswith(BACKEND_PEN_SUFFIX) and column != "penetration_m":
                name = column[:-len(BACKEND_PEN_SUFFIX)]
                if name not in names:
                    names.append(name)
    return names


def penetration_figure(runs):
    """Penetration (mm) of each run against time, with the oracle columns; None if none."""
    colours = run_colours(runs)
    fig = Figure(figsize=(10, 3.8))
    ax = fig.subplots()
    styles = {"penetration_m": dict(ls="-")}
    for k, name in enumerate(backend_names(runs)):
        styles[name + BACKEND_PEN_SUFFIX] = BACKEND_STYLES[k % len(BACKEND_STYLES)]
    sources = set()
    for run in runs:
        if run.ticks is None:
            continue
        t = run.ticks["t_ns"] * 1e-9
        colour = colours[id(run)]
        if np.isfinite(run.ticks["penetration_m"]).any():
            plot_series(ax, t, run.ticks["penetration_m"] * 1e3, color=colour, lw=1.3)
            sources.add("penetration_m")
        for column, style in styles.items():
            if column == "penetration_m" or column not in run.ticks:
                continue
            y = run.ticks[column] * 1e3
            ok = np.isfinite(y)
            ax.plot(*envelope(t[ok], y[ok]), color=colour, lw=0.9, ms=4, **style)
            sources.add(column)
    if not sources:
        return None
    handles = [Line2D([], [], color=colours[id(run)], lw=2, label=run.label)
               for run in runs if run.ticks is not None]
    handles += [Line2D([], [], color="grey", label=name, **styles[name])
                for name in styles if name in sources]
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8,
              frameon=False)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("penetration (mm)")
    ax.grid(True, alpha=0.3)
    fig.suptitle("penetration of the proxy's tool against time", fontsize=11)
    fig.subplots_adjust(left=0.08, right=0.80, top=0.90, bottom=0.14)
    return png_data_uri(fig)


def timing_figure(runs):
    """Histogram (log x) and CDF of step times with the 1 ms budget and each p99; None if none."""
    colours = run_colours(runs)
    samples = [(run, *run.step_us()) for run in runs]
    samples = [(run, values[values > 0], source) for run, values, source in samples
               if values is not None and (values > 0).any()]
    if not samples:
        return None
    lo = min(values.min() for _, values, _ in samples)
    hi = max(max(values.max() for _, values, _ in samples), ONE_MS_US)
    bins = np.geomspace(lo / 1.05, hi * 1.05, 70)
    fig = Figure(figsize=(10, 3.9))
    histogram, cdf = fig.subplots(1, 2)
    for run, values, source in samples:
        colour = colours[id(run)]
        label = run.label + ("" if source == "ticks" else " (summary sample)")
        histogram.hist(values, bins=bins, histtype="step", lw=1.3, color=colour, label=label)
        ordered = np.sort(values)
        cdf.step(ordered, np.arange(1, len(ordered) + 1) / len(ordered), where="post",
                 color=colour, lw=1.3, label=label)
        p99 = run.p99_us()
        if p99 is not None:
            histogram.axvline(p99, color=colour, ls=":", lw=1.2)
            cdf.plot([p99], [0.99], marker="o", ms=5, color=colour)
    for ax in (histogram, cdf):
        ax.set_xscale("log")
        sparse_minor_ticks(ax.xaxis)
        ax.axvline(ONE_MS_US, color="crimson", lw=1.5, ls="--", label="1 ms budget")
        ax.set_xlabel("step time (µs)")
        ax.grid(True, alpha=0.3, which="both")
    histogram.set_yscale("log")
    histogram.yaxis.set_minor_locator(NullLocator())
    histogram.set_ylabel("ticks")
    histogram.set_title("histogram (dotted: p99)", fontsize=9)
    cdf.axhline(0.99, color="grey", lw=0.8, ls=":")
    cdf.set_ylabel("fraction of ticks ≤ x")
    cdf.set_title("cumulative distribution (dots: p99)", fontsize=9)
    cdf.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, frameon=False)
    fig.suptitle("time of one step", fontsize=11)
    fig.subplots_adjust(left=0.07, right=0.80, top=0.86, bottom=0.14, wspace=0.25)
    return png_data_uri(fig)


def pareto_error(run):
    """(metric name, value): force error RMS when there is a reference, else penetration max."""
    force = dig(run.summary, "accuracy", "force_err_rms_n")
    if finite_number(force):
        return "force_err_rms_n", force
    penetration = dig(run.summary, "accuracy", "penetration_max_m")
    if finite_number(penetration):
        return "penetration_max_m", penetration
    return None, None


def pareto_front(points):
    """Indices of the points no other point beats in both cost and error."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], math.inf
    for i in order:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def cost_us(run):
    """CPU time per tick of both loops at p99 (µs): the step plus the slow-loop work
    attributed to the tick; the step alone for summaries without it."""
    cpu = microseconds(dig(run.summary, "timing", "cpu_per_tick_ns", "p99"))
    return cpu if cpu is not None else run.p99_us()


def failure_of(run):
    """Why a run cannot be on a front ('diverged', 'non-finite'), or None."""
    if dig(run.summary, "stability", "diverged") is True:
        return "diverged"
    nonfinite = dig(run.summary, "stability", "nonfinite")
    if isinstance(nonfinite, (int, float)) and nonfinite > 0:
        return "non-finite"
    return None


def pareto_panels(runs):
    """Per scenario and error metric, the runs that can be drawn: [(scenario, metric, points)]
    with points (cost µs, error, run, failure); and the runs left out."""
    panels, left_out = {}, []
    for run in runs:
        metric, value = pareto_error(run)
        cost = cost_us(run)
        if metric is None or cost is None or cost <= 0:
            left_out.append(run)
            continue
        panels.setdefault((run.folder.scenario, metric), []).append(
            (cost, value, run, failure_of(run)))
    return [(scenario, metric, points) for (scenario, metric), points in panels.items()], left_out


def pareto_figure(runs):
    """Error against CPU time per tick, one panel per scenario (errors of different scenarios
    are not comparable), each with its own Pareto front over the runs that stayed stable;
    diverged or non-finite runs are drawn hollow and never on a front.
    Returns (uri, {scenario: front names}, left out, [(run, failure)])."""
    panels, left_out = pareto_panels(runs)
    failed = [(p[2], p[3]) for _, _, points in panels for p in points if p[3]]
    if not panels:
        return None, {}, left_out, failed
    columns = 1 if len(panels) == 1 else 2
    rows = (len(panels) + columns - 1) // columns
    fig = Figure(figsize=(10 if columns == 1 else 12, 4.6 * rows), dpi=DPI)
    axes = fig.subplots(rows, columns, squeeze=False).ravel()
    fronts = {}
    placed = []
    for ax, (scenario, metric, points) in zip(axes, panels):
        scale = 1.0 if metric == "force_err_rms_n" else 1e3
        healthy = [p for p in points if not p[3]]
        xy = [(cost, value * scale) for cost, value, _, _ in healthy]
        front = pareto_front(xy) if xy else []
        fronts.setdefault(scenario, []).extend(healthy[i][2].label for i in front)
        if xy:
            ax.scatter([x for x, _ in xy], [y for _, y in xy], s=22, color="#4a6fa5", zorder=3)
            fx = [xy[i][0] for i in front]
            fy = [xy[i][1] for i in front]
            ax.step(fx, fy, where="post", color="crimson", lw=1.4, zorder=2,
                    label="Pareto front")
            ax.scatter(fx, fy, s=40, facecolors="none", edgecolors="crimson", zorder=4)
        bad = [(cost, value * scale) for cost, value, _, failure in points if failure]
        if bad:
            ax.scatter([x for x, _ in bad], [y for _, y in bad], s=40, facecolors="none",
                       edgecolors="grey", zorder=3, label="diverged or non-finite (not ranked)")
        every = xy + bad
        ax.set_xscale("log")
        sparse_minor_ticks(ax.xaxis, spans_under_two_decades([x for x, _ in every]))
        if all(y > 0 for _, y in every):
            ax.set_yscale("log")
            sparse_minor_ticks(ax.yaxis, spans_under_two_decades([y for _, y in every]))
        ax.margins(x=0.15, y=0.12)
        ax.set_title(scenario, fontsize=10)
        ax.set_xlabel("CPU time per tick, p99 (µs): step + slow loop")
        ax.set_ylabel("force error RMS (N)" if metric == "force_err_rms_n"
                      else "penetration max (mm)")
        ax.grid(True, alpha=0.3, which="both")
        ax.legend(loc="upper right", fontsize=7)
        placed.append((ax, healthy, front, points, scale))
    for ax in axes[len(panels):]:
        ax.set_visible(False)
    fig.suptitle("error against CPU time per tick, per scenario: lower left is better",
                 fontsize=11)
    fig.tight_layout()
    for ax, healthy, front, points, scale in placed:  # labels once the axes have their place
        on_front = {id(healthy[i][2]) for i in front}
        chosen = [p for p in points if len(points) <= MAX_PARETO_LABELS or id(p[2]) in on_front]
        label_points(ax, [((p[0], p[1] * scale), p[2].label, id(p[2]) in on_front)
                          for p in chosen])
    return png_data_uri(fig), fronts, left_out, failed


def label_points(ax, labelled):
    """Writes each (point, text, bold) beside its point, moved up or down until it overlaps
    no label placed before (front points first), with a leader line when moved."""
    size = 7.0
    pixels_per_point = ax.figure.dpi / 72.0
    height = size * 1.25 * pixels_per_point
    area = ax.bbox
    ax.autoscale_view()

    def free(box):
        return all(box[2] <= b[0] or box[0] >= b[2] or box[3] <= b[1] or box[1] >= b[3]
                   for b in placed)

    marker = 3.0 * pixels_per_point
    placed = [(px - marker, py - marker, px + marker, py + marker)
              for px, py in ax.transData.transform([point for point, _, _ in labelled])]
    for (x, y), text, bold in sorted(labelled, key=lambda item: (not item[2], item[0])):
        px, py = ax.transData.transform((x, y))
        width = len(text) * size * 0.6 * pixels_per_point
        left = px + 5 if px + 5 + width <= area.x1 else px - 5 - width
        boxes = [(left, py - height / 2 + step * height, left + width,
                  py + height / 2 + step * height, step)
                 for step in [0] + [s for n in range(1, 15) for s in (n, -n)]]
        box = next((b for b in boxes if free(b)), boxes[0])
        step = box[4]
        placed.append(box[:4])
        offset = ((box[0] - px) / pixels_per_point, (box[1] + height / 2 - py) / pixels_per_point)
        ax.annotate(text, (x, y), textcoords="offset points", xytext=offset, fontsize=size,
                    va="center", ha="left", color="#222", weight="bold" if bold else "normal",
                    arrowprops=dict(arrowstyle="-", color="#999", lw=0.6) if step else None)


def passivity_figure(runs):
    """passivity_energy_min_j per run as bars; (uri, runs shown, runs without the metric)."""
    with_energy = [run for run in runs
                   if finite_number(dig(run.summary, "stability", "passivity_energy_min_j"))]
    without = [run for run in runs if run not in with_energy]
    if not with_energy:
        return None, [], without
    shown = with_energy
    if len(shown) > MAX_PASSIVITY_BARS:
        shown = sorted(shown, key=lambda r: r.summary["stability"]["passivity_energy_min_j"])
        shown = shown[:MAX_PASSIVITY_BARS]
    energies = [run.summary["stability"]["passivity_energy_min_j"] for run in shown]
    diverged = [dig(run.summary, "stability", "diverged") is True for run in shown]
    fig = Figure(figsize=(10, 1.2 + 0.24 * len(shown)))
    ax = fig.subplots()
    positions = np.arange(len(shown))[::-1]
    colours = ["#c62828" if e < 0 else "#2e7d32" for e in energies]
    ax.barh(positions, energies, color=colours, height=0.7)
    for position, energy, is_diverged in zip(positions, energies, diverged):
        text = "%.3g J%s" % (energy, "  diverged" if is_diverged else "")
        ax.annotate(text, (0, position), textcoords="offset points",
                    xytext=(4 if energy >= 0 else -4, -3), fontsize=7,
                    ha="left" if energy >= 0 else "right")
    ax.set_yticks(positions)
    ax.set_yticklabels([run.name for run in shown], fontsize=7)
    nonzero = [abs(e) for e in energies if e != 0]
    linear = min(nonzero) if nonzero else 1e-6
    ax.set_xscale("symlog", linthresh=linear)
    span = max(nonzero) if nonzero else 1e-6
    ax.set_xlim(-span * 30, span * 30)
    ax.axvline(0, color="black", lw=0.8)
    ax.set_xlabel("passivity observer minimum E_min (J), symmetric log scale; below 0 the "
                  "rendering gave energy away")
    ax.grid(True, axis="x", alpha=0.3)
    fig.tight_layout()
    return png_data_uri(fig), shown, without


def integrator_of(run):
    integrator = dig(run.summary, "params", "integrator")
    return integrator if isinstance(integrator, str) else run.label


def coupling_stiffness(folder):
    """(scene, k_t) when the folder is one point of a coupling stiffness sweep, else None.
    The scene is the name without its stiffness; k_t comes from the scenario.json a sweep
    keeps in the run folder, else from the name."""
    for name in (folder.scenario, os.path.basename(os.path.normpath(folder.path))):
        for pattern in STIFFNESS_NAMES:
            match = pattern.match(name)
            if match:
                k = dig(read_json_or_none(os.path.join(folder.path, "scenario.json")) or {},
                        "coupling", "k_t")
                return (match.group("head") + match.group("tail"),
                        float(k) if finite_number(k) else float(match.group("k")))
    return None


def read_json_or_none(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def stiffness_sweeps(folders):
    """Scenes run at several coupling stiffnesses with two or more integrators, each at two
    or more stiffnesses: {scene: {integrator: [(k_t, run)]}}."""
    sweeps = {}
    for folder in folders:
        point = coupling_stiffness(folder)
        if point is None:
            continue
        scene, k = point
        for run in folder.runs:
            sweeps.setdefault(scene, {}).setdefault(integrator_of(run), []).append((k, run))
    return {scene: by_integrator for scene, by_integrator in sweeps.items()
            if len(by_integrator) >= 2
            and all(len({k for k, _ in runs}) >= 2 for runs in by_integrator.values())}


def stiffness_text(k):
    """A stiffness (N/m) as people write it: 5000, 1000000, 2500.5."""
    if not finite_number(k):
        return "none" if k is None else str(k)
    return "%d" % k if float(k).is_integer() else "%g" % k


def stiffness_limits(runs):
    """(largest stable k_t, smallest unstable k_t) by the runs' stability
    verdicts, None where there is none."""
    stable = [k for k, run in runs if verdict_stable(run) is True]
    unstable = [k for k, run in runs if verdict_stable(run) is False]
    return (max(stable) if stable else None), (min(unstable) if unstable else None)


def sweep_figure(by_integrator, closed_form_bound):
    """Largest proxy separation (or the divergence verdict) against k_t, one line per integrator."""
    fig = Figure(figsize=(10, 4.2))
    ax = fig.subplots()
    palette = matplotlib.colormaps["tab10"]
    every_run = [run for runs in by_integrator.values() for _, run in runs]
    separation_of = {id(run): dig(run.summary, "stability", "max_proxy_separation_m")
                     for run in every_run}
    has_separation = all(finite_number(v) and v > 0 for v in separation_of.values())
    # A diverged proxy flies off to 1e150 m: such points sit on the top edge.
    stable_separations = [separation_of[id(run)] for run in every_run
                          if has_separation and dig(run.summary, "stability", "diverged") is False]
    ceiling = max([1.0] + [10 * v for v in stable_separations])
    clipped_any = False
    for i, (integrator, runs) in enumerate(sorted(by_integrator.items())):
        colour = palette(i % 10)
        runs = sorted(runs, key=lambda kr: kr[0])
        ks = [k for k, _ in runs]
        if has_separation:
            y = [min(separation_of[id(run)], ceiling) for _, run in runs]
        else:  # no separation in the summaries: draw the verdict itself
            y = [1.0 if dig(run.summary, "stability", "diverged") else 0.0 for _, run in runs]
        ax.plot(ks, y, color=colour, lw=1.0, alpha=0.6)
        for k, value, (_, run) in zip(ks, y, runs):
            diverged = dig(run.summary, "stability", "diverged") is True
            clipped = has_separation and separation_of[id(run)] > ceiling
            clipped_any |= clipped
            ax.plot([k], [value], ls="none", marker="^" if clipped else "x" if diverged else "o",
                    ms=7 if diverged else 5, color=colour, mfc=colour if diverged else "none")
        largest, _ = stiffness_limits(runs)
        if largest is not None:
            ax.axvline(largest, color=colour, ls=":", lw=1.5)
        ax.plot([], [], color=colour, label="%s (largest stable %s N/m)"
                % (integrator, stiffness_text(largest)))
    if closed_form_bound:
        ax.axvline(closed_form_bound, color="black", ls="--", lw=1.0,
                   label="explicit Euler bound b_t/Δt = %s N/m"
                   % stiffness_text(closed_form_bound))
    ax.plot([], [], ls="none", marker="o", mfc="none", color="grey", label="stable")
    ax.plot([], [], ls="none", marker="x", color="grey", label="diverged")
    if clipped_any:
        ax.plot([], [], ls="none", marker="^", color="grey",
                label="diverged, off scale (> %g m)" % ceiling)
    ax.set_xscale("log")
    sparse_minor_ticks(ax.xaxis)
    if has_separation:
        ax.set_yscale("log")
        sparse_minor_ticks(ax.yaxis)
        ax.set_ylabel("max proxy separation (m)")
    else:
        ax.set_ylabel("diverged (1) or not (0)")
    ax.set_xlabel("coupling stiffness k_t (N/m)")
    ax.grid(True, alpha=0.3, which="both")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    fig.suptitle("stability against coupling stiffness", fontsize=11)
    fig.subplots_adjust(left=0.08, right=0.70, top=0.90, bottom=0.13)
    return png_data_uri(fig)


def sweep_file_verdict(runs):
    """scripts/stability-sweep's stability.json beside the run folders, if there is one."""
    parents = {os.path.dirname(os.path.normpath(run.folder.path)) for _, run in runs}
    if len(parents) != 1:
        return None
    path = os.path.join(parents.pop(), "stability.json")
    data = read_json_or_none(path)
    return (path, data) if isinstance(data, dict) else None


# ---------------------------------------------------------------- page


def esc(value):
    return html.escape(str(value), quote=True)


def fmt(value, pattern="%.3g", scale=1.0):
    if isinstance(value, bool):
        return "yes" if value else "no"
    if not finite_number(value):
        return None
    # A scale below 1 divides by its inverse (1e-3: by 1000.0, exactly), so that
    # 8935 ns prints 8.94 µs as printf("%.2f", ns / 1000.0) does, where
    # 8935 * 1e-3 = 8.934999... would print 8.93.
    scaled = value / (1.0 / scale) if 0 < scale < 1 else value * scale
    return pattern % scaled


def cell(value, pattern="%.3g", scale=1.0, css=""):
    text = fmt(value, pattern, scale)
    if text is None:
        return '<td class="na" title="does not apply to this run">—</td>'
    return '<td%s>%s</td>' % (' class="%s"' % css if css else "", esc(text))


def budget_items(budgets):
    if not budgets:
        return '<td class="na" title="no budgets in the scenario">—</td>', "none"
    items = []
    for budget in budgets:
        passed = budget.get("pass") is True
        relation = "≥" if budget.get("lower_bound") else "≤"
        value = fmt(budget.get("value"), "%.4g")
        text = "%s %s %s %s" % (budget.get("name", "?"), value if value is not None else "n/a",
                                relation, fmt(budget.get("limit"), "%.4g") or "?")
        tip = budget.get("message") or ("within budget" if passed else "over budget")
        items.append('<li class="%s" title="%s">%s %s</li>'
                     % ("pass" if passed else "fail", esc(tip), "✓" if passed else "✗",
                        esc(text)))
    verdict = "pass" if all(b.get("pass") is True for b in budgets) else "fail"
    return '<td class="text"><ul class="budgets">%s</ul></td>' % "".join(items), verdict


# How the summary table shows a metric of a unit: (header unit, format, scale).
UNIT_DISPLAY = {"ns": ("µs", "%.2f", 1e-3), "m": ("mm", "%.3f", 1e3), "N": ("N", "%.4g", 1.0),
                "deg": ("°", "%.3g", 1.0), "J": ("J", "%.3g", 1.0), "N·m": ("N·m", "%.3g", 1.0),
                "ticks": ("ticks", "%d", 1.0)}


def metric_cell(metric, value):
    """One cell of a metric: flags as yes/no, counts of bad ticks and energy given away marked."""
    if metric["unit"] == "flag":
        return ('<td class="%s">%s</td>' % ("fail" if value else "pass", "yes" if value else "no")
                if isinstance(value, bool) else '<td class="na">—</td>')
    _, pattern, scale = UNIT_DISPLAY.get(metric["unit"], ("", "%.4g", 1.0))
    css = ""
    if finite_number(value):
        if metric["unit"] == "ticks" and value > 0:
            css = "fail"
        elif metric["better"] == "higher" and value < 0:
            css = "warn"
    return cell(value, pattern, scale, css=css)


def summary_table(folders, metric_table):
    """One row per scenario and label; the metric columns are the metric table's report
    columns (harness/metrics/metric_table.cpp), so that a metric is added in one place."""
    columns = [m for m in metric_table if m.get("report_column")]
    head = ("<tr><th class='text'>scenario</th><th class='text'>label (algorithm)</th>"
            "<th>ticks</th>"
            + "".join("<th title='%s'>%s (%s)</th>" % (
                esc(m.get("description", "")), esc(m["name"]),
                esc(UNIT_DISPLAY.get(m["unit"], (m["unit"],))[0])) for m in columns)
            + "<th class='text'>pen source</th><th class='text'>budgets</th></tr>")
    rows = []
    for folder in folders:
        for position, run in enumerate(folder.runs):
            s = run.summary
            budgets, verdict = budget_items(s.get("budgets") or [])
            source = dig(s, "accuracy", "penetration_source")
            rows.append(
                '<tr data-scenario="%s" data-label="%s" data-verdict="%s"%s>'
                % (esc(folder.scenario), esc(run.label), verdict,
                   ' class="scenario-first"' if position == 0 else "")
                + '<td class="text"><a href="#%s">%s</a></td>' % (folder.slug, esc(folder.scenario))
                + '<td class="text">%s <span class="small">(%s)</span></td>'
                % (esc(run.label), esc(s.get("algorithm", "?")))
                + cell(dig(s, "timing", "ticks"), "%d")
                + "".join(metric_cell(m, at_pointer(s, m["pointer"])) for m in columns)
                + ('<td class="text">%s</td>' % esc(source) if source
                   else '<td class="na">—</td>')
                + budgets + "</tr>")
    return ('<div class="wide"><table class="summary" id="summary-table"><thead>%s</thead>'
            "<tbody>%s</tbody></table></div>" % (head, "".join(rows)))


def figure_html(identifier, uri, alt, caption):
    return ('<figure><img id="%s" alt="%s" src="%s"><figcaption>%s</figcaption></figure>'
            % (identifier, esc(alt), uri, caption))


def note(text):
    return '<p class="note">%s</p>' % text


def context_html(folders):
    keys = ("commit", "build_type", "compiler", "cpu")
    contexts = {}
    for folder in folders:
        context = folder.summary.get("context") or {}
        contexts.setdefault(tuple(str(context.get(k, "?")) for k in keys), []).append(folder)
    dates = sorted(str(dig(f.summary, "context", "date")) for f in folders
                   if dig(f.summary, "context", "date"))
    date = ("" if not dates else dates[0] if dates[0] == dates[-1]
            else "%s … %s" % (dates[0], dates[-1]))
    parts = []
    if len(contexts) == 1:
        values = next(iter(contexts))
        items = "".join("<dt>%s</dt><dd class='mono'>%s</dd>" % (esc(k), esc(v))
                        for k, v in zip(keys, values))
        parts.append('<dl class="context">%s<dt>date</dt><dd class="mono">%s</dd></dl>'
                     % (items, esc(date or "?")))
    else:
        rows = "".join("<tr>%s<td class='text'>%s</td></tr>"
                       % ("".join("<td class='text mono'>%s</td>" % esc(v) for v in values),
                          esc(", ".join(f.scenario for f in members)))
                       for values, members in contexts.items())
        parts.append(note("The runs come from %d different builds or machines: compare their "
                          "timings with care." % len(contexts)))
        parts.append("<table><tr>%s<th class='text'>scenarios</th></tr>%s</table>"
                     % ("".join("<th class='text'>%s</th>" % k for k in keys), rows))
        parts.append('<dl class="context"><dt>date</dt><dd class="mono">%s</dd></dl>'
                     % esc(date or "?"))
    return "".join(parts)


def folders_html(folders):
    items = []
    for folder in folders:
        with_ticks = sum(run.ticks is not None for run in folder.runs)
        items.append("<li><code>%s</code> — %s, %d run%s%s</li>"
                     % (esc(folder.path), esc(folder.scenario), len(folder.runs),
                        "" if len(folder.runs) == 1 else "s",
                        "" if with_ticks == len(folder.runs)
                        else " (%d without ticks CSV)" % (len(folder.runs) - with_ticks)))
    return "<ul>%s</ul>" % "".join(items)


def scenario_section(folder):
    runs = folder.runs
    s = folder.summary.get("scenario") or {}
    parts = ['<section class="scenario" id="%s"><h3>%s</h3>'
             % (folder.slug, esc(folder.scenario))]
    facts = ["run folder <code>%s</code>" % esc(folder.path)]
    if s.get("path"):
        facts.append("scenario <code>%s</code>" % esc(s["path"]))
    if s.get("trace"):
        facts.append("trace: %s" % esc(s["trace"]))
    if s.get("hash"):
        facts.append("hash <code>%s</code>" % esc(s["hash"]))
    parts.append('<p class="small">%s</p>' % "; ".join(facts))
    missing = [run for run in runs if run.ticks is None]
    if missing:
        parts.append(note("No ticks CSV for %s (a summary-only run folder): no time series for "
                          "%s." % (", ".join("<code>%s</code>" % esc(os.path.basename(r.ticks_path))
                                             for r in missing),
                                   "this scenario" if len(missing) == len(runs)
                                   else "these labels")))
    if len(missing) < len(runs):
        uri, has_reference = wrench_figure(runs, "force")
        parts.append(figure_html(
            "fig-force-" + folder.slug, uri, "force against time, " + folder.scenario,
            "Displayed force (world frame) per label"
            + (", dashed: the analytic reference (ideal rigid contact)." if has_reference
               else "; no analytic reference for this scene.")))
        uri, has_reference = wrench_figure(runs, "torque")
        parts.append(figure_html(
            "fig-torque-" + folder.slug, uri, "torque against time, " + folder.scenario,
            "Displayed torque about the tool frame's origin (world frame)"
            + (", dashed: the analytic reference." if has_reference
               else "; no analytic reference for this scene.")))
        uri = penetration_figure(runs)
        if uri:
            parts.append(figure_html(
                "fig-penetration-" + folder.slug, uri, "penetration against time, "
                + folder.scenario, "Penetration of the proxy's tool: <code>penetration_m</code> "
                "(analytic, else the primary oracle), and where present each oracle backend's own "
                "column <code>&lt;backend&gt;_pen_m</code> (in the order of the summary's "
                "<code>oracle_backends</code>: dotted, crosses, dash-dot; an exact backend on "
                "every N-th tick only)."))
        else:
            parts.append(note("No penetration ground truth in this scenario (no analytic "
                              "reference, oracle off or distance-only scene)."))
    uri = timing_figure(runs)
    if uri:
        from_sample = [r for r in runs if r.ticks is None and r.step_us()[0] is not None]
        parts.append(figure_html(
            "fig-timing-" + folder.slug, uri, "step time distribution, " + folder.scenario,
            "Time of <code>Renderer::step</code> per tick: histogram (log x) and cumulative "
            "distribution, dashed red: the 1 ms budget, dotted / dots: each label's p99 from "
            "the summary." + (" Labels without ticks use the summary's evenly spaced sample of "
                              "step times." if from_sample else "")))
    else:
        parts.append(note("No step times in this run folder (no ticks CSV and no sample in the "
                          "summary)."))
    parts.append(metric_table_html(folder))
    parts.append(work_counters_html(folder))
    parts.append("</section>")
    return "".join(parts)


def at_pointer(mapping, pointer):
    """The value at a JSON pointer ("/timing/step_ns/p99"), or None."""
    node = mapping
    for key in pointer.strip("/").split("/"):
        if not isinstance(node, dict) or key not in node:
            return None
        node = node[key]
    return node


def metric_table_html(folder):
    """Every metric of the summary's metric_table (the code's one table of metrics), one row
    per metric and one column per label; '' for summaries written before the table."""
    table = folder.summary.get("metric_table")
    if not isinstance(table, list) or not table:
        return ""
    head = "<tr><th class='text'>metric</th><th class='text'>unit</th>" + "".join(
        "<th>%s</th>" % esc(run.label) for run in folder.runs) + "</tr>"
    rows = []
    for metric in table:
        pointer = metric.get("pointer", "")
        cells = []
        for run in folder.runs:
            value = at_pointer(run.summary, pointer)
            if isinstance(value, bool):
                cells.append('<td class="%s">%s</td>' % ("fail" if value else "pass",
                                                          "yes" if value else "no"))
            else:
                cells.append(cell(value, "%.4g"))
        rows.append("<tr><td class='text' title='%s'><code>%s</code></td><td class='text'>%s</td>"
                    % (esc(metric.get("description", "")), esc(metric.get("name", "")),
                       esc(metric.get("unit", ""))) + "".join(cells) + "</tr>")
    return ("<details><summary>All metrics of the metric table</summary>"
            '<div class="wide"><table class="summary" id="metrics-%s"><thead>%s</thead>'
            "<tbody>%s</tbody></table></div></details>" % (folder.slug, head, "".join(rows)))


def work_counters_html(folder):
    """The algorithms' own work counters (contacts.work: CCD tests, kernel calls, budget
    hits, points looked up ...), totals over the run, one row per counter name and one
    column per label; '' when no run counts anything."""
    works = [dig(run.summary, "contacts", "work") or {} for run in folder.runs]
    names = sorted({name for work in works for name in work})
    if not names:
        return ""
    head = "<tr><th class='text'>counter</th>" + "".join(
        "<th>%s</th>" % esc(run.label) for run in folder.runs) + "</tr>"
    rows = ["<tr><td class='text'><code>%s</code></td>%s</tr>"
            % (esc(name), "".join(cell(work.get(name), "%.0f") for work in works))
            for name in names]
    return ("<details><summary>Work counters (totals over the run)</summary>"
            '<div class="wide"><table class="summary" id="work-%s"><thead>%s</thead>'
            "<tbody>%s</tbody></table></div></details>" % (folder.slug, head, "".join(rows)))


def stability_html(folders, runs):
    parts = []
    uri, shown, without = passivity_figure(runs)
    if uri:
        parts.append(figure_html(
            "fig-passivity", uri, "passivity energy minimum per run",
            "Minimum over time of the passivity observer E = Σ (F·v + τ·ω) Δt at the device "
            "port, per run (red: below zero; diverged runs are marked)."
            + (" The %d lowest of %d runs are shown." % (len(shown), len(runs) - len(without))
               if len(shown) < len(runs) - len(without) else "")))
    if without:
        parts.append(note("No passivity energy for %s."
                          % ", ".join(esc(r.name) for r in without)))
    for index, (base, by_integrator) in enumerate(sorted(stiffness_sweeps(folders).items())):
        all_runs = [kr for runs in by_integrator.values() for kr in runs]
        from_file = sweep_file_verdict(all_runs)
        bound = dig(from_file[1], "explicit_bound_closed_form_n_per_m") if from_file else None
        parts.append("<h3>Coupling stiffness sweep: %s</h3>" % esc(base))
        rows = []
        for integrator, integrator_runs in sorted(by_integrator.items()):
            largest, smallest = stiffness_limits(integrator_runs)
            ks = sorted({k for k, _ in integrator_runs})
            rows.append(
                '<tr data-integrator="%s"><td class="text">%s</td><td>%d (%s … %s)</td>'
                '<td class="largest-stable">%s</td><td class="smallest-unstable">%s</td></tr>'
                % (esc(integrator), esc(integrator), len(ks), stiffness_text(ks[0]),
                   stiffness_text(ks[-1]), stiffness_text(largest), stiffness_text(smallest)))
        parts.append(
            '<table class="stiffness-sweep" data-sweep="%s"><tr><th class="text">integrator</th>'
            "<th>stiffnesses run (N/m)</th><th>largest stable k_t (N/m)</th>"
            "<th>smallest unstable k_t (N/m)</th></tr>%s</table>" % (esc(base), "".join(rows)))
        parts.append('<p class="small">Stable: the run\'s stability verdict '
                     "(<code>stability.verdict.stable</code> in its summary).</p>")
        if from_file:
            path, data = from_file
            verdicts = "; ".join(
                "%s largest stable %s N/m, smallest unstable %s N/m"
                % (esc(name), stiffness_text(dig(data, name, "largest_stable_n_per_m")),
                   stiffness_text(dig(data, name, "smallest_unstable_n_per_m")))
                for name in sorted(by_integrator) if isinstance(data.get(name), dict))
            if verdicts:
                parts.append(note("<code>%s</code> (written by scripts/stability-sweep, which also "
                                  "counts growth of the proxy's separation beyond the exciting "
                                  "jump as unstable): %s." % (esc(path), verdicts)))
        parts.append(figure_html(
            "fig-stiffness-sweep-%d" % index, sweep_figure(by_integrator, bound),
            "stability against coupling stiffness, " + base,
            "Largest proxy separation from the device per run against the coupling stiffness "
            "(crosses: diverged); dotted: each integrator's largest stable k_t."))
    return "".join(parts)


def is_stress_folder(folder):
    """A run of a scenario kept in a folder named stress (scenarios/stress/)."""
    path = str(dig(folder.summary, "scenario", "path") or "")
    return os.path.basename(os.path.dirname(path)) == "stress"


def stress_verdict(run):
    """(passed, text) from the run's stability verdict, which hapticbench
    computes (summary.json stability.verdict; harness/stability/
    stability_verdict.h): the first failed check with its figure, or the
    figure behind a pass. (None, "no verdict") for a summary without one."""
    verdict = dig(run.summary, "stability", "verdict")
    if not isinstance(verdict, dict) or not isinstance(verdict.get("stable"), bool):
        return None, "no verdict"
    return verdict["stable"], str(verdict.get("reason") or "")


def verdict_stable(run):
    """True or False from the run's stability verdict; None without one."""
    stable = dig(run.summary, "stability", "verdict", "stable")
    return stable if isinstance(stable, bool) else None


def stress_matrix_html(folders):
    """Algorithm label × stress scenario, each cell pass/fail with its figure."""
    stress = [f for f in folders if is_stress_folder(f)]
    if not stress:
        return ""
    labels = []
    for folder in stress:
        for run in folder.runs:
            if run.label not in labels:
                labels.append(run.label)
    header = "".join('<th class="text">%s</th>' % esc(f.scenario) for f in stress)
    rows = []
    failures = 0
    for label in labels:
        cells = []
        for folder in stress:
            run = next((r for r in folder.runs if r.label == label), None)
            if run is None:
                cells.append('<td class="na">—</td>')
                continue
            passed, text = stress_verdict(run)
            if passed is None:
                cells.append('<td class="na">%s</td>' % esc(text))
                continue
            failures += not passed
            cells.append('<td class="%s" data-pass="%s">%s %s</td>'
                         % ("pass" if passed else "fail", "true" if passed else "false",
                            "✓" if passed else "✗", esc(text)))
        rows.append('<tr><td class="text">%s</td>%s</tr>' % (esc(label), "".join(cells)))
    return ("<h3 id='stress-matrix'>Stress matrix</h3>"
            + note("Each run of a scenario in a <code>stress/</code> folder, by algorithm label: "
                   "the run's stability verdict (<code>stability.verdict</code>, the same that "
                   "<code>hapticbench stability</code> applies). A cell fails on the first of: "
                   "a non-finite wrench, divergence, tunnelling, an energy minimum below −ε, "
                   "chatter at the end of the run or a limit cycle; a passing cell shows the "
                   "largest penetration. %d of the cells fail." % failures)
            + '<div class="wide"><table class="stress-matrix"><tr><th class="text">label</th>%s'
              "</tr>%s</table></div>" % (header, "".join(rows)))


def scene_friction(folder):
    """The largest Coulomb μ of the scenario's scene objects (0 when absent)."""
    values = [number_or_none(v) for v in dig(folder.summary, "scenario", "scene_friction") or []]
    return max([v for v in values if v is not None] or [0.0])


def friction_html(folders):
    """What friction changes: every run of a scenario whose scene has μ > 0,
    whether its algorithm renders friction, its force error against the
    analytic reference (which has the friction) and its penetration."""
    rough = [(f, scene_friction(f)) for f in folders if scene_friction(f) > 0]
    if not rough:
        return ""
    rows = []
    for folder, mu in rough:
        for run in folder.runs:
            # The algorithm's registry entry says whether it renders friction.
            renders = run.summary.get("renders_friction") is True
            error = number_or_none(dig(run.summary, "accuracy", "force_err_rms_n"))
            depth = number_or_none(dig(run.summary, "accuracy", "penetration_max_m"))
            rows.append('<tr><td class="text">%s</td><td>%s</td><td class="text">%s</td>'
                        '<td class="text" data-friction="%s">%s</td>%s%s</tr>'
                        % (esc(folder.scenario), fmt(mu, "%.2g"), esc(run.label),
                           "true" if renders else "false",
                           "Coulomb μ" if renders else "frictionless",
                           cell(error, "%.3g"), cell(depth, "%.3g", 1e3)))
    return ("<h3 id='friction'>Friction</h3>"
            + note("Runs of scenarios whose scene has Coulomb friction (scene objects' "
                   "<code>friction</code>). Whether an algorithm renders it is its registry entry's "
                   "word (<code>renders_friction</code> in the summary); the difference between "
                   "the two groups is what friction changes. Force error is against the analytic reference or, on meshes, the mesh "
                   "force reference; both stick and slide with the scene's μ.")
            + '<table><tr><th class="text">scenario</th><th>μ</th><th class="text">label</th>'
              '<th class="text">contacts</th><th>force error RMS (N)</th>'
              "<th>penetration max (mm)</th></tr>%s</table>" % "".join(rows))


def read_stability_result(path):
    """A stability.json as `hapticbench stability` writes it."""
    data = read_json_object(path)
    for key in ("scenario", "label", "param"):
        if not isinstance(data.get(key), str):
            raise ReportInputError(path, "/" + key, "expected a string")
    if not isinstance(data.get("runs"), list):
        raise ReportInputError(path, "/runs", "expected an array of runs")
    return data


def margin_quantity(param):
    """What a parameter pointer varies, for the margin table's columns."""
    name = param.rstrip("/").split("/")[-1]
    if param == "/coupling/k_t":
        return "coupling stiffness k_t (N/m)"
    if name in ("contact_stiffness", "point_stiffness"):
        return "contact stiffness (N/m)"
    return name


def margin_value_html(value, bound, data):
    if value is None:
        low = dig(data, "range")
        return ("none ≥ %s" % fmt(low[0])
                if isinstance(low, list) and low and finite_number(low[0]) else "none")
    text = fmt(value, "%.4g")
    return text + (" (the range's top)" if bound is None else "")


def unstable_because(data, smallest):
    """Why the run at the smallest unstable value was unstable: ' (diverged,
    passivity, chatter, display passivity, limit cycle)', or ''."""
    run = next((r for r in data["runs"] if isinstance(r, dict) and r.get("value") == smallest
                and r.get("stable") is False), None)
    if run is None:
        return ""
    reasons = [why for why, failed in (
        ("diverged", run.get("diverged")),
        ("non-finite", (run.get("nonfinite") or 0) > 0),
        ("passivity %s mJ" % fmt(run.get("passivity_energy_min_j"), "%.3g", 1e3),
         number_or_none(run.get("passivity_energy_min_j")) is not None
         and run["passivity_energy_min_j"] < -(number_or_none(data.get("epsilon_j")) or 0)),
        ("chatter", run.get("chatters")),
        ("display passivity %s mJ" % fmt(run.get("display_energy_min_j"), "%.3g", 1e3),
         number_or_none(run.get("display_energy_min_j")) is not None
         and run["display_energy_min_j"] < -(number_or_none(data.get("epsilon_j")) or 0)),
        ("limit cycle", run.get("limit_cycle"))) if failed]
    return " (%s)" % ", ".join(reasons) if reasons else ""


def stability_margins_html(results):
    """The stability-margin table: largest stable value per scenario, label
    and parameter, from the stability.json files given."""
    if not results:
        return ""
    quantities = []
    for _, data in results:
        q = margin_quantity(data["param"])
        if q not in quantities:
            quantities.append(q)
    table = {}
    for path, data in results:
        key = (data["scenario"], data["label"])
        table.setdefault(key, {})[margin_quantity(data["param"])] = (path, data)
    rows = []
    for (scenario, label), by_quantity in table.items():
        cells = []
        for q in quantities:
            entry = by_quantity.get(q)
            if entry is None:
                cells.append('<td class="na">—</td>')
                continue
            path, data = entry
            largest = number_or_none(data.get("largest_stable"))
            smallest = number_or_none(data.get("smallest_unstable"))
            unstable = ('<br><span class="small">unstable at %s%s</span>'
                        % (esc(fmt(smallest, "%.4g")), esc(unstable_because(data, smallest)))
                        if smallest is not None else "")
            cells.append('<td title="%s; %d runs">%s%s</td>'
                         % (esc(path), len(data["runs"]),
                            esc(margin_value_html(largest, smallest, data)), unstable))
        first = next(iter(by_quantity.values()))[1]
        algorithm = first.get("algorithm") if isinstance(first.get("algorithm"), str) else ""
        integrator = first.get("integrator") if isinstance(first.get("integrator"), str) else ""
        rows.append('<tr><td class="text">%s</td><td class="text">%s</td><td class="text">%s</td>'
                    '<td class="text">%s</td>%s</tr>'
                    % (esc(scenario), esc(label), esc(algorithm or "—"),
                       esc(integrator or "—"), "".join(cells)))
    criteria = sorted({str(data.get("criterion", "")) for _, data in results})
    return ("<h3 id='stability-margins'>Stability margins</h3>"
            + note("Largest stable value found by <code>hapticbench stability</code> "
                   "(bracketing, then bisection on a log scale), and the smallest unstable value "
                   "with what made it unstable (hover a cell for the file). “the range's top”: no unstable value in the "
                   "range searched; “none ≥ x”: unstable already at the range's bottom. "
                   "Criterion: %s" % esc(" / ".join(criteria)))
            + '<table class="stability-margins"><tr><th class="text">scenario</th>'
              '<th class="text">label</th><th class="text">algorithm</th>'
              '<th class="text">integrator</th>%s</tr>%s</table>'
            % ("".join("<th>%s</th>" % esc(q) for q in quantities), "".join(rows)))


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


def zwidth_figure(scenario, results):
    """One scenario's Z-width map: per algorithm label, the largest stable
    value of the y field against the x field, the band up to the smallest
    unstable value shaded; below the line is stable."""
    fig = Figure(figsize=(8, 4.2))
    ax = fig.subplots()
    palette = matplotlib.colormaps["tab10"]
    for i, (_, data) in enumerate(sorted(results, key=lambda r: r[1]["label"])):
        colour = palette(i % 10)
        points = sorted(data["points"], key=lambda p: p["x"])
        xs = [p["x"] for p in points if p.get("largest_stable") is not None]
        stable = [p["largest_stable"] for p in points if p.get("largest_stable") is not None]
        ax.plot(xs, stable, color=colour, marker="o", ms=4, label=data["label"])
        band = [(p["x"], p["largest_stable"], p["smallest_unstable"]) for p in points
                if p.get("largest_stable") is not None and p.get("smallest_unstable") is not None]
        if band:
            ax.fill_between([b[0] for b in band], [b[1] for b in band], [b[2] for b in band],
                            color=colour, alpha=0.25, lw=0)
        top = [p["x"] for p in points if p.get("smallest_unstable") is None]
        if top:
            range_top = dig(data, "y_range")
            if isinstance(range_top, list) and len(range_top) == 2 and finite_number(range_top[1]):
                ax.plot(top, [range_top[1]] * len(top), ls="none", marker="^", color=colour)
    first = results[0][1]
    values = [p[key] for _, d in results for p in d["points"]
              for key in ("largest_stable", "smallest_unstable") if p.get(key)]
    if values and max(values) > 10 * min(values):  # a decade or more: log scale
        ax.set_yscale("log")
        sparse_minor_ticks(ax.yaxis)
    ax.set_xlabel(first["x_param"])
    ax.set_ylabel("largest stable " + first["y_param"])
    ax.grid(True, alpha=0.3, which="both")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    fig.suptitle("Z-width: %s" % scenario, fontsize=11)
    fig.subplots_adjust(left=0.11, right=0.75, top=0.90, bottom=0.13)
    return png_data_uri(fig)


def zwidth_html(results):
    """One Z-width figure per scenario from the zwidth.json files given."""
    if not results:
        return ""
    by_scenario = {}
    for path, data in results:
        by_scenario.setdefault(data["scenario"], []).append((path, data))
    parts = ["<h3 id='zwidth'>Z-width</h3>",
             note("The stable region over two parameters (Colgate & Brown 1994), found by "
                  "<code>hapticbench zwidth</code>: for each value on the x axis, the largest "
                  "stable value (the line; stable below it) and the smallest unstable one (the "
                  "band's top). ▲: stable up to the range's top. Criterion: %s"
                  % esc(" / ".join(sorted({str(d.get("criterion", "")) for _, d in results}))))]
    for scenario, scenario_results in by_scenario.items():
        uri = zwidth_figure(scenario, scenario_results)
        parts.append(figure_html(
            "fig-zwidth-" + re.sub(r"[^A-Za-z0-9_-]+", "-", scenario), uri,
            "Z-width of %s" % scenario,
            "%s: %s" % (esc(scenario), esc(", ".join(
                "%s (%s)" % (d["label"], os.path.basename(os.path.dirname(p)) or p)
                for p, d in scenario_results)))))
    return "".join(parts)


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


def render(folders, template, metric_table, stability_results=(), progress=Progress(),
           zwidth_results=()):
    slugs = set()
    for folder in folders:
        slug = "scenario-" + re.sub(r"[^A-Za-z0-9_-]+", "-", folder.scenario)
        candidate, n = slug, 2
        while candidate in slugs:
            candidate, n = "%s-%d" % (slug, n), n + 1
        slugs.add(candidate)
        folder.slug = candidate
    runs = [run for folder in folders for run in folder.runs]
    failed = [run for run in runs if any(b.get("pass") is not True
                                         for b in run.summary.get("budgets") or [])]
    body = ["<header><h1>hapticbench report</h1>",
            '<p class="small">%d scenario%s, %d run%s; generated %s.</p>'
            % (len(folders), "" if len(folders) == 1 else "s", len(runs),
               "" if len(runs) == 1 else "s",
               datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")),
            context_html(folders),
            "<details%s><summary>Run folders covered (%d)</summary>%s</details></header>"
            % (" open" if len(folders) <= 12 else "", len(folders), folders_html(folders))]
    body.append("<nav><h2>Contents</h2><ul><li><a href='#summary'>Summary</a></li>"
                "<li><a href='#pareto'>Error against CPU time per tick</a></li>"
                "<li><a href='#stability'>Stability</a></li>%s</ul></nav>"
                % "".join("<li><a href='#%s'>%s</a></li>" % (f.slug, esc(f.scenario))
                          for f in folders))
    body.append('<section id="summary"><h2>Summary</h2>')
    body.append('<p class="%s">%s</p>' % (
        "fail" if failed else "pass",
        "%d of %d runs failed a budget: %s." % (len(failed), len(runs),
                                                ", ".join(esc(r.name) for r in failed))
        if failed else "All %d runs are within their budgets." % len(runs)))
    body.append(summary_table(folders, metric_table))
    body.append('<p class="small">Columns come from the metric table '
                "(<code>hapticbench list --metrics</code>; hover a header for its definition). "
                "Step times are of <code>Renderer::step</code> only; CPU per tick adds the "
                "slow-loop work attributed to the tick. Force and direction errors are against "
                "the analytic reference (ideal rigid contact); penetration comes from the "
                "analytic reference, else the Embree oracle. "
                "— : the metric does not apply to the run.</p></section>")
    body.append('<section id="pareto"><h2>Error against CPU time per tick</h2>')
    progress.step("drawing the summary figures")
    uri, fronts, left_out, failed = pareto_figure(runs)
    if uri:
        on_front = "; ".join("%s: %s" % (scenario, ", ".join(labels))
                             for scenario, labels in fronts.items())
        body.append(figure_html(
            "fig-pareto", uri, "error against CPU time per tick p99, one panel per scenario",
            "One panel per scenario (errors of different scenarios are not comparable): force "
            "error RMS against the reference (the analytic one, else the mesh force "
            "reference, both with the scene's Coulomb friction; without either, the maximum penetration) against the p99 CPU time per tick of both loops, the haptic step "
            "plus the slow-loop work attributed to the tick (timing.cpu_per_tick_ns), so that "
            "an algorithm whose work sits in its slow loop is not shown as free. The red line "
            "is each scenario's Pareto front: no other run of that scenario is both cheaper "
            "and more accurate. On the fronts: %s." % esc(on_front)))
    if failed:
        body.append(note("Drawn hollow and never on a front, because their error says nothing "
                         "about the algorithm's accuracy: %s." % esc(", ".join(
                             "%s (%s)" % (run.name, why) for run, why in failed))))
    if left_out:
        body.append(note("Not on the figure (no force error, no penetration or no step time): "
                         "%s." % esc(", ".join(r.name for r in left_out))))
    body.append('</section><section id="stability"><h2>Stability</h2>')
    body.append(stress_matrix_html(folders))
    body.append(stability_margins_html(list(stability_results)))
    body.append(zwidth_html(list(zwidth_results)))
    body.append(stability_html(folders, runs))
    body.append(friction_html(folders))
    body.append("</section><section id='scenarios'><h2>Scenarios</h2>")
    for done, folder in enumerate(folders):
        progress.step("drawing the scenarios' figures", done, len(folders), "scenarios")
        body.append(scenario_section(folder))
    body.append("</section>")
    return string.Template(template).substitute(title="hapticbench report", body="\n".join(body))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, help="HTML file to write")
    parser.add_argument("--template", default=os.path.join(os.path.dirname(
        os.path.abspath(__file__)), "report_template.html"))
    parser.add_argument("--metric-table", help="the metric table as JSON (hapticbench report "
                        "passes it); else the one the first summary carries")
    parser.add_argument("--stability", action="append", default=[],
                        help="a stability.json of `hapticbench stability` (repeatable): a row "
                        "of the stability-margin table")
    parser.add_argument("--zwidth", action="append", default=[],
                        help="a zwidth.json of `hapticbench zwidth` (repeatable): drawn in the "
                        "scenario's Z-width figure")
    parser.add_argument("--progress-fd", type=int, help="file descriptor for progress lines "
                        "(hapticbench report passes it; see Progress)")
    parser.add_argument("folders", nargs="*", help="run folders (each with a summary.json)")
    args = parser.parse_args()
    progress = Progress(args.progress_fd)
    try:
        folders = []
        for done, path in enumerate(args.folders):
            progress.step("reading run folders", done, len(args.folders), "folders")
            folders.append(load_run_folder(path))
        metric_table = []
        if args.metric_table:
            with open(args.metric_table, encoding="utf-8") as f:
                metric_table = json.load(f)
        else:
            metric_table = next((f.summary["metric_table"] for f in folders
                                 if isinstance(f.summary.get("metric_table"), list)), [])
        with open(args.template, encoding="utf-8") as f:
            template = f.read()
        stability_results = [(path, read_stability_result(path)) for path in args.stability]
        zwidth_results = [(path, read_zwidth_result(path)) for path in args.zwidth]
        page = render(folders, template, metric_table, stability_results, progress,
                      zwidth_results)
    except ReportInputError as error:
        print("error: %s" % error, file=sys.stderr)
        return 2
    except Exception as error:  # a bug, not bad input: one line, no traceback
        if os.environ.get("HAPTICBENCH_DEBUG"):
            raise
        print("internal error: rendering failed: %s: %s (HAPTICBENCH_DEBUG=1 shows where)"
              % (type(error).__name__, error), file=sys.stderr)
        return 3
    try:
        with open(args.out, "w", encoding="utf-8") as f:
            f.write(page)
    except OSError as error:
        print("error: %s: cannot write the report: %s" % (args.out, error.strerror or error),
              file=sys.stderr)
        return 2
    return 0


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


if __name__ == "__main__":
    sys.exit(main())
