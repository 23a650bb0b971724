"""``redik batch SCENE``: solve many pose targets at once (see :mod:`redik.solvers.batch`).

Targets come from ``--targets FILE.npz`` (array ``T``, ``B × 4 × 4``, and optionally seeds
``q0``) or ``--random N`` (N reachable targets: the poses of random configurations). The
solutions go to ``--out FILE.npz``: ``T``, ``q``, ``success``, ``position_error``,
``rotation_error``, ``iterations``, ``restarts``, ``status`` (codes) and ``statuses`` (the
names of the codes), plus ``q_sampled`` with ``--random``.

With ``--checkpoint DIR`` every finished chunk is written to ``DIR`` as it arrives; the same
command run again after a crash (or a kill) reads those chunks back instead of solving them,
and writes the same ``--out`` an uninterrupted run would have. ``DIR`` belongs to one batch:
another batch (other targets, options, robot or redik version) is refused, naming what
differs. See :mod:`redik.solvers.batch.checkpoint`.
"""

from __future__ import annotations

import argparse
import inspect
import time
from pathlib import Path
from typing import Any

import numpy as np

from redik.apps.cli._model import add_model_arguments, load_chain
from redik.apps.progress import progress_bar, wanted
from redik.core.exceptions import InvalidInput
from redik.solvers.batch import BATCH_STATUSES, ENGINES, Chain, forward_kinematics, solve_batch
from redik.solvers.batch.checkpoint import finished_chunks


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``redik batch`` to the command line."""
    parser = subparsers.add_parser(
        "batch",
        help="solve many pose targets at once, on all cores or a Ray cluster",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_model_arguments(parser)
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--targets", type=Path, help=".npz with T (B×4×4) and optional q0")
    source.add_argument("--random", type=int, metavar="N", help="solve N random reachable poses")
    parser.add_argument("--out", type=Path, required=True, help="where to write the .npz")
    defaults = inspect.signature(solve_batch).parameters
    parser.add_argument(
        "--engine", choices=ENGINES, default=defaults["engine"].default, help="as solve_batch"
    )
    parser.add_argument(
        "--workers", type=int, default=None, help="threads or processes (default: all cores)"
    )
    parser.add_argument("--address", default=None, help="Ray cluster address (--engine ray)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--pos-tol", type=float, default=1e-6, help="metres")
    parser.add_argument("--rot-tol", type=float, default=1e-5, help="radians")
    parser.add_argument("--restarts", type=int, default=defaults["restarts"].default)
    parser.add_argument("--chunk-size", type=int, default=None, help="default: automatic")
    parser.add_argument(
        "--checkpoint",
        type=Path,
        default=None,
        metavar="DIR",
        help="write finished chunks to DIR; run the same command again to resume",
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Solve the targets, write the ``.npz`` and print the summary and the rate."""
    robot = load_chain(args)
    chain = Chain.from_robot(robot)
    extra: dict[str, Any] = {}  # arrays, typed Any for savez_compressed's keyword arguments
    q0 = None
    if args.random is not None:
        if args.random < 1:
            raise InvalidInput(f"--random needs a positive count, got {args.random}")
        q_sampled = np.random.default_rng(args.seed).uniform(
            chain.sampling_lower, chain.sampling_upper, (args.random, chain.dof)
        )
        T = forward_kinematics(chain, q_sampled)
        extra["q_sampled"] = q_sampled
    else:
        T, q0 = _read_targets(args.targets)

    if args.checkpoint is not None and (resumed := finished_chunks(args.checkpoint)):
        print(f"resuming from {args.checkpoint}: {resumed} finished chunks are read, not solved")
    bar = progress_bar(total=len(T), desc="batch IK", unit="pose", enabled=wanted(args.quiet))
    start = time.perf_counter()
    with bar:
        result = solve_batch(
            chain,
            T,
            q0=q0,
            pos_tol=args.pos_tol,
            rot_tol=args.rot_tol,
            restarts=args.restarts,
            seed=args.seed,
            engine=args.engine,
            workers=args.workers,
            address=args.address,
            chunk_size=args.chunk_size,
            progress=bar.update,
            checkpoint=args.checkpoint,
        )
    elapsed = time.perf_counter() - start

    args.out.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(
        args.out,
        T=T,
        q=result.q,
        success=result.success,
        position_error=result.position_error,
        rotation_error=result.rotation_error,
        iterations=result.iterations,
        restarts=result.restarts,
        status=result.status,
        statuses=np.asarray(BATCH_STATUSES),
        **extra,
    )
    rate = result.success.sum() / elapsed if elapsed > 0 else float("inf")
    print(f"{robot.name}: {result.summary()}")
    print(f"{elapsed:.2f} s on engine {args.engine!r}: {rate:,.0f} strict solves/s")
    print(f"wrote {args.out}")
    return 0


def _read_targets(path: Path) -> tuple[np.ndarray, np.ndarray | None]:
    """``T`` and the optional seeds ``q0`` of a targets file."""
    if not path.is_file():
        raise InvalidInput(f"targets file not found: {str(path)!r}")
    with np.load(path) as data:
        if "T" not in data:
            raise InvalidInput(
                f"{str(path)!r} must hold an array 'T' (B × 4 × 4); it has {sorted(data.files)}"
            )
        return data["T"], data["q0"] if "q0" in data else None
