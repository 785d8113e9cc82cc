"""The report's figures, each an inline PNG: the scene with the device's
path, in closed loop the device against the operator's intent, force,
torque and penetration against time, step times, the error-against-cost
Pareto panels (a sweep's jobs in one panel per scenario), passivity, the
coupling-stiffness sweeps and the Z-width maps. Every figure draws a label
in the same colour."""
import base64
import io
import json
import math
import os

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter, NullLocator  # noqa: E402

from .history import METRICS as HISTORY_METRICS  # noqa: E402
from .inputs import (  # noqa: E402
    BACKEND_PEN_SUFFIX, REFERENCE_NAMES, dig, finite_number, headline, is_baseline, microseconds,
    reference_kind)
from .sweeps import (  # noqa: E402
    is_numeric_key, key_name, spans_more_than_a_decade, sweep_at, sweep_job, value_text)


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


# How the backends' columns are drawn, in the order summary.json lists them.
BACKEND_STYLES = [dict(ls=":"), dict(ls="none", marker="x"), dict(ls="-."), dict(ls="--")]


# The grid key of a coupling stiffness sweep (a JSON pointer into the scenario).
COUPLING_STIFFNESS_KEY = "/coupling/k_t"


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


class LabelColours:
    """One colour per algorithm label across every figure of the page: tab10, then the
    lighter tab20 shades, given in the order the labels are first met."""

    def __init__(self):
        tab20 = matplotlib.colormaps["tab20"]
        self.palette = ([matplotlib.colormaps["tab10"](i) for i in range(10)]
                        + [tab20(i) for i in range(1, 20, 2)])
        self.colours = {}

    def reset(self, labels=()):
        self.colours = {}
        for label in labels:
            self.colour(label)

    def colour(self, label):
        if label not in self.colours:
            self.colours[label] = self.palette[len(self.colours) % len(self.palette)]
        return self.colours[label]

    def hex(self, label):
        return matplotlib.colors.to_hex(self.colour(label))


LABEL_COLOURS = LabelColours()


def run_colours(runs):
    return {id(run): LABEL_COLOURS.colour(run.label) for run in runs}


# Units of the parameters a sweep, a stability search or a Z-width map varies,
# by the pointer's last component (docs/scenario-format.md, docs/algorithms/README.md).
PARAMETER_UNITS = {"k_t": "N/m", "b_t": "N·s/m", "k_r": "N·m/rad", "b_r": "N·m·s/rad",
                   "contact_stiffness": "N/m", "point_stiffness": "N/m",
                   "contact_damping": "N·s/m", "proxy_mass_kg": "kg", "voxel_size": "m",
                   "pointshell_spacing": "m", "standoff": "m", "contact_distance": "m",
                   "duration_s": "s", "max_force_n": "N", "max_torque_nm": "N·m"}


COUPLING_NAMES = {"k_t": "coupling stiffness", "b_t": "coupling damping",
                  "k_r": "rotational coupling stiffness", "b_r": "rotational coupling damping"}


def parameter_label(pointer):
    """An axis or column title for a parameter: "coupling damping b_t (N·s/m)",
    "contact_stiffness (N/m)"."""
    name = key_name(pointer)
    text = ("%s %s" % (COUPLING_NAMES[name], name) if pointer.startswith("/coupling/")
            and name in COUPLING_NAMES else name)
    unit = PARAMETER_UNITS.get(name)
    return "%s (%s)" % (text, unit) if unit else text


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
        style = (dict(color="black", lw=1.0, ls="--", label=reference_name(run))
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
    return png_data_uri(fig), (reference_name(references[0]) if references else None)


def reference_name(run):
    """"mesh force reference" or "analytic reference": what the ticks' ref_* columns hold."""
    return REFERENCE_NAMES.get(reference_kind(run), "the reference")[len("the "):]


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
    force = headline(run.summary)
    if finite_number(force):
        return "force_err_rms_n", force
    penetration = headline(run.summary, "accuracy_fallback")
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


# Markers that tell the labels of one sweep panel apart (colour shows the swept value).
LABEL_MARKERS = ["o", "s", "^", "D", "v", "P", "X", "*", "<", ">"]


def panel_title(run):
    """A sweep's jobs share one panel per base scenario; any other run has its scenario's."""
    job = sweep_job(run.folder)
    return job.group if job else run.folder.scenario


def pareto_panels(runs):
    """Per scenario (a sweep: per base scenario) and error metric, the runs that can be
    drawn: [(title, metric, points)] with points (cost µs, error, run, failure), a sweep's
    in numeric order of its grid values; and the runs left out."""
    panels, left_out = {}, []
    for run in runs:
        metric, value = pareto_error(run)
        cost = cost_us(run)
        if metric is None or cost is None or cost <= 0:
            left_out.append(run)
            continue
        panels.setdefault((panel_title(run), metric), []).append(
            (cost, value, run, failure_of(run)))
    return [(title, metric, sorted(points, key=point_order(points)))
            for (title, metric), points in panels.items()], left_out


def point_order(points):
    """Sort key of a panel's points: label in order of appearance, then a sweep job's grid
    values in numeric order; other points keep their order."""
    labels = list(dict.fromkeys(p[2].label for p in points))

    def key(point):
        job = sweep_job(point[2].folder)
        return (labels.index(point[2].label), job.sort_key() if job else ())
    return key


def point_name(run):
    """A run as the page names a point: its label, with a sweep job's grid values."""
    job = sweep_job(run.folder)
    return "%s (%s)" % (run.label, job.describe()) if job else run.label


def pareto_figure(runs):
    """Error against CPU time per tick, one panel per scenario (errors of different scenarios
    are not comparable; a sweep's jobs share their base scenario's panel, coloured by the
    swept value), each with its own Pareto front over the runs that stayed stable and render
    contact; diverged or non-finite runs are drawn hollow, baselines that render no contact
    grey, and neither is ever on a front.
    Returns (uri, {panel title: front names}, left out, [(run, failure)])."""
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
    for ax, (title, metric, points) in zip(axes, panels):
        scale = 1.0 if metric == "force_err_rms_n" else 1e3
        ranked = [p for p in points if not p[3] and not is_baseline(p[2])]
        xy = [(cost, value * scale) for cost, value, _, _ in ranked]
        front = pareto_front(xy) if xy else []
        fronts.setdefault(title, []).extend(point_name(ranked[i][2]) for i in front)
        jobs = [sweep_job(p[2].folder) for p in ranked]
        if jobs and all(jobs):
            draw_sweep_points(fig, ax, ranked, jobs, scale)
        else:
            ax.scatter([x for x, _ in xy], [y for _, y in xy], s=26, zorder=3,
                       color=[LABEL_COLOURS.colour(p[2].label) for p in ranked])
        if front:
            fx = [xy[i][0] for i in front]
            fy = [xy[i][1] for i in front]
            ax.step(fx, fy, where="post", color="crimson", lw=1.4, zorder=2,
                    label="Pareto front")
            ax.scatter(fx, fy, s=60, facecolors="none", edgecolors="crimson", zorder=4)
        unranked = draw_unranked_points(ax, points, scale)
        finish_pareto_axes(ax, title, metric, xy + unranked)
        placed.append((ax, ranked, front, points, scale))
    for ax in axes[len(panels):]:
        ax.set_visible(False)
    fig.suptitle("error against CPU time per tick, per scenario: lower left is better",
                 fontsize=11)
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.4 / fig.get_figheight()))  # room for the title
    for ax, ranked, front, points, scale in placed:  # labels once the axes have their place
        on_front = {id(ranked[i][2]) for i in front}
        chosen = [p for p in points if len(points) <= MAX_PARETO_LABELS or id(p[2]) in on_front]
        label_points(ax, [((p[0], p[1] * scale), point_text(p[2]), id(p[2]) in on_front)
                          for p in chosen])
    return png_data_uri(fig), fronts, left_out, failed


def point_text(run):
    """The text beside a point: a sweep job's grid values (its marker tells the label), else
    the label."""
    job = sweep_job(run.folder)
    if job is None:
        return run.label
    keys = job.sweep.keys
    return value_text(job.values.get(keys[0])) if len(keys) == 1 else job.describe()


def draw_unranked_points(ax, points, scale):
    """Baselines (grey) and diverged or non-finite runs (hollow): drawn, never ranked.
    Returns their (x, y)."""
    baseline = [(c, v * scale) for c, v, run, failure in points if not failure and is_baseline(run)]
    bad = [(c, v * scale) for c, v, _, failure in points if failure]
    if baseline:
        ax.scatter([x for x, _ in baseline], [y for _, y in baseline], s=30, color="#b0b0b0",
                   edgecolors="#777", zorder=3, label="baseline, renders no contact (not ranked)")
    if bad:
        ax.scatter([x for x, _ in bad], [y for _, y in bad], s=40, facecolors="none",
                   edgecolors="grey", zorder=3, label="diverged or non-finite (not ranked)")
    return baseline + bad


def draw_sweep_points(fig, ax, points, jobs, scale):
    """A sweep's points coloured by the first swept value (a colour bar, log when the values
    span more than a decade), a marker per label, each label's points joined in order of the
    value (one line per combination of the other keys' values)."""
    key = jobs[0].sweep.keys[0]
    numeric = is_numeric_key(jobs, key)
    listed = jobs[0].sweep.grid.get(key, [])
    shade = [float(job.values[key]) if numeric else listed.index(job.values.get(key))
             if job.values.get(key) in listed else len(listed) for job in jobs]
    norm = (matplotlib.colors.LogNorm(min(shade), max(shade))
            if numeric and spans_more_than_a_decade(shade)
            else matplotlib.colors.Normalize(min(shade), max(shade) if max(shade) > min(shade)
                                             else min(shade) + 1))
    labels = list(dict.fromkeys(p[2].label for p in points))
    lines = {}
    for point, job, value in zip(points, jobs, shade):
        others = tuple(value_text(job.values.get(k)) for k in job.sweep.keys[1:])
        lines.setdefault((point[2].label, others), []).append(
            (job.value_sort_key(key), point[0], point[1] * scale))
    for line in lines.values():
        line.sort()
        ax.plot([x for _, x, _ in line], [y for _, _, y in line], color="#bbbbbb", lw=0.8,
                zorder=1)
    for label in labels:
        chosen = [i for i, p in enumerate(points) if p[2].label == label]
        marker = LABEL_MARKERS[labels.index(label) % len(LABEL_MARKERS)]
        mappable = ax.scatter([points[i][0] for i in chosen],
                              [points[i][1] * scale for i in chosen],
                              c=[shade[i] for i in chosen], cmap="viridis", norm=norm, s=34,
                              marker=marker, edgecolors="#333", linewidths=0.4, zorder=3)
        ax.scatter([], [], marker=marker, color="#777", label=label)
    bar = fig.colorbar(mappable, ax=ax, pad=0.02)
    bar.set_label(parameter_label(key), fontsize=8)
    if not numeric:
        bar.set_ticks(range(len(listed)))
        bar.set_ticklabels([value_text(v, 12) for v in listed])
    bar.ax.tick_params(labelsize=7)


def finish_pareto_axes(ax, title, metric, every):
    ax.set_xscale("log")
    sparse_minor_ticks(ax.xaxis, spans_under_two_decades([x for x, _ in every]))
    if all(y > 0 for _, y in every):
        ax.set_yscale("log")
        sparse_minor_ticks(ax.yaxis, spans_under_two_decades([y for _, y in every]))
    ax.margins(x=0.15, y=0.12)
    ax.set_title(title, fontsize=10)
    ax.set_xlabel("CPU time per tick, p99 (µs): step + slow loop")
    ax.set_ylabel("force error RMS (N)" if metric == "force_err_rms_n"
                  else "max penetration (mm)")
    ax.grid(True, alpha=0.3, which="both")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="upper right", fontsize=7)


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
    # In mJ, as the console and the budget passivity_energy_min_mj give it.
    energies = [run.summary["stability"]["passivity_energy_min_j"] * 1e3 for run in shown]
    diverged = [dig(run.summary, "stability", "diverged") is True for run in shown]
    fig = Figure(figsize=(10, 1.2 + 0.24 * len(shown)))
    ax = fig.subplots()
    positions = np.arange(len(shown))[::-1]
    colours = ["#c62828" if e < 0 else "#2e7d32" for e in energies]
    ax.barh(positions, energies, color=colours, height=0.7)
    for position, energy, is_diverged in zip(positions, energies, diverged):
        text = "%.3g mJ%s" % (energy, "  diverged" if is_diverged else "")
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
    ax.set_xlabel("passivity energy min (mJ), symmetric log scale; below 0 the rendering "
                  "gave energy away")
    ax.grid(True, axis="x", alpha=0.3)
    fig.tight_layout()
    return png_data_uri(fig), shown, without


def integrator_of(run):
    integrator = dig(run.summary, "params", "integrator")
    return integrator if isinstance(integrator, str) else run.label


def sweep_index(parent):
    """The sweep.json `hapticbench sweep` wrote into a folder: (its grid, {job name: job}),
    or None without one."""
    sweep = sweep_at(parent)
    return (sweep.grid, sweep.jobs_by_name) if sweep else None


def coupling_stiffness(folder):
    """(scene, k_t) when the folder is one job of a sweep over the coupling stiffness (the
    sweep.json beside it has /coupling/k_t in its grid), else None. k_t (N/m) is the one the
    run's summary.json gives; the scene is the job's scenario file and its values of the
    sweep's other varied keys."""
    parent, name = os.path.split(os.path.normpath(os.path.abspath(folder.path)))
    index = sweep_index(parent)
    if index is None:
        return None
    grid, jobs = index
    job = jobs.get(name)
    k = dig(folder.summary, "scenario", "coupling", "k_t")
    if job is None or COUPLING_STIFFNESS_KEY not in grid or not finite_number(k):
        return None
    scene = os.path.splitext(os.path.basename(str(job.get("scenario") or name)))[0]
    varied = [key for key, values in sorted(grid.items())
              if key != COUPLING_STIFFNESS_KEY and isinstance(values, list) and len(values) > 1]
    values = job.get("grid") if isinstance(job.get("grid"), dict) else {}
    if varied:
        scene += " (%s)" % ", ".join("%s=%s" % (key, json.dumps(values.get(key)))
                                     for key in varied)
    return scene, float(k)


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


def verdict_stable(run):
    """True or False from the run's stability verdict; None without one."""
    stable = dig(run.summary, "stability", "verdict", "stable")
    return stable if isinstance(stable, bool) else None


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
    every_run = [run for runs in by_integrator.values() for _, run in runs]
    separation_of = {id(run): dig(run.summary, "stability", "max_proxy_separation_m")
                     for run in every_run}
    has_separation = all(finite_number(v) and v > 0 for v in separation_of.values())
    # A diverged proxy flies off to 1e150 m: such points sit on the top edge.
    stable_separations = [separation_of[id(run)] for run in every_run
                          if has_separation and dig(run.summary, "stability", "diverged") is False]
    ceiling = max([1.0] + [10 * v for v in stable_separations])
    clipped_any = False
    for integrator, runs in sorted(by_integrator.items()):
        colour = LABEL_COLOURS.colour(integrator)
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


def zwidth_figure(scenario, results):
    """One scenario's Z-width map: per algorithm label, the largest stable
    value of the y field against the x field (the large-signal search: full
    runs, with the device's friction and quantisation), the band up to the
    smallest unstable value shaded; below the line is stable. Dashed, where
    the map has it, the small-signal limit of the same loop linearised
    (small_signal_limit: no friction, no quantisation)."""
    fig = Figure(figsize=(8, 4.2))
    ax = fig.subplots()
    for _, data in sorted(results, key=lambda r: r[1]["label"]):
        colour = LABEL_COLOURS.colour(data["label"])
        points = sorted(data["points"], key=lambda p: p["x"])
        xs = [p["x"] for p in points if p.get("largest_stable") is not None]
        stable = [p["largest_stable"] for p in points if p.get("largest_stable") is not None]
        ax.plot(xs, stable, color=colour, marker="o", ms=4, label=data["label"])
        band = [(p["x"], p["largest_stable"], p["smallest_unstable"]) for p in points
                if p.get("largest_stable") is not None and p.get("smallest_unstable") is not None]
        if band:
            ax.fill_between([b[0] for b in band], [b[1] for b in band], [b[2] for b in band],
                            color=colour, alpha=0.25, lw=0)
        small = [(p["x"], p["small_signal_limit"]) for p in points
                 if finite_number(p.get("small_signal_limit"))]
        if small:
            ax.plot([x for x, _ in small], [k for _, k in small], color=colour, ls="--", lw=1,
                    label=data["label"] + " (small-signal)")
        top = [p["x"] for p in points if p.get("smallest_unstable") is None]
        if top:
            range_top = dig(data, "y_range")
            if isinstance(range_top, list) and len(range_top) == 2 and finite_number(range_top[1]):
                ax.plot(top, [range_top[1]] * len(top), ls="none", marker="^", color=colour)
    first = results[0][1]
    values = [p[key] for _, d in results for p in d["points"]
              for key in ("largest_stable", "smallest_unstable", "small_signal_limit")
              if p.get(key)]
    if values and max(values) > 10 * min(values):  # a decade or more: log scale
        ax.set_yscale("log")
        sparse_minor_ticks(ax.yaxis)
    ax.set_xlabel(parameter_label(first["x_param"]))
    ax.set_ylabel("largest stable " + parameter_label(first["y_param"]))
    ax.grid(True, alpha=0.3, which="both")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    fig.suptitle("Z-width: %s" % scenario, fontsize=11)
    fig.subplots_adjust(left=0.11, right=0.75, top=0.90, bottom=0.13)
    return png_data_uri(fig)


# What a sweep's metric-against-parameter figure draws: (axis title, value of a run).
SWEEP_METRICS = [
    ("force error RMS (N)", lambda run: headline(run.summary)),
    ("max penetration (mm)", lambda run: scaled(dig(run.summary, "accuracy",
                                                    "penetration_max_m"), 1e3)),
    ("step time p99 (µs)", lambda run: run.p99_us()),
]


def scaled(value, factor):
    return value * factor if finite_number(value) else None


def sweep_metric_lines(jobs, key):
    """The runs of a sweep's jobs as lines against one grid key: {(label, the other keys'
    values): [(x, run)]}, each line in numeric order of the key's value. x is the value,
    or its place in the grid's list for a key whose values are not numbers."""
    numeric = is_numeric_key(jobs, key)
    listed = jobs[0].sweep.grid.get(key, []) if jobs else []
    lines = {}
    for job in jobs:
        value = job.values.get(key)
        x = float(value) if numeric else (listed.index(value) if value in listed
                                          else len(listed))
        others = job.describe([k for k in job.sweep.keys if k != key])
        for run in job.folder.runs:
            lines.setdefault((run.label, others), []).append((job.value_sort_key(key), x, run))
    return {line: [(x, run) for _, x, run in sorted(points, key=lambda p: p[0])]
            for line, points in lines.items()}


def sweep_metrics_figure(jobs, key):
    """Force error RMS, max penetration and step time p99 against one grid key of a sweep's
    jobs (one base scenario): a line per label, and per combination of the other keys'
    values (their own line style). Log x when the values span more than a decade."""
    lines = sweep_metric_lines(jobs, key)
    combinations = list(dict.fromkeys(others for _, others in lines))
    styles = ["-", "--", ":", "-."]
    fig = Figure(figsize=(12, 3.9))
    axes = fig.subplots(1, len(SWEEP_METRICS))
    xs = sorted({x for points in lines.values() for x, _ in points})
    numeric = is_numeric_key(jobs, key)
    for ax, (title, value_of) in zip(axes, SWEEP_METRICS):
        drawn = False
        for (label, others), points in lines.items():
            kept = [(x, value_of(run)) for x, run in points if finite_number(value_of(run))]
            if not kept:
                continue
            drawn = True
            ax.plot([x for x, _ in kept], [y for _, y in kept], marker="o", ms=4, lw=1.3,
                    color=LABEL_COLOURS.colour(label),
                    ls=styles[combinations.index(others) % len(styles)],
                    label=label + (", " + others if others else ""))
        if not drawn:
            ax.text(0.5, 0.5, "not measured", transform=ax.transAxes, ha="center",
                    color="#777")
        values = [y for line in ax.get_lines() for y in line.get_ydata()]
        if drawn and spans_more_than_a_decade(values):
            ax.set_yscale("log")
            sparse_minor_ticks(ax.yaxis, spans_under_two_decades(values))
        set_sweep_x_axis(ax, key, xs, numeric, jobs)
        ax.set_title(title, fontsize=9)
        ax.grid(True, alpha=0.3, which="both")
    axes[-1].legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, frameon=False)
    fig.suptitle("%s: against %s" % (jobs[0].group, key_name(key)), fontsize=11)
    fig.subplots_adjust(left=0.06, right=0.80, top=0.84, bottom=0.16, wspace=0.3)
    return png_data_uri(fig)


def set_sweep_x_axis(ax, key, xs, numeric, jobs):
    ax.set_xlabel(parameter_label(key), fontsize=8)
    if numeric:
        if spans_more_than_a_decade(xs):
            ax.set_xscale("log")
            sparse_minor_ticks(ax.xaxis, spans_under_two_decades(xs))
        return
    listed = jobs[0].sweep.grid.get(key, [])
    ax.set_xticks(range(len(listed)))
    ax.set_xticklabels([value_text(v, 12) for v in listed], fontsize=7, rotation=20)


# The history figure labels at most this many entries on its x axis.
MAX_HISTORY_TICKS = 24


def history_figure(history, scenario, moves):
    """One scenario's metrics across the history's entries: a panel per metric measured
    (force error RMS, max penetration, step time p99, instructions per step), a line per
    label, x the entries in commit order labelled by short commit. Red crosses: the label
    was unstable at that entry; a black ring: the series' first move. None when the
    scenario measured none of them."""
    shown = [m for m in HISTORY_METRICS if m.rule != "verdict" and history.measured(scenario, m.key)]
    if not shown:
        return None
    labels = history.series[scenario]
    first = {(move.label, move.metric.key): move.entry.index for move in moves
             if move.scenario == scenario}
    entries = history.entries
    legend_in = max(1.8, 0.075 * max(len(label) for label in labels) + 0.8)
    fig = Figure(figsize=(4.3 * len(shown) + legend_in, 3.9))
    axes = fig.subplots(1, len(shown), squeeze=False)[0]
    every = max(1, math.ceil(len(entries) / MAX_HISTORY_TICKS))
    for ax, metric in zip(axes, shown):
        values = []
        for label, metrics in labels.items():
            points = metrics[metric.key]
            colour = LABEL_COLOURS.colour(label)
            ys = [p.value if p.value is not None else math.nan for p in points]
            values += [y for y in ys if finite_number(y)]
            ax.plot(range(len(points)), ys, marker="o", ms=3.5, lw=1.3, color=colour,
                    label=label)
            unstable = [(p.entry.index, p.value) for p in points
                        if p.unstable and p.value is not None]
            if unstable:
                ax.plot([x for x, _ in unstable], [y for _, y in unstable], ls="none",
                        marker="X", ms=9, color="#d62728", mec="white", mew=0.6, zorder=4)
            index = first.get((label, metric.key))
            if index is not None:
                ax.plot([index], [points[index].value], ls="none", marker="o", ms=14,
                        mfc="none", mec="black", mew=1.6, zorder=5)
        if spans_more_than_a_decade(values):
            ax.set_yscale("log")
            sparse_minor_ticks(ax.yaxis, spans_under_two_decades(values))
        ax.set_title(metric.heading(), fontsize=9)
        ax.set_xlim(-0.5, len(entries) - 0.5)
        ticks = list(range(0, len(entries), every))
        ax.set_xticks(ticks)
        ax.set_xticklabels([entries[i].short_commit for i in ticks], fontsize=7, rotation=35,
                           ha="right")
        ax.grid(True, alpha=0.3, which="both")
    handles, names = axes[0].get_legend_handles_labels()
    handles += [Line2D([], [], ls="none", marker="X", ms=8, color="#d62728"),
                Line2D([], [], ls="none", marker="o", ms=11, mfc="none", mec="black", mew=1.6)]
    names += ["unstable", "first move"]
    fig.legend(handles, names, loc="upper left", bbox_to_anchor=(
        1 - (legend_in - 0.1) / fig.get_figwidth(), 0.92), fontsize=8, frameon=False)
    fig.suptitle("%s: across %d commit%s" % (scenario, len(entries),
                                             "" if len(entries) == 1 else "s"), fontsize=11)
    fig.subplots_adjust(left=0.6 / fig.get_figwidth(), right=1 - legend_in / fig.get_figwidth(),
                        top=0.84, bottom=0.2, wspace=0.3)
    return png_data_uri(fig)


# The scene figure draws the device's path from at most this many points.
MAX_PATH_POINTS = 400


# The scene figure zooms to the motion (the path and the tool at its start and deepest
# poses) when the scene and the motion together span more than this many times the
# motion's own extent; the zoomed view adds this share of the motion's extent each side.
ZOOM_RATIO = 4.0


ZOOM_MARGIN = 0.3


# The scene figure's panels: (title, horizontal axis, vertical axis), 0 1 2 = x y z.
SCENE_VIEWS = (("side view (x–z)", 0, 2), ("top view (x–y)", 0, 1))


def quaternion_matrix(w, x, y, z):
    """The rotation matrix of a quaternion (normalised here; a zero one is the identity)."""
    norm = math.sqrt(w * w + x * x + y * y + z * z)
    if not math.isfinite(norm) or norm == 0:
        return np.eye(3)
    w, x, y, z = w / norm, x / norm, y / norm, z / norm
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def box_corners(lo, hi):
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    return np.array([[(lo, hi)[i >> k & 1][k] for k in range(3)] for i in range(8)])


class DevicePath:
    """The device's tool-frame origin along a run (m, world frame, from the ticks'
    dev_p* columns) and its orientation (dev_q*, else none), with the start and the
    deepest (lowest z) tick."""

    def __init__(self, run):
        ticks = run.ticks
        self.run = run
        self.position = np.column_stack([ticks["dev_px"], ticks["dev_py"], ticks["dev_pz"]])
        finite = np.isfinite(self.position).all(axis=1)
        self.position = self.position[finite]
        quaternion = [ticks.get(name) for name in ("dev_qw", "dev_qx", "dev_qy", "dev_qz")]
        self.orientation = (np.column_stack(quaternion)[finite]
                            if all(q is not None for q in quaternion) else None)
        self.deepest = int(np.argmin(self.position[:, 2]))

    @staticmethod
    def of(runs):
        """The path of the first label whose ticks have the device's position, or None."""
        for run in runs:
            if run.ticks is not None and all(c in run.ticks for c in ("dev_px", "dev_py",
                                                                       "dev_pz")):
                path = DevicePath(run)
                if len(path.position):
                    return path
        return None

    def shown(self):
        """At most MAX_PATH_POINTS points, evenly spaced, with the first, last and deepest."""
        n = len(self.position)
        keep = np.unique(np.concatenate([np.linspace(0, n - 1, min(n, MAX_PATH_POINTS))
                                         .round().astype(int), [self.deepest]]))
        return self.position[keep]

    def rotation(self, index):
        if self.orientation is None:
            return np.eye(3)
        return quaternion_matrix(*self.orientation[index])

    def rotated(self, index):
        return not np.allclose(self.rotation(index), np.eye(3), atol=1e-6)

    def tool_centre(self, tool, index):
        """The centre of the tool's bounds at the path's tick `index` (m, world frame)."""
        centre = (np.asarray(tool["min"], dtype=float) + np.asarray(tool["max"], dtype=float)) / 2
        return self.rotation(index) @ centre + self.position[index]

    def tool_corners(self, tool, index):
        """The corners of the tool's bounds at the path's tick `index` (m, world frame)."""
        return (box_corners(tool["min"], tool["max"]) @ self.rotation(index).T
                + self.position[index])


def scene_view(outline, path):
    """(lo, hi, zoomed): the box (m, world frame) the scene figure shows. The whole scene
    with the motion (the path, the tool at its start and deepest poses), or, when that
    spans more than ZOOM_RATIO times the motion's extent, the motion with a margin."""
    boxes = [(np.asarray(o["min"], dtype=float), np.asarray(o["max"], dtype=float))
             for o in outline["scene"]]
    motion = None
    if path is not None:
        points = np.vstack([path.position, path.tool_corners(outline["tool"], 0),
                            path.tool_corners(outline["tool"], path.deepest)])
        motion = (points.min(axis=0), points.max(axis=0))
        boxes.append(motion)
    if not boxes:
        return None
    lo = np.min([b[0] for b in boxes], axis=0)
    hi = np.max([b[1] for b in boxes], axis=0)
    zoomed = False
    if motion is not None:
        extent = max(float(np.max(motion[1] - motion[0])), 1e-6)
        if float(np.max(hi - lo)) > ZOOM_RATIO * extent:
            lo, hi, zoomed = motion[0], motion[1], True
        margin = ZOOM_MARGIN * extent if zoomed else 0.05 * float(np.max(hi - lo))
    else:
        margin = 0.05 * max(float(np.max(hi - lo)), 1e-6)
    return lo - margin, hi + margin, zoomed


def outline_patch(kind, lo, hi, **style):
    """A scene object or the tool in one view, lo and hi its bounds there (mm): a circle
    for a sphere, a rounded rectangle for a capsule, else the bounds' rectangle."""
    from matplotlib.patches import Circle, FancyBboxPatch, Rectangle
    width, height = hi[0] - lo[0], hi[1] - lo[1]
    if kind == "sphere":
        return Circle(((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2), max(width, height) / 2,
                      **style)
    if kind == "capsule" and min(width, height) > 0:
        return FancyBboxPatch(tuple(lo), width, height, boxstyle="round,pad=0,rounding_size=%r"
                              % (min(width, height) / 2), **style)
    return Rectangle(tuple(lo), width, height, **style)


def scene_figure(outline, runs):
    """Side (x–z) and top (x–y) views of the scene in mm: each object's bounds (dashed:
    distance only), the device's path from the first label with its ticks, and the
    tool's bounds at the start and at the deepest point. Returns (uri, facts): facts has
    "path_label" (None without ticks), "zoomed", "scene_extent_mm" and "rotated"
    (the tool is turned at a pose drawn: its bounds' corners are drawn as their hull)."""
    from matplotlib.patches import Polygon
    path = DevicePath.of(runs)
    view = scene_view(outline, path)
    if view is None:
        return None, None
    lo, hi, zoomed = view
    scene = outline["scene"]
    if scene:
        scene_lo = np.min([o["min"] for o in scene], axis=0)
        scene_hi = np.max([o["max"] for o in scene], axis=0)
    colour = LABEL_COLOURS.colour(path.run.label) if path is not None else "black"
    tool = outline["tool"]
    fig = Figure(figsize=(11, 5.0))
    axes = fig.subplots(1, 2)
    rotated = False
    for ax, (title, i, j) in zip(axes, SCENE_VIEWS):
        for o in scene:
            dashed = o.get("distance_only") is True
            ax.add_patch(outline_patch(
                o["type"], 1e3 * np.array([o["min"][i], o["min"][j]]),
                1e3 * np.array([o["max"][i], o["max"][j]]), fc="none" if dashed else "#d9dde3",
                ec="#555", lw=1.2, ls="--" if dashed else "-", zorder=1))
            # Its name in the lower left corner of the part in view.
            corner = [max(o["min"][k], lo[k]) for k in (i, j)]
            if len(scene) <= 8 and all(c < min(o["max"][k], hi[k]) for k, c
                                       in zip((i, j), corner)):
                pad = 0.015 * (hi[i] - lo[i])
                ax.text(1e3 * (corner[0] + pad), 1e3 * (corner[1] + pad),
                        "%s (%s)" % (o.get("name", "?"), o["type"]), fontsize=7, color="#444",
                        ha="left", va="bottom", zorder=2)
        if path is not None:
            points = 1e3 * path.shown()
            ax.plot(points[:, i], points[:, j], color=colour, lw=1.4, zorder=4)
            for index, style in ((0, dict(ls=":", lw=1.3)), (path.deepest, dict(ls="-", lw=1.6))):
                if tool["type"] == "sphere":  # turning it changes nothing
                    centre = 1e3 * path.tool_centre(tool, index)[[i, j]]
                    radius = 1e3 * np.max(np.subtract(tool["max"], tool["min"])) / 2
                    ax.add_patch(outline_patch("sphere", centre - radius, centre + radius,
                                               fc="none", ec=colour, zorder=3, **style))
                elif not path.rotated(index):
                    corners = path.tool_corners(tool, index)
                    ax.add_patch(outline_patch(
                        tool["type"], 1e3 * corners.min(axis=0)[[i, j]],
                        1e3 * corners.max(axis=0)[[i, j]], fc="none", ec=colour, zorder=3,
                        **style))
                else:  # turned: the hull of its bounds' corners in this view
                    rotated = True
                    hull = convex_hull(1e3 * path.tool_corners(tool, index)[:, [i, j]])
                    ax.add_patch(Polygon(hull, closed=True, fc="none", ec=colour, zorder=3,
                                         **style))
            start, end, deepest = (1e3 * path.position[k] for k in (0, -1, path.deepest))
            ax.plot(start[i], start[j], ls="none", marker="o", ms=10, mfc="white", mec="black",
                    zorder=5)
            ax.plot(deepest[i], deepest[j], ls="none", marker="v", ms=7, color=colour,
                    mec="black", zorder=5)
            ax.plot(end[i], end[j], ls="none", marker="s", ms=5, color="black", zorder=6)
        ax.set_xlim(1e3 * lo[i], 1e3 * hi[i])
        ax.set_ylim(1e3 * lo[j], 1e3 * hi[j])
        ax.set_aspect("equal", adjustable="box")
        ax.set_xlabel("%s (mm)" % "xyz"[i])
        ax.set_ylabel("%s (mm)" % "xyz"[j])
        ax.set_title(title, fontsize=9)
        ax.grid(True, alpha=0.3)
    handles = [Line2D([], [], color="#555", lw=6, alpha=0.3, label="scene object (bounds)")]
    if any(o.get("distance_only") is True for o in scene):
        handles.append(Line2D([], [], color="#555", ls="--", label="distance only"))
    if path is not None:
        handles += [Line2D([], [], color=colour, lw=1.4, label="path (%s)" % path.run.label),
                    Line2D([], [], color=colour, ls=":", label="tool at the start"),
                    Line2D([], [], color=colour, lw=1.6, label="tool at the deepest point"),
                    Line2D([], [], ls="none", marker="o", mfc="white", mec="black", label="start"),
                    Line2D([], [], ls="none", marker="v", color=colour, mec="black",
                           label="deepest (lowest z)"),
                    Line2D([], [], ls="none", marker="s", ms=5, color="black", label="end")]
    fig.legend(handles=handles, loc="upper left", bbox_to_anchor=(0.81, 0.9), fontsize=8,
               frameon=False)
    fig.suptitle("the scene and the device's path" + (" (zoomed to the motion)" if zoomed
                                                      else ""), fontsize=11)
    fig.subplots_adjust(left=0.07, right=0.80, top=0.88, bottom=0.1, wspace=0.3)
    facts = {"path_label": path.run.label if path is not None else None, "zoomed": zoomed,
             "scene_extent_mm": (1e3 * (scene_hi - scene_lo)).tolist() if scene else None,
             "rotated": rotated}
    return png_data_uri(fig), facts


def convex_hull(points):
    """The convex hull of 2-D points, counter-clockwise (Andrew's monotone chain)."""
    points = sorted(set(map(tuple, np.round(points, 9))))
    if len(points) <= 2:
        return np.array(points)

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    hull = []
    for sequence in (points, points[::-1]):
        chain = []
        for p in sequence:
            while len(chain) >= 2 and cross(chain[-2], chain[-1], p) <= 0:
                chain.pop()
            chain.append(p)
        hull += chain[:-1]
    return np.array(hull)


def intent_figure(intent, runs):
    """Closed loop: the intent's z (the trace), each label's device z and, thin, its
    proxy's z against time (mm), and below each device's departure from the intent
    (device z − intent z, the intent interpolated to the ticks). None without ticks
    holding the device's position."""
    shown = [run for run in runs if run.ticks is not None and "dev_pz" in run.ticks]
    order = np.argsort(intent["t_s"], kind="stable")
    t_intent, z_intent = intent["t_s"][order], intent["pz"][order]
    ok = np.isfinite(t_intent) & np.isfinite(z_intent)
    t_intent, z_intent = t_intent[ok], z_intent[ok]
    if not shown or len(t_intent) == 0:
        return None
    fig = Figure(figsize=(10, 5.6))
    position, departure = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [3, 2]})
    position.plot(t_intent, 1e3 * z_intent, color="black", lw=1.6, ls="--", zorder=5)
    for run in shown:
        colour = LABEL_COLOURS.colour(run.label)
        t = run.ticks["t_ns"] * 1e-9
        z = run.ticks["dev_pz"]
        plot_series(position, t, 1e3 * z, color=colour, lw=1.3)
        if "proxy_pz" in run.ticks:
            plot_series(position, t, 1e3 * run.ticks["proxy_pz"], color=colour, lw=0.6,
                        alpha=0.8)
        plot_series(departure, t, 1e3 * (z - np.interp(t, t_intent, z_intent)), color=colour,
                    lw=1.1)
    departure.axhline(0, color="black", lw=0.8, ls="--")
    handles = [Line2D([], [], color="black", lw=1.6, ls="--", label="intent (trace)")]
    handles += [Line2D([], [], color=LABEL_COLOURS.colour(run.label), lw=2, label=run.label)
                for run in shown]
    handles += [Line2D([], [], color="grey", lw=1.3, label="device"),
                Line2D([], [], color="grey", lw=0.6, label="proxy")]
    position.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8,
                    frameon=False)
    position.set_ylabel("z (mm)")
    departure.set_ylabel("device z − intent z (mm)")
    departure.set_xlabel("time (s)")
    for ax in (position, departure):
        ax.grid(True, alpha=0.3)
    fig.suptitle("the device against the intent", fontsize=11)
    fig.subplots_adjust(left=0.08, right=0.80, top=0.93, bottom=0.09, hspace=0.1)
    return png_data_uri(fig)
