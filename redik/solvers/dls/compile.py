"""Compile the damped least-squares kernel into numba's on-disk cache before first use.

``python -m redik.solvers.dls.compile`` solves one target of the panda through each entry of
:mod:`redik.solvers.dls.kernel` — :func:`~redik.solvers.dls.kernel.solve_one` (what
:func:`redik.solve_pose` calls), :func:`~redik.solvers.dls.kernel.solve_serial` and
:func:`~redik.solvers.dls.kernel.solve_parallel` (what :func:`redik.solve_batch` calls) — with
the argument types those callers pass, so that numba compiles each entry and its callees once
and caches them (``cache=True``: next to the sources, or under ``NUMBA_CACHE_DIR``). Every
chain has the same types, so one arm compiles them for all. Nothing here is needed for
correctness: a cold first call compiles the same code, and a warm one loads it from the cache.
``make env`` runs it as the last step of installing.
"""

from __future__ import annotations

import numpy as np

from redik.core import compile_ahead
from redik.kinematics.chain import Chain
from redik.kinematics.robot import load
from redik.solvers.dls.kernel import batch_results, solve_parallel, solve_serial
from redik.solvers.dls.options import DLSOptions
from redik.solvers.pose import solve_pose


def main() -> None:
    """Compile and cache the three entries; print how long each took."""
    robot = load("panda")
    chain = Chain.from_robot(robot)
    T = robot.fk(robot.home)
    centre, radius = chain.reach()
    settings, counts = DLSOptions().kernel_settings()
    batch = (
        chain.kernel_arrays(), np.array([*centre, radius]), T[None].copy(), robot.home[None].copy(),
        np.int64(0), np.uint64(0), settings, counts, batch_results(1, chain.dof),
    )  # fmt: skip
    compile_ahead.main(
        {
            "solve_one (solve_pose)": lambda: solve_pose(robot, T, seed=0),
            "solve_serial (solve_batch's workers)": lambda: solve_serial(*batch),
            "solve_parallel (solve_batch in this process)": lambda: solve_parallel(*batch),
        }
    )


if __name__ == "__main__":
    main()
