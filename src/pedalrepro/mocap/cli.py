"""``pedalrepro mocap ...``: extract angles from a run; import exports; refresh the registry.

One line analyses a real run: ``pedalrepro mocap extract 3045 --out 3045.csv`` (the public
subset's files from the data folder ``$PEDALREPRO_DATA_DIR``, downloaded with a progress bar
when absent) or ``pedalrepro mocap extract path/3045_X.xlsx --out 3045.csv`` (the Y and Z files
beside it). The quality criteria are the pipeline's (:func:`pedalrepro.mocap.runs.analyse_run`):
a refused run exits with status 2 and the reason; a partial analysis says which stretch.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

import pandas as pd

__all__ = ["add_cli"]


def _sources(items: list[str]):
    """Run files from the arguments: a ``.mat`` file, export files, or a public run number."""
    from . import exports, fetch

    if len(items) == 1 and re.fullmatch(r"\d{4}", items[0]):
        rid = int(items[0])
        meta = exports.run_metadata(rid)  # clear error when not in the public subset
        pup = fetch.make_public_pooch()
        names = [n for n in meta["files"] if n in pup.registry]
        return [fetch.fetch(n, pup, progressbar=True) for n in names]
    return items[0] if len(items) == 1 else items


def _cutoff_hz(text: str) -> float:
    """``--lowpass-hz``: a finite frequency >= 0 (0 = off); the Nyquist rate is checked
    against the run (:func:`pedalrepro.mocap.runs.check_lowpass`)."""
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not (value == value and abs(value) != float("inf") and value >= 0):
        raise argparse.ArgumentTypeError(
            f"{text!r} is not a finite frequency >= 0 Hz (0 or --no-lowpass: no filter)")
    return value


def _extract(args: argparse.Namespace) -> int:
    from .runs import RunRefusedError, analyse_run

    try:
        a = analyse_run(_sources(args.run),
                        lowpass_hz=None if args.no_lowpass else args.lowpass_hz)
    except RunRefusedError as exc:
        print(f"REFUSED: {exc}", file=sys.stderr)
        return 2
    r, k, c = a.run, a.kin, a.cadence
    df = pd.DataFrame({"time_s": k.t_s, "roll_rad": k.roll_rad, "steer_rad": k.steer_rad,
                       "yaw_rad": k.yaw_rad, "crank_rad": k.crank_rad,
                       "cadence_rpm": c.cadence_rpm})
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    header = [
        f"# run {r.run_id}: rider {r.rider}, bike {r.bicycle}, task {r.task} "
        f"(condition {r.condition!r}), speed {r.speed_kmh:.4g} km/h, gear {r.gear}",
        f"# analysis={a.status} ({a.segment_s[1] - a.segment_s[0]:.2f} s)",
        f"# cadence_rpm={c.cadence_rpm:.4f} (whole-bin {c.cadence_bin_rpm:.1f}, crank-angle "
        f"slope {c.cadence_crank_rpm:.4f})",
        f"# roll_amp_rad={a.amplitudes['roll_amp_rad']:.6g} "
        f"steer_amp_rad={a.amplitudes['steer_amp_rad']:.6g} (Hann DFT at the exact cadence)",
        f"# roll_bin_amp_rad={a.amplitudes_bin['roll_amp_rad']:.6g} "
        f"steer_bin_amp_rad={a.amplitudes_bin['steer_amp_rad']:.6g} (Hann DFT bin nearest the "
        "whole-bin cadence: the thesis's method)",
        "# angles: benchmark convention (Meijaard et al. 2007), roll and steer positive to the "
        "right; crank = theta_A (0 = right foot forward, decreasing while pedalling)",
    ] + [f"# note: {n}" for n in a.notes + r.notes + k.notes]
    with out.open("w") as fh:
        fh.write("\n".join(header) + "\n")
        df.to_csv(fh, index=False, float_format="%.9g")
    print(f"{out}: {len(df)} samples, {a.status}, cadence {c.cadence_rpm:.2f} rpm, roll "
          f"{a.amplitudes['roll_amp_rad']:.4f} rad, steer {a.amplitudes['steer_amp_rad']:.4f} "
          f"rad (nearest bin: {a.amplitudes_bin['roll_amp_rad']:.4f}, "
          f"{a.amplitudes_bin['steer_amp_rad']:.4f})")
    for n in a.notes:
        print(n)
    return 0


def _import(args: argparse.Namespace) -> int:
    from . import exports

    src = _sources(args.exports)
    run = exports.read_export_run(src if not isinstance(src, str) else Path(src))
    out = Path(args.out) if args.out else Path(f"{run.run_id:04d}.mat")
    exports.write_mat(run, out)
    print(f"{out}: run {run.run_id} ({run.bicycle}, {run.task}, {run.speed_kmh:.4g} km/h, "
          f"{len(run.t_s)} samples) in the published RNNN.mat layout")
    return 0


def _refresh(args: argparse.Namespace) -> int:
    from .fetch import REGISTRY, refresh_registry

    entries = refresh_registry(args.registry or REGISTRY)
    print(f"{args.registry or REGISTRY}: {len(entries)} files")
    return 0


def add_cli(subparsers) -> None:
    """Register ``pedalrepro mocap extract | import | refresh-registry``."""
    p = subparsers.add_parser("mocap", help="treadmill motion-capture data (Sec 4.1)")
    sub = p.add_subparsers(dest="mocap_command", metavar="ACTION", required=True)
    e = sub.add_parser(
        "extract", help="roll, steer, yaw and cadence of one run (RNNN.mat, exports, or a "
        "public run number such as 3045)")
    e.add_argument("run", nargs="+",
                   help="a run file RNNN.mat, per-coordinate exports RNNN_X/Y/Z (.xlsx, .csv; "
                   "one is enough, the others are found beside it), or the number of a "
                   "public-subset run (fetched into $PEDALREPRO_DATA_DIR)")
    e.add_argument("--out", required=True, help="CSV to write")
    e.add_argument("--lowpass-hz", type=_cutoff_hz, default=12.0,
                   help="zero-phase low-pass of the angles (Hz, below the run's Nyquist rate; "
                   "0 = off), default 12")
    e.add_argument("--no-lowpass", action="store_true", help="no low-pass filter")
    e.set_defaults(func=_extract)
    i = sub.add_parser("import", help="write per-coordinate exports as a published RNNN.mat")
    i.add_argument("exports", nargs="+", help="the exports (or one of them, or a public run "
                   "number)")
    i.add_argument("--out", default=None, help="the .mat file (default RNNN.mat here)")
    i.set_defaults(func=_import)
    r = sub.add_parser("refresh-registry",
                       help="read the file list and hashes from the figshare DOI (online)")
    r.add_argument("--registry", default=None, help="registry file (default data/registry.txt)")
    r.set_defaults(func=_refresh)
