r"""The slots a class kernel fills: one candidate solution each.

A kernel fills ``q`` (S, 18), one slot row per branch combination (the joint values, then the
cosines and sines of the angles, :mod:`redik.solvers.analytic.chain`), and three (S,) integer
arrays: ``status`` — :data:`EMPTY`, :data:`REGULAR` or :data:`SINGULAR` (a subproblem was at
its boundary, or left a joint free) —, ``free``, the joint a degenerate subproblem left
arbitrary (−1 if none; it takes ``fix_value`` when ``fix_joint`` names it, else 0), and
``stage``, the step at which an empty slot failed (:data:`STAGES`).
"""

from __future__ import annotations

import numba
import numpy as np

from redik.kinematics.compiled import COMPILE

EMPTY, REGULAR, SINGULAR = 0, 1, 2

#: Why a slot is empty, by its ``stage``.
STAGES = {
    1: "the shoulder subproblem (θ1 / wrist-centre position) has no solution",
    2: "the elbow subproblem (distance to the wrist point) has no solution",
    3: "the wrist subproblem (orientation) has no solution",
    4: "a branch's forward kinematics missed the target",
}


@numba.njit(**COMPILE)
def new_slots(count):
    """Empty slots.

    ``(q, status, free, stage, codes)`` for ``count`` empty slots (``codes``: their label
    codes, :mod:`redik.solvers.analytic.labels`).
    """
    q = np.zeros((count, 18))
    flags = np.zeros((4, count), np.int64)
    flags[1] = -1
    return q, flags[0], flags[1], flags[2], flags[3]


@numba.njit(**COMPILE)
def store(q, slot, angles, cosines, sines):
    """Write a slot row: its six values, then their cosines, then their sines."""
    for j in range(6):
        q[slot, j] = angles[j]
        q[slot, 6 + j] = cosines[j]
        q[slot, 12 + j] = sines[j]


@numba.njit(**COMPILE)
def empty(slot, count, stage_code, status, stage, free):
    """Mark ``count`` slots from ``slot`` empty, failed at ``stage_code``."""
    for index in range(slot, slot + count):
        status[index], stage[index], free[index] = EMPTY, stage_code, -1


@numba.njit(**COMPILE)
def status_of(*codes):
    """SINGULAR when any subproblem status code is not OK (0), else REGULAR."""
    for code in codes:
        if code != 0:
            return SINGULAR
    return REGULAR


@numba.njit(**COMPILE)
def fixed(fix_joint, fix_value, joint):
    """The value a free joint takes: ``fix_value`` for the joint a family fixes, else 0."""
    return fix_value if fix_joint == joint else 0.0
