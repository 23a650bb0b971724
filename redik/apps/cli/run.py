"""``redik run specs/<file>.py``: run one spec with a progress bar and a summary table."""

from __future__ import annotations

import argparse
from pathlib import Path

from redik.apps.specs import Context, load_spec, run_spec, summary_table


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``redik run`` to the command line."""
    parser = subparsers.add_parser(
        "run", help="run a spec (specs/<file>.py) and print its summary table"
    )
    parser.add_argument("spec", nargs="+", type=Path, help="spec file(s)")
    parser.add_argument("--fast", action="store_true", help="the few-seconds mode")
    parser.add_argument("--seed", type=int, default=0, help="seed of the spec's randomness")
    parser.add_argument(
        "--out", type=Path, default=Path("out") / "specs", help="folder for pictures and data"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Run each spec and print its table; exit code 1 when one fails."""
    status = 0
    for path in args.spec:
        spec = load_spec(path)
        context = Context(
            fast=args.fast,
            seed=args.seed,
            out=args.out / spec.name,
            show_progress=not args.no_progress,
        )
        outcome = run_spec(spec, context)
        print(summary_table(outcome))
        if context.out.is_dir():
            print(f"outputs in {context.out}")
        status |= 0 if outcome.passed else 1
    return status
