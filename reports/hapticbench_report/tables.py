"""The report's tables and HTML pieces: the summary and metric tables, a
scenario's parameters, a sweep's table across its jobs, work counters, the
stress matrix, friction, stability margins and Z-width results, and the
escaping and number formats they share."""
import html
import os
import re

from .inputs import (
    dig, finite_number, headline, is_baseline, number_or_none, read_json_or_none, reference_wording,
    scenario_description)
from .figures import PARAMETER_UNITS, parameter_label, zwidth_figure
from .sweeps import key_name, missing_jobs, value_text


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


def name_html(text):
    """A long name (sphere_press_box__contact_stiffness=1000) that may wrap after its
    underscores."""
    return esc(text).replace("_", "_<wbr>")


def cell(value, pattern="%.3g", scale=1.0, css=""):
    text = fmt(value, pattern, scale)
    if text is None:
        return '<td class="na" title="does not apply to this run">—</td>'
    return '<td%s>%s</td>' % (' class="%s"' % css if css else "", esc(text))


def stability_item(summary):
    """The run's stability verdict as a cell, and whether it passes: stable, or unstable
    where the scenario or the command line expects it (runs[].stability.verdict)."""
    verdict = dig(summary, "stability", "verdict") or {}
    if not verdict:
        return '<td class="na">—</td>', True
    if verdict.get("stable"):
        return ('<td class="text pass" title="%s">stable</td>' % esc(verdict.get("reason", "")),
                True)
    expected = verdict.get("expected_unstable")
    text = verdict.get("reason") or verdict.get("failed") or "unstable"
    if expected:
        return ('<td class="text" title="%s">%s (expected)</td>' % (esc(expected), esc(text)),
                True)
    return '<td class="text fail">✗ %s</td>' % esc(text), False


def budget_text(budget):
    """"tick_p99_us 3.614 ≤ 1000": a budget's value against its limit."""
    relation = "≥" if budget.get("lower_bound") else "≤"
    value = fmt(budget.get("value"), "%.4g")
    return "%s %s %s %s" % (budget.get("name", "?"), value if value is not None else "n/a",
                            relation, fmt(budget.get("limit"), "%.4g") or "?")


def budget_items(budgets):
    """A cell listing the failed budgets and counting the others (hover: every budget), and
    the verdict: "pass", "fail" or "none"."""
    if not budgets:
        return '<td class="na" title="no budgets in the scenario">—</td>', "none"
    failed = [b for b in budgets if b.get("pass") is not True]
    items = ['<li class="fail" title="%s">✗ %s</li>'
             % (esc(b.get("message") or "over budget"), esc(budget_text(b))) for b in failed]
    if len(failed) < len(budgets):
        items.append('<li class="pass">✓ %d of %d</li>'
                     % (len(budgets) - len(failed), len(budgets)))
    return ('<td class="text" title="%s"><ul class="budgets">%s</ul></td>'
            % (esc("; ".join(budget_text(b) for b in budgets)), "".join(items)),
            "fail" if failed else "pass")


# How the summary table shows a metric of a unit: (header unit, format, scale).
UNIT_DISPLAY = {"ns": ("µs", "%.2f", 1e-3), "m": ("mm", "%.3f", 1e3), "N": ("N", "%.4g", 1.0),
                "deg": ("°", "%.3g", 1.0), "J": ("J", "%.3g", 1.0), "N·m": ("N·m", "%.3g", 1.0),
                "ticks": ("ticks", "%d", 1.0)}


# A metric name's unit suffix, dropped from its column header (which names the unit once).
UNIT_SUFFIXES = ("_n_per_m", "_j_per_s", "_us", "_ns", "_nm", "_deg", "_hz", "_mm", "_mj", "_m",
                 "_n", "_j")

# How a value in a metric's own unit (its name's: budget_unit) is written.
UNIT_PATTERNS = {"µs": "%.2f", "mm": "%.3f", "mJ": "%.3g", "N": "%.4g", "ticks": "%d"}


def display_unit(metric):
    """(unit shown, printf pattern, scale from the summary's value) of a metric: the unit of
    its name, as budgets and the console give it (the metric table's budget_unit and
    budget_scale), else the summary's unit mapped as UNIT_DISPLAY says."""
    unit = metric.get("budget_unit")
    scale = metric.get("budget_scale")
    if isinstance(unit, str) and unit and isinstance(scale, (int, float)):
        return unit, UNIT_PATTERNS.get(unit, "%.4g"), float(scale)
    return UNIT_DISPLAY.get(metric["unit"], (metric["unit"], "%.4g", 1.0))


HEADER_WORDS = {"err": "error", "rms": "RMS", "dir": "direction", "cpu": "CPU",
                "nonfinite": "non-finite"}


def metric_header(metric):
    """A metric's column header in words with its unit once: max_penetration_m ->
    "max penetration (mm)", tick_p99_us -> "tick p99 (µs)"."""
    name = str(metric["name"])
    suffix = next((s for s in UNIT_SUFFIXES if name.endswith(s)), "")
    words = [HEADER_WORDS.get(w, w) for w in name[:len(name) - len(suffix)].split("_") if w]
    unit = display_unit(metric)[0]
    if not unit or unit == "flag" or words[-1:] == [unit]:
        return " ".join(words)
    return "%s (%s)" % (" ".join(words), unit)


def label_html(run):
    """A run's label, its algorithm where the label does not say it, and a baseline mark."""
    algorithm = run.summary.get("algorithm", "?")
    return (name_html(run.label)
            + (' <span class="small">(%s)</span>' % name_html(algorithm) if algorithm != run.label
               else "")
            + (' <span class="tag" title="renders no contact: the coupling alone, to compare '
               'with">baseline</span>' if is_baseline(run) else ""))


def metric_cell(metric, value):
    """One cell of a metric: flags as yes/no, counts of bad ticks and energy given away marked."""
    if metric["unit"] == "flag":
        return ('<td class="%s">%s</td>' % ("fail" if value else "pass", "yes" if value else "no")
                if isinstance(value, bool) else '<td class="na">—</td>')
    _, pattern, scale = display_unit(metric)
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
            "<th>ticks</th><th class='text'>stability</th>"
            + "".join("<th title='%s: %s'>%s</th>" % (
                esc(m["name"]), esc(m.get("description", "")), esc(metric_header(m)))
                for m in columns)
            + "<th class='text'>pen source</th><th class='text'>budgets</th></tr>")
    rows = []
    for folder in folders:
        for position, run in enumerate(folder.runs):
            s = run.summary
            budgets, verdict = budget_items(s.get("budgets") or [])
            stability, stable = stability_item(s)
            if not stable:
                verdict = "fail"
            source = dig(s, "accuracy", "penetration_source")
            rows.append(
                '<tr data-scenario="%s" data-label="%s" data-verdict="%s"%s>'
                % (esc(folder.scenario), esc(run.label), verdict,
                   ' class="scenario-first"' if position == 0 else "")
                + '<td class="text"><a href="#%s">%s</a></td>' % (folder.slug,
                                                                   name_html(folder.scenario))
                + '<td class="text">%s</td>' % label_html(run)
                + cell(dig(s, "timing", "ticks"), "%d")
                + stability
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


def sweep_file_verdict(runs):
    """scripts/stability-sweep's stiffness-limits.json beside the run folders, if there is one."""
    parents = {os.path.dirname(os.path.normpath(run.folder.path)) for _, run in runs}
    if len(parents) != 1:
        return None
    path = os.path.join(parents.pop(), "stiffness-limits.json")
    data = read_json_or_none(path)
    return (path, data) if isinstance(data, dict) else None


def is_stress_folder(folder):
    """A run of a scenario tagged "stress" (summary.json scenario.tags; scenarios/stress/)."""
    tags = dig(folder.summary, "scenario", "tags")
    return isinstance(tags, list) and "stress" in tags


def stress_verdict(run):
    """(passed, text) from the run's stability verdict, which hapticbench
    computes (summary.json stability.verdict; harness/metrics/
    stability_verdict.h): the first failed check with its figure, or the
    figure behind a pass. (None, "no verdict") for a summary without one."""
    verdict = dig(run.summary, "stability", "verdict")
    if not isinstance(verdict, dict) or not isinstance(verdict.get("stable"), bool):
        return None, "no verdict"
    return verdict["stable"], str(verdict.get("reason") or "")


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
            + note("Each run of a scenario tagged <code>stress</code>, by algorithm label: "
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
            error = number_or_none(headline(run.summary))
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
                  "band's top): the large-signal search, full runs with the device's Coulomb "
                  "friction and encoder quantisation. Dashed: the small-signal limit, the same "
                  "loop linearised at the contact (hand, device, zero-order-held coupling, "
                  "filtered velocity; no friction, no quantisation), where the map has it. Between "
                  "the two, friction can hold the encoder's force staircase, so that small "
                  "oscillations die and a larger bounce grows. ▲: stable up to the range's top. "
                  "Criterion: %s"
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


def parameter_text(name, value):
    """"contact_stiffness 1000 N/m": a parameter with its unit where it has one."""
    unit = PARAMETER_UNITS.get(name)
    text = value_text(value, 40)
    return "%s %s%s" % (name, text, " " + unit if unit and finite_number(value) else "")


def scenario_parameters_html(folder):
    """What a scenario section says the run was: the scenario's description, the coupling
    (summary.json scenario.coupling) and each label's parameters (runs[].params: those the
    scenario sets; the others are the algorithm's defaults)."""
    parts = []
    described = scenario_description(folder)
    if described:
        parts.append('<p class="description">%s <span class="small">(<code>%s</code>)</span>'
                     "</p>" % (esc(described[0]), esc(described[1])))
    coupling = dig(folder.summary, "scenario", "coupling")
    if isinstance(coupling, dict) and coupling:
        order = ["k_t", "b_t", "k_r", "b_r"]
        names = sorted(coupling, key=lambda n: (order.index(n) if n in order else len(order), n))
        parts.append('<p class="small">Coupling: %s.</p>' % esc(", ".join(
            parameter_text(name, coupling[name]) for name in names)))
    rows = []
    for run in folder.runs:
        params = run.summary.get("params")
        if not isinstance(params, dict):
            continue
        text = ", ".join(parameter_text(name, value) for name, value in params.items())
        rows.append('<tr><td class="text">%s</td><td class="text">%s</td></tr>'
                    % (label_html(run), esc(text) if text else
                       '<span class="small">the algorithm\'s defaults</span>'))
    if rows:
        parts.append('<table class="parameters"><tr><th class="text">label (algorithm)</th>'
                     '<th class="text">parameters the scenario sets</th></tr>%s</table>'
                     % "".join(rows))
    return "".join(parts)


# The columns of a sweep's table per label: (header, cell of a run's summary).
SWEEP_COLUMNS = [
    ("force error RMS (N)",
     lambda s: cell(headline(s), "%.4g")),
    ("max penetration (mm)",
     lambda s: cell(dig(s, "accuracy", "penetration_max_m"), "%.3f", 1e3)),
    ("step p50 (µs)", lambda s: cell(dig(s, "timing", "step_ns", "p50"), "%.2f", 1e-3)),
    ("step p99 (µs)", lambda s: cell(dig(s, "timing", "step_ns", "p99"), "%.2f", 1e-3)),
    ("stability", lambda s: stability_item(s)[0]),
    ("budgets", lambda s: budget_items(s.get("budgets") or [])[0]),
]


def sweep_table_html(sweep, jobs):
    """One table across a sweep's jobs: a row per job in numeric order of its grid values
    (a job without a run folder shows its status), the values first, then per label the
    force error, max penetration, step time p50 and p99, stability verdict and budgets."""
    labels = list(dict.fromkeys(run.label for job in jobs for run in job.folder.runs))
    several = len({job.base for job in jobs}) > 1
    keys = sweep.keys
    head = ("<tr>%s%s%s</tr>" % (
        '<th class="text" rowspan="2">scenario</th>' if several else "",
        "".join('<th rowspan="2">%s</th>' % esc(parameter_label(key)) for key in keys),
        "".join('<th class="label" colspan="%d">%s</th>' % (len(SWEEP_COLUMNS), esc(label))
                for label in labels))
        + "<tr>%s</tr>" % "".join("<th>%s</th>" % esc(title) for _ in labels
                                  for title, _ in SWEEP_COLUMNS))
    rows = [(job.sort_key(), sweep_row(job.job, job.base, several, keys, "".join(
        sweep_label_cells(job, label) for label in labels))) for job in jobs]
    present = {job.job.get("name") for job in jobs}
    for job in missing_jobs(sweep, present):
        status = '<td class="text na" colspan="%d">no run folder: %s</td>' % (
            len(SWEEP_COLUMNS) * max(1, len(labels)), esc(job.get("status", "?")))
        base = os.path.splitext(os.path.basename(str(job.get("scenario"))))[0]
        rows.append((sweep.sort_key(job), sweep_row(job, base, several, keys, status)))
    return ('<div class="wide"><table class="summary sweep-table" data-sweep="%s">'
            "<thead>%s</thead><tbody>%s</tbody></table></div>"
            % (esc(sweep.name), head, "".join(row for _, row in sorted(rows,
                                                                       key=lambda r: r[0]))))


def sweep_row(job, base, several, keys, cells):
    values = job.get("grid") if isinstance(job.get("grid"), dict) else {}
    return ('<tr data-job="%s">%s%s%s</tr>'
            % (esc(job.get("name", "")),
               '<td class="text">%s</td>' % esc(base) if several else "",
               "".join('<td data-key="%s">%s</td>' % (esc(key_name(key)),
                                                      esc(value_text(values.get(key))))
                       for key in keys), cells))


def sweep_label_cells(job, label):
    run = next((r for r in job.folder.runs if r.label == label), None)
    if run is None:
        return '<td class="na">—</td>' * len(SWEEP_COLUMNS)
    return "".join(column(run.summary) for _, column in SWEEP_COLUMNS)
