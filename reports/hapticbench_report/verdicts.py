"""The answer the page leads with: a card per algorithm label (stable or not,
force error, penetration, step time against the 1 ms tick, failed budgets)
and the best label by accuracy and by cost in each scenario."""
from .inputs import dig, finite_number, headline, is_baseline
from .figures import LABEL_COLOURS, ONE_MS_US, verdict_stable
from .sweeps import sweep_job
from .tables import budget_text, esc, fmt


def label_runs(runs):
    """{label: [runs]} in order of first appearance."""
    by_label = {}
    for run in runs:
        by_label.setdefault(run.label, []).append(run)
    return by_label


def stability_state(runs):
    """("unstable" | "expected" | "stable" | "no verdict", unstable runs): unstable where any
    run is unstable unexpectedly, "expected" where every unstable run is expected to be."""
    verdicts = [dig(run.summary, "stability", "verdict") or {} for run in runs]
    unstable = [run for run, v in zip(runs, verdicts) if v.get("stable") is False]
    if any(not dig(run.summary, "stability", "verdict", "expected_unstable") for run in unstable):
        return "unstable", unstable
    if unstable:
        return "expected", unstable
    if all(v.get("stable") is True for v in verdicts):
        return "stable", []
    return "no verdict", []


def worst(runs, value_of):
    values = [value_of(run) for run in runs if finite_number(value_of(run))]
    return max(values) if values else None


def force_error(run):
    return headline(run.summary)


def penetration_mm(run):
    value = dig(run.summary, "accuracy", "penetration_max_m")
    return value * 1e3 if finite_number(value) else None


def comparison_group(run):
    """Runs are ranked against the runs of their own scenario (a sweep: of its base
    scenario), never across scenarios."""
    job = sweep_job(run.folder)
    return job.group if job else run.folder.scenario


def run_name(run):
    job = sweep_job(run.folder)
    return "%s at %s" % (run.label, job.describe()) if job else run.label


def best_runs(runs):
    """Per scenario, (best by accuracy, best by cost) among the runs that render contact and
    are stable: the lowest force error RMS and the lowest step time p99 (None where no run
    qualifies). {scenario: (run or None, run or None)}."""
    groups = {}
    for run in runs:
        groups.setdefault(comparison_group(run), [])
        if not is_baseline(run) and verdict_stable(run) is True:
            groups[comparison_group(run)].append(run)
    return {group: (lowest(candidates, force_error), lowest(candidates, lambda r: r.p99_us()))
            for group, candidates in groups.items()}


def lowest(runs, value_of):
    measured = [run for run in runs if finite_number(value_of(run))]
    return min(measured, key=value_of) if measured else None


STATE_BADGES = {"stable": ("pass", "stable"), "unstable": ("fail", "unstable"),
                "expected": ("warn", "unstable, as expected"), "no verdict": ("na", "no verdict")}


def verdict_card(label, runs):
    state, unstable = stability_state(runs)
    css, text = STATE_BADGES[state]
    if unstable and len(runs) > 1:
        text += " (%d of %d runs)" % (len(unstable), len(runs))
    why = "; ".join("%s: %s" % (r.name, dig(r.summary, "stability", "verdict", "reason") or "?")
                    for r in unstable)
    algorithm = runs[0].summary.get("algorithm", "?")
    p99 = worst(runs, lambda r: r.p99_us())
    failed = [(run, b) for run in runs for b in run.summary.get("budgets") or []
              if b.get("pass") is not True]
    scope = "" if len(runs) == 1 else ' <span class="small">worst of %d runs</span>' % len(runs)
    rows = [("force error RMS", fmt(worst(runs, force_error), "%.4g", 1.0), "N"),
            ("max penetration", fmt(worst(runs, penetration_mm), "%.3f"), "mm"),
            ("step p99", fmt(p99, "%.2f"), "µs")]
    items = "".join("<dt>%s</dt><dd>%s</dd>" % (name, "%s %s" % (value, unit) if value else "—")
                    for name, value, unit in rows)
    tick = ('<span class="%s">%s 1 ms tick</span>' % (("pass", "within the") if p99 <= ONE_MS_US
                                                     else ("fail", "over the"))
            if p99 is not None else "")
    budgets = ('<span class="fail">✗ %s</span>' % esc("; ".join(
        "%s (%s)" % (budget_text(b), run.folder.scenario) for run, b in failed)) if failed
        else "all pass" if any(run.summary.get("budgets") for run in runs) else "none")
    return ('<div class="card" data-label="%s" data-state="%s">'
            '<h4><span class="swatch" style="background:%s"></span>%s%s%s</h4>'
            '<p class="badge %s" title="%s">%s</p><dl>%s<dt>budgets</dt><dd>%s</dd></dl>%s%s</div>'
            % (esc(label), state, LABEL_COLOURS.hex(label), esc(label),
               ' <span class="small">(%s)</span>' % esc(algorithm) if algorithm != label else "",
               ' <span class="tag">baseline</span>' if is_baseline(runs[0]) else "",
               css, esc(why), esc(text), items, budgets, tick, scope))


def best_html(runs):
    """The best label by accuracy and by cost, per scenario."""
    rows = []
    for group, (accurate, cheap) in best_runs(runs).items():
        rows.append('<tr data-scenario="%s"><td class="text">%s</td>%s%s</tr>'
                    % (esc(group), esc(group),
                       best_cell(accurate, "best-accuracy", force_error, "%.4g N"),
                       best_cell(cheap, "best-cost", lambda r: r.p99_us(), "%.2f µs")))
    return ('<table class="best"><tr><th class="text">scenario</th>'
            '<th class="text">best by accuracy (lowest force error RMS)</th>'
            '<th class="text">best by cost (lowest step p99)</th></tr>%s</table>'
            % "".join(rows))


def best_cell(run, css, value_of, pattern):
    if run is None:
        return '<td class="na %s">no stable run that renders contact</td>' % css
    return ('<td class="text %s" data-label="%s">%s <span class="small">%s</span></td>'
            % (css, esc(run.label), esc(run_name(run)), esc(pattern % value_of(run))))


def verdicts_html(runs):
    """The cards, one per label across the page's runs, then the best labels."""
    if not runs:
        return ""
    cards = "".join(verdict_card(label, group) for label, group in label_runs(runs).items())
    return ('<section id="verdicts"><h2>Verdict</h2><div class="cards">%s</div>%s'
            '<p class="small">Stable: every run\'s stability verdict '
            "(<code>stability.verdict</code>); “as expected”: the scenario expects the "
            "instability. Values are a label's worst over its runs. The best labels are ranked "
            "within each scenario (a sweep: its base scenario) among the runs that are stable "
            "and render contact; a baseline that renders no contact is never ranked.</p>"
            "</section>" % (cards, best_html(runs)))
