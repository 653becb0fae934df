"""``pedalrepro mocap ...``: extract angles from a run file; refresh the data registry."""

from __future__ import annotations

import argparse
from pathlib import Path

import pandas as pd


def _extract(args: argparse.Namespace) -> int:
    from .runs import analyse_run

    a = analyse_run(args.run_file, lowpass_hz=None if args.no_lowpass else args.lowpass_hz)
    r, k, c = a.run, a.kin, a.cadence
    df = pd.DataFrame({"time_s": k.t_s, "roll_rad": k.roll_rad, "steer_rad": k.steer_rad,
                       "yaw_rad": k.yaw_rad, "crank_rad": k.crank_rad,
                       "cadence_rpm": c.cadence_rpm})
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    header = [
        f"# run {r.run_id}: rider {r.rider}, bike {r.bicycle}, task {r.task} "
        f"(condition {r.condition!r}), speed {r.speed_kmh:g} km/h, gear {r.gear}",
        f"# cadence_rpm={c.cadence_rpm:.4f} (whole-bin {c.cadence_bin_rpm:.1f}, crank-angle "
        f"slope {c.cadence_crank_rpm:.4f})",
        f"# roll_amp_rad={a.amplitudes['roll_amp_rad']:.6g} "
        f"steer_amp_rad={a.amplitudes['steer_amp_rad']:.6g} (Hann DFT at the cadence)",
        "# angles: benchmark convention (Meijaard et al. 2007), roll and steer positive to the "
        "right; crank = theta_A (0 = right foot forward, decreasing while pedalling)",
    ] + [f"# note: {n}" for n in r.notes + k.notes]
    with out.open("w") as fh:
        fh.write("\n".join(header) + "\n")
        df.to_csv(fh, index=False, float_format="%.9g")
    print(f"{out}: {len(df)} samples, cadence {c.cadence_rpm:.2f} rpm")
    return 0


def _refresh(args: argparse.Namespace) -> int:
    from .fetch import REGISTRY, refresh_registry

    entries = refresh_registry(args.registry or REGISTRY)
    print(f"{args.registry or REGISTRY}: {len(entries)} files")
    return 0


def add_cli(subparsers) -> None:
    """Register ``pedalrepro mocap extract`` and ``pedalrepro mocap refresh-registry``."""
    p = subparsers.add_parser("mocap", help="treadmill motion-capture data (Sec 4.1)")
    sub = p.add_subparsers(dest="mocap_command", metavar="ACTION", required=True)
    e = sub.add_parser("extract", help="roll, steer, yaw and cadence of one run file RNNN.mat")
    e.add_argument("run_file", help="a published (or stand-in) run file, e.g. 3082.mat")
    e.add_argument("--out", required=True, help="CSV to write")
    e.add_argument("--lowpass-hz", type=float, default=12.0,
                   help="zero-phase low-pass of the angles (Hz), default 12")
    e.add_argument("--no-lowpass", action="store_true", help="no low-pass filter")
    e.set_defaults(func=_extract)
    r = sub.add_parser("refresh-registry",
                       help="read the file list and hashes from the figshare DOI (online)")
    r.add_argument("--registry", default=None, help="registry file (default data/registry.txt)")
    r.set_defaults(func=_refresh)
