"""The ``pedalrepro`` command line.

Sub-commands are contributed by modules that define ``add_cli(subparsers)``; list them in
:data:`COMMAND_MODULES`.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from . import __version__

#: Modules (relative to the package) that add sub-commands.
COMMAND_MODULES: tuple[str, ...] = ("mocap.cli", "report", "own_bicycle", "periodic")


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
    return parser


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
