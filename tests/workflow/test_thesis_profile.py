"""The thesis profile end to end (``python -m pytest -m slow``; about 20 min on 2 cores with a warm
derivation cache): ``snakemake -j2`` with ``config/config.yaml`` into its own results folder, then
every report row against the thesis column of ``tests/expected_status.csv`` and the published
values of ``data/published``.

The thesis column of the pin is written only from such a run (``pedalrepro report-status
--profile thesis --update <results>/tables/reproduction_report.csv`` refuses a report built with
any other configuration). Run it before committing a change that can move a thesis-profile status
(CONTRIBUTING.md, "Pinned statuses").
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest
from mocap_data import copy_real_subset
from required import REAL, required

from pedalrepro import paths, report

pytestmark = pytest.mark.slow


def _template(template: str) -> re.Pattern:
    parts = re.split(r"\{([^}]*)\}", template)
    rx = "".join(re.escape(p) if k % 2 == 0 else f"(?P<{p}>.+?)" for k, p in enumerate(parts))
    return re.compile(rx + r"\Z")


def _literal_length(template: str) -> int:
    return len(re.sub(r"\{[^}]*\}", "", template))


def _most_specific(hits: list) -> list:
    """The matching templates with the most literal text ('table_4_2.spectra.{key}.CF' before
    'table_4_2.{key}.{system}', which matches the same id)."""
    if not hits:
        return hits
    best = max(_literal_length(t) for t, _ in hits)
    return [(t, m) for t, m in hits if _literal_length(t) == best]


def _first_number(text: str) -> float | None:
    m = re.search(r"[-+]?\d*\.?\d+(?:[eE][-+]?\d+)?", text)
    return float(m.group()) if m else None


@pytest.fixture(scope="module")
def thesis_run(tmp_path_factory):
    """``snakemake -j2`` of the thesis profile into ``results/pytest_thesis`` (or
    ``$PEDALREPRO_TEST_THESIS_RESULTS``; kept between runs, so a rerun only rebuilds what
    changed); the real subset in the data folder, as in CI."""
    results = Path(os.environ.get("PEDALREPRO_TEST_THESIS_RESULTS",
                                  paths.ROOT / "results" / "pytest_thesis")).resolve()
    env = dict(os.environ)
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    env.pop("PEDALREPRO_RESULTS", None)
    if not (Path(env.get("PEDALREPRO_DATA_DIR", "")) / "3045_X.xlsx").is_file():
        env["PEDALREPRO_DATA_DIR"] = str(copy_real_subset(tmp_path_factory.mktemp("data")))
    cmd = [sys.executable, "-m", "snakemake", "-j2", "--rerun-incomplete", "--config",
           f"results_dir={results}"]
    start = time.perf_counter()
    proc = subprocess.run(cmd, cwd=paths.ROOT, env=env, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    log = proc.stdout + proc.stderr
    results.parent.mkdir(parents=True, exist_ok=True)
    (results.parent / f"{results.name}.snakemake.log").write_text(
        f"$ {' '.join(cmd)}\n# {elapsed:.1f} s, exit {proc.returncode}\n{log}")
    print(f"\nthesis profile: {elapsed:.0f} s, exit {proc.returncode}")
    assert proc.returncode == 0, log[-4000:]
    return results


def test_thesis_statuses_equal_the_pin(thesis_run):
    path = thesis_run / "tables" / "reproduction_report.csv"
    rep = pd.read_csv(path, dtype=str, keep_default_na=False)
    report.validate_report(rep, str(path))
    assert report.profile_of(path) == "thesis"
    expected = report.expected_status()
    assert (expected["thesis"] != "").all(), "pin rows without a thesis status"
    changes = report.status_changes(rep, expected, "thesis")
    counts = report.summary(rep)
    print(f"\nthesis report: {len(rep)} rows, {counts}")
    assert changes.empty, (
        f"{len(changes)} thesis-profile statuses differ from {report.EXPECTED_STATUS_FILE}:\n"
        f"{changes.to_string(index=False)}\nRecord an intended change with\n"
        f"    pedalrepro report-status --profile thesis --update {path}")
    if required(REAL):
        assert rep["id"].str.startswith("table_4_1.real_run_").sum() >= 6


def test_thesis_rows_quote_the_published_values(thesis_run):
    """Each row's published cell is the number ``data/published`` holds for its claim (where the
    claim's value reference can be filled from the row's id alone), to the 3 significant digits
    every published column shows at least."""
    rep = pd.read_csv(thesis_run / "tables" / "reproduction_report.csv", dtype=str,
                      keep_default_na=False)
    templates = {t: _template(t) for t in report.claims()}
    compared = 0
    for row in rep.itertuples():
        hits = _most_specific([(t, m) for t, rx in templates.items() if (m := rx.match(row.id))])
        assert len(hits) == 1, (row.id, [t for t, _ in hits])
        c = report.claim(hits[0][0])
        if c.value is None or c.published_text is not None:
            continue
        try:
            pub = report.published_value(c.value, **hits[0][1].groupdict())
        except (KeyError, IndexError):
            continue  # the reference needs a field the id does not carry (a column index)
        if isinstance(pub, list):
            pub = pub[0]
        shown = _first_number(row.published)
        if not isinstance(pub, int | float) or shown is None:
            continue
        assert shown == pytest.approx(float(pub), rel=5e-3, abs=1e-12), (row.id, row.published)
        compared += 1
    assert compared >= 20, compared
