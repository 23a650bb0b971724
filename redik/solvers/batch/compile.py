"""Compile the batch entries of the damped least-squares kernel into numba's cache.

``python -m redik.solvers.batch.compile`` solves one target of the panda through
:func:`~redik.solvers.dls.kernel.solve_serial` (what :func:`redik.solve_batch`'s workers
call) and :func:`~redik.solvers.dls.kernel.solve_parallel` (what it calls in this process)
with the argument types :func:`redik.solve_batch` passes, so that numba compiles each entry
and its callees once and caches them (``cache=True``: next to the sources, or under
``NUMBA_CACHE_DIR``). Every chain has the same types, so one arm compiles them for all.
Nothing here is needed for correctness: a cold first call compiles the same code, and a warm
one loads it from the cache (``python -m redik.core.compile_ahead --all`` runs it).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from redik.core import compile_ahead
from redik.kinematics.chain import Chain
from redik.kinematics.robot import load
from redik.solvers.dls import DLSOptions, batch_results, solve_parallel, solve_serial


def _arguments() -> tuple[object, ...]:
    """One panda target, as :func:`redik.solve_batch` passes it to either entry."""
    robot = load("panda")
    chain = Chain.from_robot(robot)
    centre, radius = chain.reach()
    settings, counts = DLSOptions().kernel_settings()
    return (
        chain.kernel_arrays(), np.array([*centre, radius]), robot.fk(robot.home)[None].copy(),
        robot.home[None].copy(), np.int64(0), np.uint64(0), settings, counts,
        batch_results(1, chain.dof),
    )  # fmt: skip


#: What :func:`redik.core.compile_ahead.compile_all` runs, by name.
STEPS: dict[str, Callable[[], object]] = {
    "solve_serial (solve_batch's workers)": lambda: solve_serial(*_arguments()),
    "solve_parallel (solve_batch in this process)": lambda: solve_parallel(*_arguments()),
}


if __name__ == "__main__":
    compile_ahead.main(STEPS)
