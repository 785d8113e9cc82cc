"""Which run folders are jobs of a `hapticbench sweep`, found by the
sweep.json beside them (never by parsing folder names), and the order of
their grid values: numeric wherever the values are numbers (1000, 2000,
10000, not as text)."""
import functools
import json
import os

from .inputs import finite_number, read_json_or_none


class Sweep:
    """A sweep.json: its name, its folder, its grid (pointer -> values) and
    the keys it varies (those with two or more values, in the file's order;
    all keys when none varies)."""

    def __init__(self, parent, index):
        self.parent = parent
        self.name = str(index.get("name") or os.path.basename(parent))
        self.grid = {key: values for key, values in index["grid"].items()
                     if isinstance(values, list)}
        varied = [key for key, values in self.grid.items() if len(values) > 1]
        self.keys = varied or list(self.grid)
        self.scenarios = [str(s) for s in index.get("scenarios") or []]
        self.jobs = [job for job in index.get("jobs") or [] if isinstance(job, dict)]
        self.jobs_by_name = {job.get("name"): job for job in self.jobs}

    def values_of(self, job):
        """The job's value of each varied key."""
        grid = job.get("grid") if isinstance(job.get("grid"), dict) else {}
        return {key: grid.get(key) for key in self.keys}

    def sort_key(self, job):
        """Scenario in the sweep's order, then the grid values in numeric order."""
        scenario = str(job.get("scenario"))
        position = (self.scenarios.index(scenario) if scenario in self.scenarios
                    else len(self.scenarios))
        values = self.values_of(job)
        return (position,) + tuple(value_sort_key(values[key], self.grid.get(key, []))
                                   for key in self.keys)


class SweepJob:
    """One run folder that is a job of a sweep."""

    def __init__(self, sweep, job, folder):
        self.sweep = sweep
        self.job = job
        self.folder = folder
        self.values = sweep.values_of(job)
        self.base = base_scenario(job, folder)
        self.group = "%s (sweep %s)" % (self.base, sweep.name)

    def sort_key(self):
        return self.sweep.sort_key(self.job)

    def value_sort_key(self, key):
        return value_sort_key(self.values.get(key), self.sweep.grid.get(key, []))

    def describe(self, keys=None):
        """"contact_stiffness=1000, k_t=2000": the job's values of the keys given (all varied)."""
        return ", ".join("%s=%s" % (key_name(key), value_text(self.values.get(key)))
                         for key in (self.sweep.keys if keys is None else keys))


def base_scenario(job, folder):
    """The scenario file the job came from, without folder and extension."""
    scenario = job.get("scenario") or os.path.basename(str(folder.path))
    return os.path.splitext(os.path.basename(str(scenario)))[0]


@functools.lru_cache(maxsize=None)
def sweep_at(parent):
    """The Sweep of the sweep.json in a folder, or None without one."""
    index = read_json_or_none(os.path.join(parent, "sweep.json"))
    if not isinstance(index, dict) or not isinstance(index.get("grid"), dict):
        return None
    return Sweep(parent, index)


def sweep_job(folder):
    """The SweepJob of a run folder listed in the sweep.json beside it, else None."""
    if not getattr(folder, "path", None):
        return None
    parent, name = os.path.split(os.path.normpath(os.path.abspath(folder.path)))
    sweep = sweep_at(parent)
    job = sweep.jobs_by_name.get(name) if sweep else None
    return SweepJob(sweep, job, folder) if job else None


def sweep_jobs(folders):
    """{(sweep folder, sweep name): [SweepJob]} in numeric order, sweeps in order of first
    appearance."""
    sweeps = {}
    for folder in folders:
        job = sweep_job(folder)
        if job is not None:
            sweeps.setdefault((job.sweep.parent, job.sweep.name), []).append(job)
    return {key: sorted(jobs, key=SweepJob.sort_key) for key, jobs in sweeps.items()}


def numeric_folder_order(folders):
    """The folders with each sweep's jobs in numeric order of their grid values, at the
    place of the sweep's first job; every other folder keeps its place."""
    ordered = {key: iter(jobs) for key, jobs in sweep_jobs(folders).items()}
    result = []
    for folder in folders:
        job = sweep_job(folder)
        result.append(folder if job is None
                      else next(ordered[(job.sweep.parent, job.sweep.name)]).folder)
    return result


def missing_jobs(sweep, present):
    """The sweep's jobs without a run folder (pending, failed, crashed), in numeric order."""
    return sorted((job for job in sweep.jobs if job.get("name") not in present
                   and job.get("status") not in ("ok", "budget_failed")), key=sweep.sort_key)


def value_sort_key(value, listed=()):
    """Numbers by value, before any other value, which keeps its place in the grid's list."""
    if finite_number(value):
        return (0, float(value), 0)
    position = listed.index(value) if value in listed else len(listed)
    return (1, float(position), value_text(value))


def is_numeric_key(jobs, key):
    return all(finite_number(job.values.get(key)) for job in jobs)


def spans_more_than_a_decade(values):
    return bool(values) and min(values) > 0 and max(values) > 10 * min(values)


def key_name(pointer):
    """The last component of a JSON pointer: what a job name calls the key."""
    return pointer.rstrip("/").split("/")[-1].replace("~1", "/").replace("~0", "~")


def value_text(value, width=28):
    """A grid value as people write it: 5000, 0.03, voxmap; long arrays and objects cut."""
    if finite_number(value):
        return "%d" % value if float(value).is_integer() and abs(value) < 1e15 else "%g" % value
    text = value if isinstance(value, str) else json.dumps(value, separators=(",", ":"))
    return text if len(text) <= width else text[:width - 1] + "…"
