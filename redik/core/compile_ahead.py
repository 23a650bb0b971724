"""Run named compile-ahead steps and report each one's seconds.

The compile-ahead modules (``python -m redik.solvers.dls.compile``,
``redik.qp.compiled.compile``, ``redik.solvers.analytic.compile``) each call a few entries
of their numba kernels once with the argument types their callers pass, so that numba
compiles and caches them (``cache=True``) before a user's first solve. This is their one
runner.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping


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
