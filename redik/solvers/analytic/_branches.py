r"""Which physical branch a PUMA, UR or Stanford solution is on, from its joints (compiled).

:class:`redik.solvers.analytic.AnalyticSolver` solves these two families with the compiled
subproblem decomposition (:mod:`.decomposed`) and names each solution by the slot the
family's own kernel (:mod:`.puma`, :mod:`.ur`) would have put it in, so that both paths give
the same labelled set (tested equal on random poses). Each slot is
``4·shoulder + 2·elbow + wrist`` of :data:`._arm.ARM_LABELS`, read off the angles by the
family's definitions (module docstrings of :mod:`.puma`, :mod:`.ur`, :mod:`.stanford`), in
its DH base frame ``T``:

- *shoulder*: the signed lateral reach ``X = c1 p_x + s1 p_y`` of the wrist point (PUMA: the
  wrist centre ``p − d6 ẑ``; UR: ``p5 = p − d6 ẑ``) has the sign of the "left" slot;
- *elbow*: the 2R branch of :func:`.planar.two_link` (branch 0 has its second angle in
  [0, π]), turned into up/down as each kernel does (it depends on the shoulder side);
- *wrist*: noflip when θ5 ∈ [0, π].

The Stanford arm has no elbow (``2·shoulder + wrist`` of :data:`._arm.SHOULDER_WRIST_LABELS`)
and its solver keeps d3 ≥ 0 only.

Only regular solutions are labelled here: at a singularity a branch sign is 0 and the
family's kernel decides (the caller falls back to it).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from redik.kinematics.compiled import COMPILE


@numba.njit(**COMPILE)
def _slot(shoulder_left, elbow_branch, side_flip, sin5):
    left_right = 0 if shoulder_left else 1
    up_down = elbow_branch ^ left_right ^ side_flip
    wrist = 0 if sin5 >= 0.0 else 1
    return 4 * left_right + 2 * up_down + wrist


@numba.njit(**COMPILE)
def puma_slots_of(q, T, a2, a3, d3, d4, d6):
    """The :mod:`.puma` slot of each row of ``q`` (k, 6) for the base-frame pose ``T``."""
    px = T[0, 3] - d6 * T[0, 2]
    py = T[1, 3] - d6 * T[1, 2]
    side = 1.0 if d3 >= 0.0 else -1.0
    gamma = math.atan2(d4, a3)
    flipped = math.pi if a2 < 0.0 else 0.0
    slots = np.empty(q.shape[0], np.int64)
    for row in range(q.shape[0]):
        reach = math.cos(q[row, 0]) * px + math.sin(q[row, 0]) * py
        branch = 0 if math.sin(q[row, 2] - gamma - flipped) >= 0.0 else 1
        slots[row] = _slot(reach * side > 0.0, branch, 1 if side < 0.0 else 0, math.sin(q[row, 4]))
    return slots


@numba.njit(**COMPILE)
def ur_slots_of(q, T, a2, a3, d4, d6):
    """The :mod:`.ur` slot of each row of ``q`` (k, 6) for the base-frame pose ``T``."""
    px = T[0, 3] - d6 * T[0, 2]
    py = T[1, 3] - d6 * T[1, 2]
    side = -1.0 if d4 > 0.0 else 1.0
    shift2 = math.pi if a2 < 0.0 else 0.0
    shift3 = (math.pi if a3 < 0.0 else 0.0) - shift2
    slots = np.empty(q.shape[0], np.int64)
    for row in range(q.shape[0]):
        reach = math.cos(q[row, 0]) * px + math.sin(q[row, 0]) * py
        branch = 0 if math.sin(q[row, 2] + shift3) >= 0.0 else 1
        slots[row] = _slot(reach * side > 0.0, branch, 1 if side > 0.0 else 0, math.sin(q[row, 4]))
    return slots


@numba.njit(**COMPILE)
def stanford_slots_of(q, T, d2, d6):
    """The :mod:`.stanford` slot (``2·shoulder + wrist``) of each row of ``q`` (k, 6) for the
    base-frame pose ``T``; −1 for a row with d3 < 0, which that solver excludes."""
    px = T[0, 3] - d6 * T[0, 2]
    py = T[1, 3] - d6 * T[1, 2]
    side = 1.0 if d2 >= 0.0 else -1.0
    slots = np.empty(q.shape[0], np.int64)
    for row in range(q.shape[0]):
        reach = math.cos(q[row, 0]) * px + math.sin(q[row, 0]) * py
        left_right = 0 if reach * side > 0.0 else 1
        slots[row] = -1 if q[row, 2] < 0.0 else 2 * left_right + (0 if q[row, 4] >= 0.0 else 1)
    return slots
