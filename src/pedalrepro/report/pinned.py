"""Pinned statuses: ``tests/expected_status.csv`` holds the expected status of every report row
per profile (a test expectation); :func:`status_changes` compares a report with it and
``pedalrepro report-status`` records a new one after validating it."""

from __future__ import annotations

import sys
from pathlib import Path

import pandas as pd

from .statuses import STATUSES

__all__ = [
    "EXPECTED_STATUS_FILE", "PROFILES", "expected_status", "status_changes", "profile_of",
    "validate_report", "update_expected_status", "add_cli",
]

#: Where the expected status of every report row is pinned, per profile (a test expectation).
EXPECTED_STATUS_FILE = "tests/expected_status.csv"
#: The profiles with a column in the expected-status file (``profile`` in ``config/*.yaml``).
PROFILES: tuple[str, ...] = ("quick", "thesis")


def expected_status(path: str | Path | None = None) -> pd.DataFrame:
    """The pinned statuses: columns ``id`` and one per :data:`PROFILES` ("" = not recorded)."""
    from .. import paths

    path = Path(path or paths.ROOT / EXPECTED_STATUS_FILE)
    df = pd.read_csv(path, dtype=str, keep_default_na=False)
    if list(df.columns) != ["id", *PROFILES]:
        raise ValueError(f"{path}: columns {list(df.columns)} != {['id', *PROFILES]}")
    bad = set(df[list(PROFILES)].to_numpy().ravel()) - {"", *STATUSES}
    if bad:
        raise ValueError(f"{path}: unknown status {sorted(bad)}")
    if df["id"].duplicated().any():
        raise ValueError(f"{path}: repeated ids {sorted(set(df['id'][df['id'].duplicated()]))}")
    return df


def status_changes(rep: pd.DataFrame, expected: pd.DataFrame, profile: str) -> pd.DataFrame:
    """Rows whose status differs from the pinned one of ``profile``, and rows added or removed:
    columns id, expected, got ("" for a row that is absent on that side)."""
    if profile not in PROFILES:
        raise ValueError(f"profile {profile!r} not in {PROFILES}")
    want = dict(zip(expected["id"], expected[profile], strict=True))
    want = {k: v for k, v in want.items() if v}
    got = dict(zip(rep["id"], rep["status"], strict=True))
    ids = list(got) + [k for k in want if k not in got]
    out = [(i, want.get(i, ""), got.get(i, "")) for i in ids if want.get(i, "") != got.get(i, "")]
    return pd.DataFrame(out, columns=["id", "expected", "got"])


def profile_of(report_path: str | Path) -> str:
    """The profile a reproduction report was built with: the results folder's configuration copy
    (:func:`pedalrepro.config.results_config`) must equal ``config/config.yaml`` (``thesis``) or
    ``config/config.yaml`` + ``config/quick.yaml`` (``quick``) in every key but ``results_dir``;
    otherwise a ValueError names the first keys that differ (a report of any other configuration
    cannot pin a profile's statuses)."""
    from .. import config, paths

    results = Path(report_path).resolve().parents[1]
    used = {k: v for k, v in config.results_config(results).items() if k != "results_dir"}
    diffs = {}
    for profile, extra in (("thesis", ()), ("quick", (paths.CONFIG / "quick.yaml",))):
        want = {k: v for k, v in config.load(None, *extra).items() if k != "results_dir"}
        if used == want:
            return profile
        diffs[profile] = sorted(k for k in set(used) | set(want) if used.get(k) != want.get(k))
    nearest = min(diffs, key=lambda p: len(diffs[p]))
    raise ValueError(f"{report_path}: built with a configuration that is neither the thesis nor "
                     f"the quick profile (keys differing from the {nearest} profile: "
                     f"{diffs[nearest][:6]})")


def validate_report(rep: pd.DataFrame, where: str) -> None:
    """A reproduction report fit to pin: the report's columns, known statuses, unique non-empty
    ids (ValueError naming ``where`` and the offending values otherwise)."""
    from .rows import COLUMNS

    if list(rep.columns) != list(COLUMNS):
        raise ValueError(f"{where}: columns {list(rep.columns)} != {list(COLUMNS)}")
    _validate_statuses(rep, where)


def _validate_statuses(rep: pd.DataFrame, where: str) -> None:
    """Known statuses and unique non-empty ids (columns ``id`` and ``status``)."""
    bad = sorted(set(rep["status"]) - set(STATUSES))
    if bad:
        raise ValueError(f"{where}: unknown status {bad} (allowed: {list(STATUSES)})")
    ids = rep["id"].astype(str).str.strip()
    if (ids == "").any():
        raise ValueError(f"{where}: {int((ids == '').sum())} rows without an id")
    dup = sorted(set(ids[ids.duplicated()]))
    if dup:
        raise ValueError(f"{where}: repeated ids {dup[:5]}")


def update_expected_status(rep: pd.DataFrame, profile: str, path: str | Path | None = None
                           ) -> pd.DataFrame:
    """Record the statuses of ``rep`` as the pinned ones of ``profile`` (other profiles kept;
    ids of the report first, in report order), write the file and return it. The report is
    checked first (known statuses, unique ids): nothing is written for a malformed one."""
    from .. import paths

    if profile not in PROFILES:
        raise ValueError(f"profile {profile!r} not in {PROFILES}")
    _validate_statuses(rep, "report")
    path = Path(path or paths.ROOT / EXPECTED_STATUS_FILE)
    old = (expected_status(path) if path.exists()
           else pd.DataFrame(columns=["id", *PROFILES], dtype=str))
    ids = list(rep["id"]) + [i for i in old["id"] if i not in set(rep["id"])]
    new = pd.DataFrame({"id": ids}).merge(old, on="id", how="left").fillna("")
    new[profile] = new["id"].map(dict(zip(rep["id"], rep["status"], strict=True))).fillna("")
    keep = (new[list(PROFILES)] != "").any(axis=1)
    new = new[keep][["id", *PROFILES]]
    new.to_csv(path, index=False)
    return new


def add_cli(sub) -> None:
    """``pedalrepro report-status``: compare a reproduction report with the pinned statuses."""
    p = sub.add_parser(
        "report-status",
        help="compare a reproduction report's statuses with tests/expected_status.csv",
        description="Compare (or with --update record) the status of every report row against "
                    f"{EXPECTED_STATUS_FILE} for one profile.")
    p.add_argument("report", help="results/<...>/tables/reproduction_report.csv")
    p.add_argument("--profile", required=True, choices=PROFILES)
    p.add_argument("--update", action="store_true",
                   help="write the report's statuses into the file (then commit it with the "
                        "reason for every change in the message)")
    p.set_defaults(func=_cli_status)


def _cli_status(args) -> int:
    from .. import paths

    try:
        rep = pd.read_csv(args.report, dtype=str, keep_default_na=False)
        validate_report(rep, args.report)
        if args.update:
            built = profile_of(args.report)
            if built != args.profile:
                raise ValueError(f"{args.report}: built with the {built} profile, not "
                                 f"{args.profile}: the {args.profile} column is written only "
                                 f"from a {args.profile}-profile run")
    except (OSError, ValueError) as exc:
        print(f"report-status: {exc}", file=sys.stderr)
        return 2
    pinned = (expected_status() if (paths.ROOT / EXPECTED_STATUS_FILE).exists()
              else pd.DataFrame(columns=["id", *PROFILES], dtype=str))
    changes = status_changes(rep, pinned, args.profile)
    print(changes.to_string(index=False) if len(changes) else "no status change")
    if args.update:
        update_expected_status(rep, args.profile)
        print(f"updated {EXPECTED_STATUS_FILE} ({args.profile})")
        return 0
    return 1 if len(changes) else 0
