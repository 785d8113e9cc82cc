#!/usr/bin/env python3
"""Renders hapticbench run folders into one self-contained HTML report.

usage: render_report.py --out REPORT.html [--template FILE] [--history DIR] RUN_FOLDER...

Each RUN_FOLDER holds a summary.json (schema_version 1) and, unless it is a
summary-only baseline, one ticks_<label>.csv per algorithm label. The page
leads with a verdict card per algorithm label and the best label by accuracy
and by cost per scenario, then has a summary table per scenario and label,
error against tick time (Pareto front) per scenario, each sweep's jobs as a
sweep (one panel per base scenario, metrics against the swept values, a
table across the jobs, in numeric order), passivity and stiffness-sweep
stability figures, and per scenario its description and parameters, a
picture of the scene with the device's path (when summary.json has
scenario.outline), in closed loop the device against the operator's intent
(intent.csv), the displayed force and torque against time (with the
analytic or mesh force reference when there is one), penetration against
time (with each oracle backend's column when present) and the distribution
of step times.

With --history DIR (a history folder of `hapticbench history add`: history.json
and the summaries of each stored commit) a History section follows the
verdict: the first commit where each scenario's, label's and metric's value
moved beyond its tolerance, and per scenario its metrics across the commits.
Run folders are optional then: without them the page is the history alone.

Every figure is an inline PNG, the style sheet is inline and the only script
is a few lines that count the decoded figures: the file opens offline.
`hapticbench report` calls this script; it checks the run folders first.

Exit codes: 0 written, 2 bad input (the message names the file and where).
"""
import os
import sys

# The package beside this script, wherever it is run from.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hapticbench_report.page import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
