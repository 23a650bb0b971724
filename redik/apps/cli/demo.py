"""``redik demo [--out DIR]``: the main job on a bundled scene (see :mod:`redik.apps.demo`)."""

from __future__ import annotations

import argparse
from pathlib import Path


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``redik demo`` to the command line."""
    parser = subparsers.add_parser(
        "demo",
        help="dexter8r: QP solve with limit avoidance and posture, self-motion, pictures",
    )
    parser.add_argument("--out", type=Path, default=Path("out") / "demo", help="output folder")
    parser.add_argument("--seed", type=int, default=0, help="seed of the self-motion starts")
    parser.add_argument(
        "--max-samples", type=int, default=1500, help="sample budget of the self-motion"
    )
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Run the demo, print its summary; exit code 1 when the QP solve failed."""
    from redik.apps.demo import format_summary, run_demo  # heavy imports only for this command

    result = run_demo(args.out, seed=args.seed, max_samples=args.max_samples)
    print(format_summary(result))
    return 0 if result.summary["qp"]["success"] else 1
