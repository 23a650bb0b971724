r"""The spherical wrist of every wrist class: axes 4, 5, 6 through one point.

With the arm angles θ1–θ3 known, :math:`R_{36} = R_3^\top R_2^\top R_1^\top Z = R_4 R_5 R_6`;
``R6`` keeps ``h6`` and ``R4ᵀ`` is a rotation about ``−h4``, so

.. math:: \mathrm{rot}(-h_4, θ_4)\, R_{36} h_6 = \mathrm{rot}(h_5, θ_5)\, h_6

is SP2 (two solutions, "noflip" and "flip" for a ZYZ wrist), and
``rot(h6, θ6) e = R5ᵀ R4ᵀ R36 e`` (``e`` ⊥ h6) is SP1. The wrist axes may be any three axes
through one point with consecutive axes not parallel: ZYZ, ZYX, ZXZ and skew ones.
"""

from __future__ import annotations

import numba

from redik.kinematics.compiled import COMPILE
from redik.solvers.analytic.chain import AXES, PERPENDICULAR
from redik.solvers.analytic.kernels.slots import EMPTY, SINGULAR, fixed, store
from redik.solvers.analytic.subproblems import BOUNDARY, FREE, OUT, sp1_cs, sp2_cs
from redik.solvers.analytic.vectors import neg, rotate_cs, row


@numba.njit(**COMPILE)
def _arm_inverse(G, cs, v):
    """Undo the arm's three rotations.

    ``R3ᵀ R2ᵀ R1ᵀ v`` for the arm angles' cosines and sines ``cs = (c1, s1, c2, s2, c3, s3)``
    (a slide's "cosine and sine" are 1 and 0).
    """
    h1, h2, h3 = row(G, AXES), row(G, AXES + 1), row(G, AXES + 2)
    return rotate_cs(
        h3, cs[4], -cs[5], rotate_cs(h2, cs[2], -cs[3], rotate_cs(h1, cs[0], -cs[1], v))
    )


@numba.njit(**COMPILE)
def wrist(G, z, y, t, cs, fix_joint, fix_value, tol, slot, q, status, free, stage, arm_status):
    """Fill slots ``slot`` and ``slot + 1`` with the two wrist solutions after the arm.

    Args:
        G: The packed chain.
        z: ``Z h6``, the target's image of the last axis.
        y: ``Z e``, the target's image of the perpendicular ``e`` (row 16 of ``G``).
        t: The arm's values ``(θ1, θ2, θ3)``.
        cs: Their cosines and sines ``(c1, s1, c2, s2, c3, s3)``.
        fix_joint: A joint held at ``fix_value`` (a family member), or −1.
        fix_value: Its value (rad).
        tol: The subproblems' tolerance (m).
        slot: The first of the two slots.
        q: The slot rows (:mod:`.slots`).
        status: The slots' status codes.
        free: The slots' free joints; ``free[slot]`` already holds the arm's.
        stage: The stage at which an empty slot failed.
        arm_status: REGULAR or SINGULAR, what the arm's subproblems found.
    """
    h4, h5, h6, e = row(G, AXES + 3), row(G, AXES + 4), row(G, AXES + 5), row(G, PERPENDICULAR)
    zw, yw = _arm_inverse(G, cs, z), _arm_inverse(G, cs, y)
    t4a, t5a, t4b, t5b, result, which, trig = sp2_cs(
        neg(h4), zw, h5, h6, fixed(fix_joint, fix_value, 3), 0.0, tol
    )
    arm_free = free[slot]
    for branch in range(2):
        index = slot + branch
        c4, s4 = trig[4 * branch], trig[4 * branch + 1]  # θ4 is an angle about −h4: R4ᵀ
        c5, s5 = trig[4 * branch + 2], trig[4 * branch + 3]
        t6, c6, s6, _ = sp1_cs(h6, e, rotate_cs(h5, c5, -s5, rotate_cs(h4, c4, -s4, yw)))
        t4, t5 = (t4a, t5a) if branch == 0 else (t4b, t5b)
        store(q, index, (t[0], t[1], t[2], t4, t5, t6), (cs[0], cs[2], cs[4], c4, c5, c6),
              (cs[1], cs[3], cs[5], s4, s5, s6))  # fmt: skip
        free[index] = arm_free
        status[index] = arm_status
        if result == OUT:
            status[index], stage[index] = EMPTY, 3
        elif result == FREE and branch == 1:
            status[index], stage[index] = EMPTY, 0  # the same family as the first slot
        elif result == FREE:
            status[index] = SINGULAR
            free[index] = 3 if which == 1 else 5
        elif result == BOUNDARY:
            status[index] = SINGULAR
