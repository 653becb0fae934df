"""scripts/bench_pipeline.py: the job-time table, critical path and wall time of the last build.

A hand-made build (log, metadata, benchmark files) with a known answer, then the quick build's
own files: every job of it has a benchmark file (every rule writes one), and the numbers obey
what any schedule on two cores must: critical path <= wall time <= total job time, and total job
time <= 2 x wall time (two cores), each within the logs' 1 s timestamp resolution.
"""

from __future__ import annotations

import base64
import importlib.util
import json
import sys
import time
from pathlib import Path

import pytest

from pedalrepro import paths

_SPEC = importlib.util.spec_from_file_location("bench_pipeline",
                                               paths.ROOT / "scripts" / "bench_pipeline.py")
bench = importlib.util.module_from_spec(_SPEC)
sys.modules["bench_pipeline"] = bench  # dataclasses look their module up
_SPEC.loader.exec_module(bench)

STAMP = "%a %b %d %H:%M:%S %Y"


def _fake_build(tmp_path: Path, jobs: dict[str, tuple[float, float, list[str], float]]):
    """jobs: name -> (start offset s, job time s, inputs, cpu s); rule = name; output
    ``out/<name>``; log ``logs/<name>.log``; benchmark ``benchmarks/<name>.tsv``."""
    t0 = float(int(time.time())) - 1000.0
    end = max(s + d for s, d, _, _ in jobs.values())
    log = [f"  Date: {time.strftime('%Y-%m-%d %H:%M:%S', time.localtime(t0))}", ""]
    meta = tmp_path / ".snakemake" / "metadata"
    meta.mkdir(parents=True)
    (tmp_path / "results" / "benchmarks").mkdir(parents=True)
    for i, (name, (s, d, inputs, cpu)) in enumerate(jobs.items()):
        out = f"out/{name}"
        rec = {"rule": name, "input": inputs, "log": [f"results/logs/{name}.log"],
               "starttime": t0 + s, "endtime": t0 + s + d, "job_hash": i}
        (meta / base64.b64encode(out.encode()).decode()).write_text(json.dumps(rec))
        (tmp_path / "results" / "benchmarks" / f"{name}.tsv").write_text(
            "s\th:m:s\tmax_rss\tmean_load\tcpu_time\n"
            f"{d:.2f}\t0:00:00\t10.0\t50.0\t{cpu:.2f}\n")
        log += [f"[{time.strftime(STAMP, time.localtime(t0 + s))}]", f"Job {i}: {name}",
                f"[{time.strftime(STAMP, time.localtime(t0 + s + d))}]",
                f"Finished jobid: {i} (Rule: {name})"]
    log.append(f"[{time.strftime(STAMP, time.localtime(t0 + end))}]")
    folder = tmp_path / ".snakemake" / "log"
    folder.mkdir(parents=True)
    (folder / "2026-01-01T000000.000000.snakemake.log").write_text("\n".join(log) + "\n")
    return tmp_path


def test_hand_made_build(tmp_path):
    # a -> b -> d and a -> c: two cores, the path a, b, d is the critical one (10 + 30 + 5 s)
    root = _fake_build(tmp_path, {
        "nonlinear_codegen_plain": (0, 10, [], 9.0),
        "periodic_map_thesis_NT_HR": (10, 30, ["out/nonlinear_codegen_plain"], 29.0),
        "periodic_map_thesis_NP_HR": (10, 20, ["out/nonlinear_codegen_plain"], 19.0),
        "figures_periodic": (40, 5, ["out/periodic_map_thesis_NT_HR",
                                     "out/periodic_map_thesis_NP_HR"], 4.0)})
    build = bench.last_build(root, root / "results")
    assert len(build.jobs) == 4 and build.wall_s == pytest.approx(45, abs=1)
    rows = {r["group"]: r for r in bench.table(build)}
    assert rows["periodic maps"]["jobs"] == 2
    assert rows["periodic maps"]["job_s"] == pytest.approx(50.0)
    assert rows["periodic maps"]["cpu_s"] == pytest.approx(48.0)
    assert rows["derivation (once)"]["job_s"] == pytest.approx(10.0)
    assert rows["periodic figures"]["share_pct"] == pytest.approx(100 * 5 / 65)
    path = bench.critical_path(build.jobs)
    assert [j.name for j in path] == ["nonlinear_codegen_plain", "periodic_map_thesis_NT_HR",
                                      "figures_periodic"]
    text = bench.report(build)
    assert "Critical path (45.0 s" in text and "Wall time of the build: 45 s" in text
    wing = next(line for line in text.splitlines() if line.startswith("periodic wing"))
    assert wing.split()[2:5] == ["3", "55.0", "52.0"]  # two maps and the periodic figures


def test_not_a_log_is_refused(tmp_path):
    folder = tmp_path / ".snakemake" / "log"
    folder.mkdir(parents=True)
    (folder / "x.snakemake.log").write_text("nothing here\n")
    with pytest.raises(ValueError, match="not a Snakemake log"):
        bench.last_build(tmp_path, tmp_path / "results")
    with pytest.raises(FileNotFoundError, match="no Snakemake log"):
        bench.last_build(tmp_path / "empty", tmp_path / "results")


@pytest.mark.workflow
def test_quick_build_benchmarks(quick_workflow):
    assert quick_workflow.returncode == 0
    # the quick run's own log: other tests of the session start Snakemake after it
    assert quick_workflow.snakemake_log is not None and quick_workflow.snakemake_log.is_file()
    build = bench.last_build(paths.ROOT, quick_workflow.results, quick_workflow.snakemake_log)
    assert len(build.jobs) >= 60
    missing = [j.rule for j in build.jobs if not j.benchmark]
    assert not missing, f"jobs without a benchmark file: {missing}"
    total = sum(j.seconds for j in build.jobs)
    path = sum(j.seconds for j in bench.critical_path(build.jobs))
    assert path <= build.wall_s + 2
    assert build.wall_s <= total + 2 and total <= 2 * build.wall_s + 2 * len(build.jobs)
    assert build.wall_s <= quick_workflow.elapsed_s + 2
