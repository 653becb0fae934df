"""The ``pedalrepro`` command line.

Sub-commands are contributed by modules that define ``add_cli(subparsers)``; list them in
:data:`COMMAND_MODULES`. ``pedalrepro periodic`` (:mod:`pedalrepro.periodic`) is defined here.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from . import __version__

__all__ = ["COMMAND_MODULES", "build_parser", "add_periodic_cli", "main"]

#: Modules (relative to the package) that add sub-commands.
COMMAND_MODULES: tuple[str, ...] = ("mocap.cli", "report", "own_bicycle")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every registered sub-command."""
    parser = argparse.ArgumentParser(
        prog="pedalrepro",
        description="Reproduction of Baines: pedalling and the lateral dynamics of cycling.",
    )
    parser.add_argument("--version", action="version", version=f"pedalrepro {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMAND_MODULES:
        importlib.import_module(f"pedalrepro.{name}").add_cli(sub)
    add_periodic_cli(sub)
    return parser


def add_periodic_cli(subparsers) -> None:
    """The ``periodic`` sub-command: one orbit of :mod:`pedalrepro.periodic` as JSON."""
    from .periodic import solver

    lo, hi = solver.SPEED_RANGE_M_S
    rlo, rhi = solver.CADENCE_RANGE_RPM
    p = subparsers.add_parser(
        "periodic", help="periodic pedalling response of a non-linear model (shooting)",
        description="Periodic orbit of a non-linear model under pedalling (speed held by a "
                    "rear-hub torque): cadence-harmonic amplitudes and phases, Floquet "
                    "multipliers, periodicity residual. Prints one JSON object.")
    p.add_argument("--model", required=True, help="HS, CF, HR or CR")
    p.add_argument("--speed-m-s", type=float, required=True, dest="speed_m_s",
                   help=f"forward speed, m/s, in [{lo}, {hi}]")
    p.add_argument("--cadence-rpm", type=float, required=True, dest="cadence_rpm",
                   help=f"cadence, rpm, in [{rlo}, {rhi}]")
    p.add_argument("--method", default="NT", help="NT (torques, default) or NP (moving legs)")
    p.add_argument("--segments", type=int, default=None,
                   help="shooting segments (1: single shooting; default: from the instability)")
    p.add_argument("--torque-scale", type=float, default=1.0, dest="torque_scale",
                   help="factor on the NT torques (default 1; finite; 0: the upright motion)")
    p.set_defaults(func=_periodic)


def _periodic(args) -> int:
    import json
    import math

    from .periodic import solver

    if args.segments is not None and not 1 <= args.segments <= 256:
        raise ValueError(f"--segments must be in [1, 256], got {args.segments}")
    for name in ("speed_m_s", "cadence_rpm", "torque_scale"):
        value = getattr(args, name)
        if not math.isfinite(value):
            raise ValueError(f"--{name.replace('_', '-')} must be finite, got {value}")
    try:
        orb = solver.orbit(args.model, args.method, args.speed_m_s,
                           args.cadence_rpm * 2.0 * math.pi / 60.0, segments=args.segments,
                           torque_scale=args.torque_scale)
    except solver.ConvergenceError as exc:
        print(f"pedalrepro periodic: error: {exc}", file=sys.stderr)
        return 3
    print(json.dumps(orb.summary()))
    return 0


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``pedalrepro`` console script."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    try:
        return int(args.func(args) or 0)
    except (ValueError, OSError, KeyError) as exc:
        print(f"pedalrepro: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
