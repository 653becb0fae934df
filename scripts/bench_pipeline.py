"""Job time of the last Snakemake build, by rule group, with its critical path and wall time.

    python scripts/bench_pipeline.py [--results results] [--workdir .] [--jobs]

Reads (nothing is written):

* Snakemake's newest log, ``<workdir>/.snakemake/log/*.snakemake.log``: the build's start (its
  ``Date:`` header) and end (the last ``[timestamp]``), i.e. the wall time, and the rules it ran
  (``Finished jobid: N (Rule: name)``);
* Snakemake's metadata, ``<workdir>/.snakemake/metadata/*``: for every output file the rule,
  the inputs, the log files and the job's start and end time. The jobs of the last build are
  those that started in the log's time window (one job per rule and job hash);
* the benchmark files ``<results>/benchmarks/<name>.tsv`` (every rule writes one, named as its
  log ``<results>/logs/<name>.log``): the job time (``s``) and CPU time (``cpu_time``) of each
  job; a job without one counts its metadata end minus start time.

Prints the job time by rule group (:data:`GROUPS`), the critical path (the chain of jobs, each
needing an output of the previous one, with the largest sum of job times: the wall time with
unlimited cores) and the wall time. On a shared machine the job times grow with the load; the
CPU times do not (the table shows both, and the jobs' mean CPU use Snakemake recorded).
"""

from __future__ import annotations

import argparse
import base64
import csv
import json
import re
from dataclasses import dataclass, field
from datetime import datetime
from pathlib import Path

from pedalrepro import paths

#: Rule name prefix -> group (first match wins).
GROUPS: tuple[tuple[str, str], ...] = (
    ("nonlinear_codegen", "derivation (once)"), ("nonlinear_time", "NT/NP sweeps"),
    ("nonlinear_calibration", "calibration"), ("periodic_map", "periodic maps"),
    ("periodic_branch", "periodic branches"), ("periodic_tables", "periodic tables"),
    ("periodic_map_subgrid", "periodic maps"), ("figures_periodic", "periodic figures"),
    ("figures_", "figures"),
    ("linear_figure_data", "figures"), ("validation_figure_data", "figures"),
    ("book", "book"), ("mathjax", "book"), ("write_config", "book"),
    ("nonlinear_", "nonlinear (other)"), ("linear_", "linear"), ("section2_", "section 2"),
    ("mocap_", "validation data"), ("validation_", "validation data"),
    ("own_bicycle", "own bicycle"), ("reproduction_report", "report"))

_STAMP = re.compile(r"^\[(\w{3} \w{3} +\d+ \d\d:\d\d:\d\d \d{4})\]$")
_DATE = re.compile(r"^\s*Date: (\d{4}-\d\d-\d\d \d\d:\d\d:\d\d)")
_FINISHED = re.compile(r"Finished jobid: \d+ \(Rule: ([\w-]+)\)")


def group_of(rule: str) -> str:
    """The rule group of ``rule`` (:data:`GROUPS`; the rule itself when none matches)."""
    for prefix, group in GROUPS:
        if rule.startswith(prefix):
            return group
    return rule


@dataclass
class Job:
    rule: str
    start: float
    end: float
    outputs: list[str] = field(default_factory=list)
    inputs: list[str] = field(default_factory=list)
    logs: list[str] = field(default_factory=list)
    seconds: float = 0.0
    cpu_s: float = float("nan")
    load: float = float("nan")
    benchmark: str = ""

    @property
    def name(self) -> str:
        return Path(self.benchmark or (self.logs[0] if self.logs else self.rule)).stem


@dataclass
class Build:
    log: Path
    start: float
    end: float
    rules: list[str]
    jobs: list[Job]

    @property
    def wall_s(self) -> float:
        return self.end - self.start


def parse_log(path: Path) -> tuple[float, float, list[str]]:
    """Start and end (epoch seconds, local time as Snakemake prints it) and the finished rules of
    one Snakemake log."""
    start = end = None
    rules = []
    for line in path.read_text(errors="replace").splitlines():
        if start is None and (m := _DATE.match(line)):
            start = datetime.strptime(m.group(1), "%Y-%m-%d %H:%M:%S").timestamp()
        if m := _STAMP.match(line.strip()):
            t = datetime.strptime(" ".join(m.group(1).split()), "%a %b %d %H:%M:%S %Y").timestamp()
            start = t if start is None else start
            end = t
        if m := _FINISHED.search(line):
            rules.append(m.group(1))
    if start is None or end is None:
        raise ValueError(f"{path}: not a Snakemake log (no Date: header or [timestamp] lines)")
    return start, end, rules


def read_benchmark(path: Path) -> dict[str, float] | None:
    """The last row of a Snakemake benchmark file as numbers (None: missing or garbled)."""
    try:
        rows = list(csv.DictReader(path.open(), delimiter="\t"))
        row = rows[-1]
        return {k: float(v) for k, v in row.items() if k != "h:m:s" and v not in (None, "", "NA")}
    except (OSError, IndexError, ValueError, KeyError):
        return None


def last_build(workdir: Path, results: Path, log: Path | None = None) -> Build:
    """The newest Snakemake run of ``workdir`` (or the run of Snakemake log ``log``): its jobs
    with their job times."""
    if log is None:
        logs = sorted((workdir / ".snakemake" / "log").glob("*.snakemake.log"))
        if not logs:
            raise FileNotFoundError(f"no Snakemake log in {workdir / '.snakemake' / 'log'}")
        log = logs[-1]
    start, end, rules = parse_log(log)
    jobs: dict[tuple, Job] = {}
    meta = workdir / ".snakemake" / "metadata"
    for f in sorted(meta.iterdir()) if meta.is_dir() else []:
        try:
            rec = json.loads(f.read_text())
            out = base64.b64decode(f.name.replace("@", "/")).decode()
        except (ValueError, UnicodeDecodeError, OSError):
            continue
        t0, t1 = rec.get("starttime"), rec.get("endtime")
        if t0 is None or t1 is None or not (start - 1 <= t0 <= end + 1):
            continue
        # one job per log file (every rule logs); the outputs of one job share it
        key = (rec.get("rule"), tuple(sorted(rec.get("log") or [])) or rec.get("job_hash"))
        job = jobs.setdefault(key, Job(rec.get("rule", "?"), float(t0), float(t1),
                                       inputs=list(rec.get("input") or []),
                                       logs=list(rec.get("log") or [])))
        job.outputs.append(out)
    bench_dir = paths.benchmarks(results)
    for job in jobs.values():
        job.seconds = job.end - job.start
        for log_file in job.logs:
            b = bench_dir / (Path(log_file).stem + ".tsv")
            row = read_benchmark(b)
            if row is not None and "s" in row:
                job.benchmark = str(b)
                job.seconds = row["s"]
                job.cpu_s = row.get("cpu_time", float("nan"))
                job.load = row.get("mean_load", float("nan"))
                break
    return Build(log, start, end, rules, sorted(jobs.values(), key=lambda j: j.start))


def critical_path(jobs: list[Job]) -> list[Job]:
    """The chain of jobs (each reading an output of the one before) with the largest total job
    time."""
    producer = {o: j for j in jobs for o in j.outputs}
    best: dict[int, tuple[float, list[Job]]] = {}

    def longest(job: Job) -> tuple[float, list[Job]]:
        if id(job) in best:
            return best[id(job)]
        parents = {id(producer[i]): producer[i] for i in job.inputs
                   if i in producer and producer[i] is not job}
        prev = max((longest(p) for p in parents.values()), key=lambda x: x[0],
                   default=(0.0, []))
        best[id(job)] = (prev[0] + job.seconds, prev[1] + [job])
        return best[id(job)]

    return max((longest(j) for j in jobs), key=lambda x: x[0], default=(0.0, []))[1]


def table(build: Build) -> list[dict]:
    """Rows ``group, jobs, job_s, cpu_s, share_pct`` sorted by job time."""
    groups: dict[str, dict] = {}
    for j in build.jobs:
        g = groups.setdefault(group_of(j.rule), {"group": group_of(j.rule), "jobs": 0,
                                                 "job_s": 0.0, "cpu_s": 0.0})
        g["jobs"] += 1
        g["job_s"] += j.seconds
        g["cpu_s"] += j.cpu_s if j.cpu_s == j.cpu_s else 0.0
    total = sum(g["job_s"] for g in groups.values()) or 1.0
    for g in groups.values():
        g["share_pct"] = 100.0 * g["job_s"] / total
    return sorted(groups.values(), key=lambda g: -g["job_s"])


def report(build: Build, per_job: bool = False) -> str:
    """The printed report of :func:`main`."""
    rows = table(build)
    lines = [f"Last build: {build.log.name} ({len(build.jobs)} jobs with metadata, "
             f"{len(build.rules)} finished in the log)", "",
             f"{'group':<22}{'jobs':>5}{'job time (s)':>14}{'cpu (s)':>10}{'share':>8}"]
    for r in rows:
        lines.append(f"{r['group']:<22}{r['jobs']:>5}{r['job_s']:>14.1f}{r['cpu_s']:>10.1f}"
                     f"{r['share_pct']:>7.1f}%")
    total = sum(r["job_s"] for r in rows)
    cpu = sum(r["cpu_s"] for r in rows)
    lines.append(f"{'total':<22}{sum(r['jobs'] for r in rows):>5}{total:>14.1f}{cpu:>10.1f}")
    wing = [r for r in rows if r["group"].startswith("periodic")]
    if wing:
        lines.append(f"{'periodic wing':<22}{sum(r['jobs'] for r in wing):>5}"
                     f"{sum(r['job_s'] for r in wing):>14.1f}{sum(r['cpu_s'] for r in wing):>10.1f}"
                     "  (maps, branches, tables, figures)")
    loads = [j.load for j in build.jobs if j.load == j.load]
    if loads:
        lines.append(f"mean CPU use of a job (Snakemake's mean_load, % of one core; far below "
                     f"100: a loaded machine): {sum(loads) / len(loads):.0f}")
    path = critical_path(build.jobs)
    lines += ["", f"Critical path ({sum(j.seconds for j in path):.1f} s of job time):"]
    lines += [f"  {j.seconds:8.1f} s  {j.name}" for j in path]
    lines += ["", f"Wall time of the build: {build.wall_s:.0f} s"]
    if per_job:
        lines += ["", "Jobs:"] + [f"  {j.seconds:8.1f} s  {j.cpu_s:8.1f} cpu  {j.name}"
                                  for j in sorted(build.jobs, key=lambda j: -j.seconds)]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--results", default="results", help="results folder of the build")
    ap.add_argument("--workdir", default=".", help="folder holding .snakemake/")
    ap.add_argument("--jobs", action="store_true", help="also list every job")
    ap.add_argument("--log", default=None,
                    help="the build's Snakemake log (default: the newest in .snakemake/log)")
    args = ap.parse_args(argv)
    build = last_build(Path(args.workdir), Path(args.results),
                       None if args.log is None else Path(args.log))
    print(report(build, args.jobs))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
