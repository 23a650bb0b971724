"""Compile the damped least-squares solve of one target into numba's cache before first use.

``python -m redik.solvers.dls.compile`` solves one target of the panda by
:func:`redik.solve_pose`, which calls :func:`~redik.solvers.dls.kernel.solve_one` (as
:func:`redik.solve_problem`'s warm start does) with the argument types every caller passes,
so that numba compiles it and its callees once and caches them (``cache=True``: next to the
sources, or under ``NUMBA_CACHE_DIR``). Every chain has the same types, so one arm compiles it
for all. Nothing here is needed for correctness: a cold first call compiles the same code, and
a warm one loads it from the cache. ``make env`` runs it as a step of installing
(:mod:`redik.core.compile_ahead`); :mod:`redik.solvers.batch.compile` compiles the batch
entries of the same kernel.
"""

from __future__ import annotations

from collections.abc import Callable

from redik.core import compile_ahead
from redik.kinematics.robot import load
from redik.solvers.pose import solve_pose


def _solve_pose() -> object:
    robot = load("panda")
    return solve_pose(robot, robot.fk(robot.home), seed=0)


#: What :func:`redik.core.compile_ahead.compile_all` runs, by name.
STEPS: dict[str, Callable[[], object]] = {"solve_one (solve_pose)": _solve_pose}


if __name__ == "__main__":
    compile_ahead.main(STEPS)
