"""``redik bench NAME``: run a benchmark (see :mod:`redik.apps.bench`)."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path
from types import ModuleType

from redik.apps import measured
from redik.apps.bench import benchmarks


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``redik bench NAME`` (one subparser per benchmark, and ``all``)."""
    parser = subparsers.add_parser("bench", help="run a benchmark (not a test): redik bench NAME")
    names = parser.add_subparsers(dest="benchmark", metavar="NAME", required=True)
    for name, module in benchmarks().items():
        help_text = (module.__doc__ or name).strip().splitlines()[0]
        sub = names.add_parser(name, help=help_text, description=module.__doc__)
        module.add_arguments(sub)
        sub.add_argument(
            "--record",
            metavar="FILE",
            default=None,
            help="also write the tables as JSON, with this command, the date and the core "
            f"count (docs/measured/{name}.json feeds the site and README's Measured table)",
        )
        sub.set_defaults(func=lambda args, module=module, name=name: run_one(name, module, args))
    everything = names.add_parser("all", help="every benchmark with its defaults")
    everything.add_argument(
        "--record", metavar="DIR", default=None, help="write DIR/NAME.json for each benchmark"
    )
    everything.set_defaults(func=run_all)


def run_one(
    name: str, module: ModuleType, args: argparse.Namespace, argv: list[str] | None = None
) -> int:
    """Run one benchmark; with ``--record FILE`` write what it measured to ``FILE``."""
    load = os.getloadavg()
    measured.start()
    status = int(module.run(args) or 0)
    if args.record:
        typed = argv or getattr(args, "argv", None) or sys.argv[1:]
        path = measured.write(args.record, name, typed, load)
        print(f"recorded {path}")
    return status


def run_all(args: argparse.Namespace) -> int:
    """Run every benchmark with its defaults; the exit codes OR-ed together."""
    status = 0
    for name, module in benchmarks().items():
        print(f"\n=== redik bench {name} ===")
        parser = argparse.ArgumentParser()
        module.add_arguments(parser)
        options = parser.parse_args([])
        options.record = str(Path(args.record) / f"{name}.json") if args.record else None
        status |= run_one(name, module, options, ["bench", name])
    return status
