"""The ``redik`` command line.

Each subcommand lives in its own module of this package and defines
``register(subparsers) -> None``, adding a parser whose ``func`` default takes the parsed
arguments and returns an exit code. Modules are discovered, so a new subcommand is a new
file here and nothing else.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys
from collections.abc import Sequence

from redik.apps.cli._model import in_flags
from redik.core.exceptions import RedikError


def build_parser() -> argparse.ArgumentParser:
    """The ``redik`` parser, with one subparser per module of this package."""
    parser = argparse.ArgumentParser(
        prog="redik",
        description="Optimisation-based, redundancy-resolving inverse kinematics on MuJoCo.",
    )
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND")
    for module in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
        if module.name.startswith("_"):
            continue
        importlib.import_module(f"{__name__}.{module.name}").register(subparsers)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``redik`` on ``argv`` (default ``sys.argv[1:]``) and return its exit code.

    A :class:`~redik.core.exceptions.RedikError` is printed as one line on stderr, in the
    command line's words (:func:`~redik.apps.cli._model.in_flags`), with exit code 2.
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    args.argv = list(sys.argv[1:] if argv is None else argv)  # as typed, for bench --record
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        return int(args.func(args) or 0)
    except RedikError as error:
        print(f"redik {args.command}: error: {in_flags(str(error))}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
