"""``redik regress``: run every spec and compare it with the stored baselines."""

from __future__ import annotations

import argparse
from pathlib import Path

from redik.apps.progress import wanted
from redik.apps.regress import run_regression


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``redik regress`` to the command line."""
    parser = subparsers.add_parser(
        "regress",
        help="run every spec, compare with specs/baselines/*.json, exit 1 on a regression",
    )
    parser.add_argument("--fast", action="store_true", help="run the specs in fast mode")
    parser.add_argument("--update", action="store_true", help="rewrite the baselines")
    parser.add_argument("--specs", type=Path, default=None, help="spec folder")
    parser.add_argument(
        "--baselines", type=Path, default=None, help="baseline folder (default SPECS/baselines)"
    )
    parser.add_argument("--seed", type=int, default=0, help="seed passed to every spec")
    parser.add_argument("--out", type=Path, default=None, help="keep the specs' pictures here")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Run the specs against the baselines; exit code 1 on a regression."""
    report = run_regression(
        args.specs,
        args.baselines,
        fast=args.fast,
        update=args.update,
        seed=args.seed,
        out=args.out,
        show_progress=wanted(args.quiet),
    )
    print(report.table())
    for path in report.updated:
        print(f"updated {path}")
    if args.update:
        not_written = [s.outcome.name for s in report.specs if not s.outcome.passed]
        if not_written:
            print(f"baselines NOT updated for failing specs: {', '.join(not_written)}")
            return 1
        return 0
    return 1 if report.regressed else 0
