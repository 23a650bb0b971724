"""Compile every closed-form kernel into numba's on-disk cache before it is first used.

``python -m redik.solvers.analytic.compile`` solves one target of a generated arm of each
6-joint class, of a general arm by the elimination (its standard and re-based splits) and of
the small solvers, so that numba compiles each compiled entry and its callees once and caches
them (``cache=True``: next to the sources, or under ``NUMBA_CACHE_DIR``). Nothing here is
needed for correctness — every kernel compiles on its first call anyway — but a cold first
call costs seconds of compilation per class, and a warm one loads it from the cache. Run it
once per machine after installing, as an install step would.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from redik.core import compile_ahead
from redik.lie import se3_exp
from redik.solvers.analytic.elimination import Elimination
from redik.solvers.analytic.geometry import KINDS, Chain, arm_screws, classify, random_arm
from redik.solvers.analytic.planar import planar_2r
from redik.solvers.analytic.six_joint import SixJointSolver


def _arm(kind: str, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Screws ``S`` and home ``M`` of a random arm of a class (:func:`.geometry.random_arm`)."""
    return arm_screws(*random_arm(kind, rng), prismatic=kind.endswith("prismatic"))


def _target(S: np.ndarray, M: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """The pose of random joint values (product of exponentials)."""
    T = M
    for i in reversed(range(6)):
        T = se3_exp(np.concatenate([S[3:, i], S[:3, i]]) * rng.uniform(-1.0, 1.0)) @ T
    return np.ascontiguousarray(T)


def _closed_form(kind: str) -> Callable[[], object]:
    def solve() -> object:
        rng = np.random.default_rng(0)
        S, M = _arm(kind, rng)
        found = classify(S, M)
        assert found is not None and found.kind == kind, kind
        solver = SixJointSolver(found.kind, found.reversed, found.geometry, *_unbounded())
        T = _target(S, M, rng)
        solver(T)
        solver.raw(T)
        return solver.batch(T[None])

    return solve


def _elimination(split: str) -> Callable[[], object]:
    def solve() -> object:
        rng = np.random.default_rng(0)
        S, M = _arm("gen_six_dof", rng)
        elimination = Elimination.build(Chain.from_screws(S, M), False, split, 0)
        return elimination.solve(_target(S, M, rng))

    return solve


def _unbounded() -> tuple[np.ndarray, np.ndarray]:
    return np.full(6, -np.inf), np.full(6, np.inf)


#: What :func:`redik.core.compile_ahead.compile_all` runs, by name.
STEPS: dict[str, Callable[[], object]] = {
    **{kind: _closed_form(kind) for kind in KINDS},
    "elimination (standard split)": _elimination("standard"),
    "elimination (re-based split)": _elimination("rebased"),
    "small solvers' selection": lambda: planar_2r(1.0, 0.5, 1.0, 1.0, limits=([-3, -3], [3, 3])),
}


if __name__ == "__main__":
    compile_ahead.main(STEPS)
