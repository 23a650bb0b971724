"""``redik bench NAME``: run a benchmark (see :mod:`redik.apps.bench`)."""

from __future__ import annotations

import argparse

from redik.apps.bench import benchmarks


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``redik bench NAME`` (one subparser per benchmark, and ``all``)."""
    parser = subparsers.add_parser("bench", help="run a benchmark (not a test): redik bench NAME")
    names = parser.add_subparsers(dest="benchmark", metavar="NAME", required=True)
    for name, module in benchmarks().items():
        help_text = (module.__doc__ or name).strip().splitlines()[0]
        sub = names.add_parser(name, help=help_text, description=module.__doc__)
        module.add_arguments(sub)
        sub.set_defaults(func=module.run)
    names.add_parser("all", help="every benchmark with its defaults").set_defaults(func=run_all)


def run_all(args: argparse.Namespace) -> int:
    """Run every benchmark with its defaults; the exit codes OR-ed together."""
    status = 0
    for name, module in benchmarks().items():
        print(f"\n=== redik bench {name} ===")
        parser = argparse.ArgumentParser()
        module.add_arguments(parser)
        status |= int(module.run(parser.parse_args([])) or 0)
    return status
