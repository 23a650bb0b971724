"""Run named compile-ahead steps and report each one's seconds.

A compile-ahead module (``python -m redik.solvers.dls.compile``,
``redik.solvers.batch.compile``, ``redik.qp.compiled.compile``,
``redik.solvers.analytic.compile``) calls a few entries of its numba kernels once with the
argument types their callers pass, so that numba compiles and caches them (``cache=True``)
before a user's first call. :func:`compile_all` runs one module's steps; this module run as a
program (``python -m redik.core.compile_ahead [MODULE ...]``) runs whole modules, each in a
process of its own and as many at once as there are cores: their kernels are disjoint and
numba writes each to its own cache file, and compiling is single-threaded, so the modules
take the time of the longest one instead of their sum.
"""

from __future__ import annotations

import argparse
import concurrent.futures
import os
import subprocess
import sys
import time
from collections.abc import Callable, Mapping, Sequence

INSTALL = ("redik.solvers.dls.compile", "redik.qp.compiled.compile")
"""What ``make env`` compiles: what :func:`redik.solve_pose`, :func:`redik.solve_problem`
and ``redik demo`` call first."""

EVERY = (*INSTALL, "redik.solvers.batch.compile", "redik.solvers.analytic.compile")
"""Every compile-ahead module (``--all``)."""


def compile_all(
    steps: Mapping[str, Callable[[], object]], report: Callable[[str], None] = print
) -> dict[str, float]:
    """Run every step once, in order.

    Args:
        steps: The steps by name.
        report: Called with a line per step (its name and seconds).

    Returns:
        Each step's seconds: compilation, or loading from the cache when it is warm.
    """
    seconds = {}
    for name, step in steps.items():
        start = time.perf_counter()
        step()
        seconds[name] = time.perf_counter() - start
        report(f"{name:<45}{seconds[name]:>8.2f} s")
    return seconds


def main(steps: Mapping[str, Callable[[], object]]) -> None:
    """Run :func:`compile_all` on ``steps`` and print the total."""
    total = sum(compile_all(steps).values())
    print(f"{'total':<45}{total:>8.2f} s")


def run_modules(
    modules: Sequence[str], jobs: int, report: Callable[[str], None] = print
) -> dict[str, float]:
    """Run each compile-ahead module as ``python -m MODULE``, ``jobs`` processes at a time.

    Args:
        modules: The modules' names, started in this order.
        jobs: How many run at once.
        report: Called with each module's output and seconds when it ends.

    Returns:
        Each module's wall seconds.

    Raises:
        subprocess.CalledProcessError: A module failed (its output is in the exception).
    """
    seconds: dict[str, float] = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        runs = {pool.submit(_run_module, module): module for module in modules}
        for done in concurrent.futures.as_completed(runs):
            module = runs[done]
            seconds[module], output = done.result()
            report(f"python -m {module}: {seconds[module]:.2f} s\n{output.rstrip()}")
    return seconds


def _run_module(module: str) -> tuple[float, str]:
    """``python -m module`` to its end: its wall seconds and output (stdout and stderr)."""
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-m", module],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        errors="replace",
        check=False,
    )
    if done.returncode != 0:
        raise subprocess.CalledProcessError(done.returncode, done.args, done.stdout)
    return time.perf_counter() - start, done.stdout


def _arguments(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog="python -m redik.core.compile_ahead", description=__doc__.splitlines()[0]
    )
    parser.add_argument("modules", nargs="*", help=f"default: {' '.join(INSTALL)}")
    parser.add_argument("--all", action="store_true", help="every compile-ahead module")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="default: cores")
    return parser.parse_args(argv)


def run(argv: Sequence[str] | None = None) -> None:
    """The program: the modules named (or :data:`INSTALL`, or :data:`EVERY` with ``--all``)."""
    arguments = _arguments(argv)
    modules = EVERY if arguments.all else arguments.modules or INSTALL
    start = time.perf_counter()
    run_modules(modules, max(1, arguments.jobs))
    print(f"compiled ahead in {time.perf_counter() - start:.2f} s ({arguments.jobs} at once)")


if __name__ == "__main__":
    run()
