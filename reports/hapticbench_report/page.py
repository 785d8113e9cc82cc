"""The page: the verdict it leads with, the summary, the error-against-cost
figure, the sweeps, the stability sections and one section per scenario,
put into the template; and the command line of render_report.py."""
import argparse
import datetime
import json
import os
import re
import string
import sys

from .inputs import (
    Progress, ReportInputError, dig, load_run_folder, read_stability_result, read_zwidth_result,
    reference_wording, use_headline_metrics)
from .figures import (
    LABEL_COLOURS, history_figure, intent_figure, pareto_figure, parameter_label,
    passivity_figure, penetration_figure, scene_figure, stiffness_limits, stiffness_sweeps,
    stiffness_text, sweep_figure, sweep_metrics_figure, timing_figure, wrench_figure)
from .history import (
    INSTRUCTIONS_SHARE, RELATIVE_TOLERANCE, STEP_TIME_RATIO, read_history, value_text as
    history_value_text)
from .sweeps import key_name, numeric_folder_order, sweep_jobs, value_text
from .tables import (
    context_html, esc, figure_html, folders_html, friction_html, metric_table_html, note,
    scenario_parameters_html, stability_margins_html, stress_matrix_html, summary_table,
    sweep_file_verdict, sweep_table_html, work_counters_html, zwidth_html)
from .verdicts import verdicts_html


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
    parts.append(scenario_parameters_html(folder))
    parts.append(scene_html(folder))
    parts.append(intent_html(folder))
    missing = [run for run in runs if run.ticks is None]
    if missing:
        parts.append(note("No ticks CSV for %s (a summary-only run folder): no time series for "
                          "%s." % (", ".join("<code>%s</code>" % esc(os.path.basename(r.ticks_path))
                                             for r in missing),
                                   "this scenario" if len(missing) == len(runs)
                                   else "these labels")))
    if len(missing) < len(runs):
        for kind, shown in (("force", "Displayed force (world frame) per label"),
                            ("torque", "Displayed torque about the tool frame's origin "
                                       "(world frame)")):
            # The ticks' ref_* columns: the analytic reference where its
            # closed forms cover the scene, else the mesh force reference.
            uri, reference = wrench_figure(runs, kind)
            parts.append(figure_html(
                "fig-%s-%s" % (kind, folder.slug), uri, "%s against time, %s"
                % (kind, folder.scenario),
                shown + (", dashed: the ideal rigid contact (the %s)." % esc(reference)
                         if reference else "; no force reference for this scene.")))
        uri = penetration_figure(runs)
        if uri:
            parts.append(figure_html(
                "fig-penetration-" + folder.slug, uri, "penetration against time, "
                + folder.scenario, "Penetration of the proxy's tool: <code>penetration_m</code> "
                "(%s), and where present each oracle backend's own " % penetration_source(runs)
                + "column <code>&lt;backend&gt;_pen_m</code> (in the order of the summary's "
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


def scene_html(folder):
    """The scene figure when summary.json has scenario.outline (older summaries: none)."""
    outline = dig(folder.summary, "scenario", "outline")
    if not isinstance(outline, dict):
        return ""
    uri, facts = scene_figure(outline, folder.runs)
    if uri is None:
        return ""
    caption = ["Where the trace goes: the side (x–z) and top (x–y) views of the scene in mm, "
               "equal scales, each scene object as its world-frame bounds (a sphere as a "
               "circle, a capsule as a rounded rectangle, a mesh or a box with a hole as its "
               "bounding rectangle; dashed: distance only)."]
    if facts["path_label"] is not None:
        caption.append(
            " The line is the device's tool-frame origin (<code>dev_p*</code> of "
            "<code>%s</code>'s ticks), from the circle to the square; the tool's bounds are "
            "drawn dotted at the start and solid at the deepest point (lowest z, the "
            "triangle)%s." % (esc(facts["path_label"]),
                              ", turned as the device holds it (the outline of its bounds' "
                              "corners)" if facts["rotated"] else ""))
        if getattr(folder, "intent", None) is not None:
            caption.append(" In closed loop each label's device takes its own path (the "
                           "next figure): this one is the first label's.")
    else:
        caption.append(" No ticks with the device's position: the scene alone.")
    if facts["zoomed"]:
        caption.append(" Zoomed to the motion with a margin: the scene spans %s mm."
                       % " × ".join("%.0f" % v for v in facts["scene_extent_mm"]))
    return figure_html("fig-scene-" + folder.slug, uri, "the scene and the device's path, "
                       + folder.scenario, "".join(caption))


def intent_html(folder):
    """In closed loop (intent.csv in the run folder): each label's device against the
    operator's intent."""
    intent = getattr(folder, "intent", None)
    if intent is None:
        return ""
    uri = intent_figure(intent, folder.runs)
    if uri is None:
        return note("Closed loop, but no ticks with the device's position "
                    "(<code>dev_pz</code>): no figure of the device against the intent.")
    return figure_html(
        "fig-intent-" + folder.slug, uri, "the device against the intent, " + folder.scenario,
        "Closed loop: the operator's intent (dashed, the trace, <code>intent.csv</code>), "
        "each label's device (thick) and its proxy (thin) along z in mm against time; below, "
        "how far each device departs from the intent (device z − intent z). In free space "
        "the hand's spring–damper keeps the device near the intent; in contact the "
        "displayed force pushes it back against the hand (<code>docs/closed-loop.md</code>).")


def penetration_source(runs):
    """Where penetration_m comes from, by the summary's accuracy.penetration_source."""
    sources = sorted({str(dig(run.summary, "accuracy", "penetration_source"))
                      for run in runs if dig(run.summary, "accuracy", "penetration_source")})
    return ("from " + " and ".join("the analytic reference" if s == "analytic"
                                   else "the %s oracle" % esc(s) for s in sources)
            if sources else "the analytic reference, else the primary oracle")


def metric_description(metric_table, pointer):
    """The metric table's own definition of the metric at `pointer` in a summary's run
    (hapticbench list --metrics), so that a caption never keeps a second, older copy."""
    for metric in metric_table or []:
        if metric.get("pointer") == pointer:
            return metric.get("description") or pointer
    return pointer


def stability_html(folders, runs, metric_table=()):
    parts = []
    uri, shown, without = passivity_figure(runs)
    if uri:
        parts.append(figure_html(
            "fig-passivity", uri, "passivity energy minimum per run",
            "<code>passivity_energy_min_mj</code> per run: the "
            + esc(metric_description(metric_table, "/stability/passivity_energy_min_j"))
            + " (red: below zero; diverged runs are marked)."
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
                parts.append(note("<code>%s</code> (written by scripts/stability-sweep from the "
                                  "same verdicts, with explicit Euler's closed-form bound): %s."
                                  % (esc(path), verdicts)))
        parts.append(figure_html(
            "fig-stiffness-sweep-%d" % index, sweep_figure(by_integrator, bound),
            "stability against coupling stiffness, " + base,
            "Largest proxy separation from the device per run against the coupling stiffness "
            "(crosses: diverged); dotted: each integrator's largest stable k_t."))
    return "".join(parts)


def sweeps_html(folders):
    """Per sweep: per base scenario and grid key, the metrics against the swept value, then
    one table across the sweep's jobs; '' without a sweep."""
    parts = []
    for index, jobs in enumerate(sweep_jobs(folders).values()):
        sweep = jobs[0].sweep
        parts.append("<h3 id='sweep-%d'>Sweep %s</h3>" % (index, esc(sweep.name)))
        parts.append('<p class="small">Grid: %s. Jobs in numeric order of their values.</p>'
                     % "; ".join("%s: %s" % (esc(parameter_label(key)), esc(", ".join(
                         value_text(v) for v in sweep.grid[key]))) for key in sweep.keys))
        bases = {}
        for job in jobs:
            bases.setdefault(job.base, []).append(job)
        for base, base_jobs in bases.items():
            for key in sweep.keys:
                if len({value_text(job.values.get(key)) for job in base_jobs}) < 2:
                    continue
                parts.append(figure_html(
                    "fig-sweep-%d-%s-%s" % (index, slug_text(base), slug_text(key_name(key))),
                    sweep_metrics_figure(base_jobs, key),
                    "metrics against %s, %s" % (key_name(key), base),
                    "%s: force error RMS, max penetration and step time p99 against %s, a line "
                    "per label%s." % (esc(base_jobs[0].group), esc(parameter_label(key)),
                                      " and per combination of the other keys' values "
                                      "(line style)" if len(sweep.keys) > 1 else "")))
        parts.append(sweep_table_html(sweep, jobs))
    if not parts:
        return ""
    return ('<section id="sweeps"><h2>Sweeps</h2>%s</section>' % "".join(parts))


def history_html(history):
    """The history section: the first move of every series that moved (scenario, label,
    metric, the commit where it moved, from → to, worse or better), then per scenario one
    figure of its metrics across the entries."""
    entries = history.entries
    parts = ['<section id="history"><h2>History</h2>',
             '<p class="small">History <code>%s</code>: %d commit%s%s, oldest first.</p>'
             % (esc(history.path), len(entries), "" if len(entries) == 1 else "s",
                " (%s … %s)" % (esc(entries[0].short_commit), esc(entries[-1].short_commit))
                if entries else "")]
    if not history.series:
        parts.append(note("The history holds no results yet (<code>hapticbench history add"
                          "</code> stores run folders in it)."))
        parts.append("</section>")
        return "".join(parts)
    moves = history.first_moves()
    if moves:
        rows = "".join(
            '<tr class="%s" data-scenario="%s" data-label="%s" data-metric="%s" '
            'data-commit="%s" data-direction="%s"><td class="text">%s</td>'
            '<td class="text">%s</td><td class="text">%s</td>'
            '<td class="text"><code title="%s">%s</code> %s</td><td>%s → %s</td>'
            '<td class="text %s" title="%s">%s</td></tr>'
            % ("history-move", esc(m.scenario), esc(m.label), esc(m.metric.key),
               esc(m.entry.commit), m.direction, esc(m.scenario), esc(m.label),
               esc(m.metric.heading()), esc(m.entry.commit), esc(m.entry.short_commit),
               '<span class="small">(#%d%s)</span>' % (
                   m.entry.index + 1, ", " + esc(m.entry.date) if m.entry.date else ""),
               esc(history_value_text(m.metric, m.before.value)),
               esc(history_value_text(m.metric, m.after.value)),
               "fail" if m.direction == "worse" else "pass", esc(m.why), m.direction)
            for m in moves)
        parts.append('<table class="history-moves"><tr><th class="text">scenario</th>'
                     '<th class="text">label</th><th class="text">metric</th>'
                     '<th class="text">moved at commit</th><th>from → to</th>'
                     '<th class="text">direction</th></tr>%s</table>' % rows)
    else:
        parts.append('<p class="pass">No metric moved beyond its tolerance across the %d '
                     "commits.</p>" % len(entries))
    parts.append(
        '<p class="small">A move: a change from the last earlier commit that measured the '
        "metric beyond max(abs_tol, %g × |previous|) for force error RMS and max penetration "
        "(abs_tol from the summary's metric table, as <code>hapticbench compare</code>), a "
        "step time p99 ratio beyond ×%g either way (wall clock: noisy), instructions per step "
        "beyond %g %%, or a change of the stability verdict. Worse or better by the metric "
        "table's <code>better</code>. Only the first move of each scenario, label and metric "
        "is listed.</p>" % (RELATIVE_TOLERANCE, STEP_TIME_RATIO, 100 * INSTRUCTIONS_SHARE))
    for scenario in history.series:
        uri = history_figure(history, scenario, moves)
        if uri:
            parts.append(figure_html(
                "fig-history-" + slug_text(scenario), uri, "metrics across commits, " + scenario,
                "%s: force error RMS, max penetration, step time p99 and, where counted, "
                "instructions per step at each stored commit, a line per label (gaps: the "
                "label was not run); red crosses: the run was unstable; black rings: the "
                "first move." % esc(scenario)))
        else:
            parts.append(note("%s: none of the history's metrics was measured."
                              % esc(scenario)))
    parts.append("</section>")
    return "".join(parts)


def slug_text(text):
    return re.sub(r"[^A-Za-z0-9_-]+", "-", text)


def render(folders, template, metric_table, stability_results=(), progress=Progress(),
           zwidth_results=(), history=None):
    folders = numeric_folder_order(folders)
    LABEL_COLOURS.reset(run.label for folder in folders for run in folder.runs)
    history_section = ""
    if history is not None:
        for label in history.labels():
            LABEL_COLOURS.colour(label)
        progress.step("drawing the history")
        history_section = history_html(history)
        if not folders:
            body = ["<header><h1>hapticbench report</h1>",
                    '<p class="small">History across commits; generated %s.</p></header>'
                    % generated_at(), history_section]
            return string.Template(template).substitute(title="hapticbench report",
                                                        body="\n".join(body))
    slugs = set()
    for folder in folders:
        slug = "scenario-" + slug_text(folder.scenario)
        candidate, n = slug, 2
        while candidate in slugs:
            candidate, n = "%s-%d" % (slug, n), n + 1
        slugs.add(candidate)
        folder.slug = candidate
    runs = [run for folder in folders for run in folder.runs]
    failed = [run for run in runs if any(b.get("pass") is not True
                                         for b in run.summary.get("budgets") or [])]
    unstable = [run for run in runs
                if dig(run.summary, "stability", "verdict", "pass") is False]
    body = ["<header><h1>hapticbench report</h1>",
            '<p class="small">%d scenario%s, %d run%s; generated %s.</p>'
            % (len(folders), "" if len(folders) == 1 else "s", len(runs),
               "" if len(runs) == 1 else "s", generated_at()),
            context_html(folders),
            "<details%s><summary>Run folders covered (%d)</summary>%s</details></header>"
            % (" open" if len(folders) <= 12 else "", len(folders), folders_html(folders))]
    sweeps = sweeps_html(folders)
    body.append("<nav><h2>Contents</h2><ul><li><a href='#verdicts'>Verdict</a></li>%s"
                "<li><a href='#summary'>Summary</a></li>"
                "<li><a href='#pareto'>Error against CPU time per tick</a></li>%s"
                "<li><a href='#stability'>Stability</a></li>%s</ul></nav>"
                % ("<li><a href='#history'>History</a></li>" if history_section else "",
                   "<li><a href='#sweeps'>Sweeps</a></li>" if sweeps else "",
                   "".join("<li><a href='#%s'>%s</a></li>" % (f.slug, esc(f.scenario))
                           for f in folders)))
    body.append(verdicts_html(runs))
    body.append(history_section)
    body.append('<section id="summary"><h2>Summary</h2>')
    problems = []
    if unstable:
        problems.append("%d of %d runs are unstable where that is not expected: %s."
                        % (len(unstable), len(runs),
                           ", ".join("%s (%s)" % (esc(r.name), esc(dig(
                               r.summary, "stability", "verdict", "reason") or "?"))
                                     for r in unstable)))
    if failed:
        problems.append("%d of %d runs failed a budget: %s."
                        % (len(failed), len(runs), ", ".join(esc(r.name) for r in failed)))
    body.append('<p class="%s">%s</p>' % (
        "fail" if problems else "pass",
        " ".join(problems) if problems
        else "All %d runs are stable (or unstable where the scenario expects it) and within "
             "their budgets." % len(runs)))
    warnings = [(folder.scenario, text) for folder in folders
                for text in folder.summary.get("warnings") or []]
    if warnings:
        body.append('<div class="warn"><p>%d warning%s: what a run may not measure as it seems '
                    'to.</p><ul>%s</ul></div>'
                    % (len(warnings), "" if len(warnings) == 1 else "s",
                       "".join("<li>%s: %s</li>" % (esc(name), esc(text))
                               for name, text in warnings)))
    body.append(summary_table(folders, metric_table))
    body.append('<p class="small">Columns come from the metric table '
                "(<code>hapticbench list --metrics</code>; hover a header for its definition). "
                "Step times are of <code>Renderer::step</code> only; CPU per tick adds the "
                "slow-loop work attributed to the tick. Force and direction errors are against "
                "%s (ideal rigid contact); penetration comes from the analytic reference, else "
                "the Embree oracle. <span class='tag'>baseline</span>: renders no contact (the "
                "coupling alone), to compare with; never ranked. "
                "— : the metric does not apply to the run.</p></section>"
                % reference_wording(runs))
    body.append('<section id="pareto"><h2>Error against CPU time per tick</h2>')
    progress.step("drawing the summary figures")
    uri, fronts, left_out, failed = pareto_figure(runs)
    if uri:
        on_front = "; ".join("%s: %s" % (scenario, ", ".join(labels))
                             for scenario, labels in fronts.items())
        body.append(figure_html(
            "fig-pareto", uri, "error against CPU time per tick p99, one panel per scenario",
            "One panel per scenario (errors of different scenarios are not comparable; a "
            "sweep's jobs share their base scenario's panel, coloured by the swept value, a "
            "marker per label, each label's points joined in order of the value): force "
            "error RMS against %s (with the scene's Coulomb friction; without a reference, the "
            "maximum penetration) against the p99 CPU time per tick of both loops, the haptic "
            "step "
            "plus the slow-loop work attributed to the tick (timing.cpu_per_tick_ns), so that "
            "an algorithm whose work sits in its slow loop is not shown as free. The red line "
            "is each scenario's Pareto front: no other run of that scenario is both cheaper "
            "and more accurate; a baseline that renders no contact (grey) is never on it. On "
            "the fronts: %s." % (esc(reference_wording(runs)), esc(on_front))))
    if failed:
        body.append(note("Drawn hollow and never on a front, because their error says nothing "
                         "about the algorithm's accuracy: %s." % esc(", ".join(
                             "%s (%s)" % (run.name, why) for run, why in failed))))
    if left_out:
        body.append(note("Not on the figure (no force error, no penetration or no step time): "
                         "%s." % esc(", ".join(r.name for r in left_out))))
    body.append("</section>")
    body.append(sweeps)
    body.append('<section id="stability"><h2>Stability</h2>')
    body.append(stress_matrix_html(folders))
    body.append(stability_margins_html(list(stability_results)))
    body.append(zwidth_html(list(zwidth_results)))
    body.append(stability_html(folders, runs, metric_table))
    body.append(friction_html(folders))
    body.append("</section><section id='scenarios'><h2>Scenarios</h2>")
    for done, folder in enumerate(folders):
        progress.step("drawing the scenarios' figures", done, len(folders), "scenarios")
        body.append(scenario_section(folder))
    body.append("</section>")
    return string.Template(template).substitute(title="hapticbench report", body="\n".join(body))


def generated_at():
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


def main():
    parser = argparse.ArgumentParser(
        description="Renders hapticbench run folders into one self-contained HTML report.")
    parser.add_argument("--out", required=True, help="HTML file to write")
    parser.add_argument("--template", default=os.path.join(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__))), "report_template.html"))
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
    parser.add_argument("--history", help="a history folder of `hapticbench history add` "
                        "(history.json and the summaries it lists): each metric across the "
                        "stored commits and the first commit where it moved; without run "
                        "folders the page holds that view alone")
    parser.add_argument("folders", nargs="*", help="run folders (each with a summary.json)")
    args = parser.parse_args()
    progress = Progress(args.progress_fd)
    try:
        history = None
        if args.history:
            progress.step("reading the history")
            history = read_history(args.history)
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
        use_headline_metrics(metric_table)
        with open(args.template, encoding="utf-8") as f:
            template = f.read()
        stability_results = [(path, read_stability_result(path)) for path in args.stability]
        zwidth_results = [(path, read_zwidth_result(path)) for path in args.zwidth]
        page = render(folders, template, metric_table, stability_results, progress,
                      zwidth_results, history)
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
