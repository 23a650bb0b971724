r"""The classes with three parallel axes 2 ∥ 3 ∥ 4 (direction ``h``).

:math:`R_2 R_3 R_4 = R_{234}` keeps every component along h, so projecting the chain on h
leaves equations in θ1, θ5, θ6 only. With :math:`Z = R R_M^\top` from the target:

- position: :math:`h·R_1^\top[(p - a_1) - Z(p_M - a_6)] - h·R_5(a_6 - a_5) = h·(a_5 - a_1)`,
- orientation: :math:`h·R_1^\top Z h_6 = h·R_5 h_6` (as :math:`h^\top R_5 R_6 = h^\top
  R_1^\top Z` and R6 keeps h6).

``three_parallel_two_intersecting`` (axes 5, 6 meet at ``w``: Universal Robots)
    with :math:`p_w = p - Z(p_M - w)` the position equation no longer holds θ5:
    ``h·R1ᵀ(p_w − a1) = h·(w − a1)`` gives θ1 (SP4, shoulder ±), then the orientation
    equation θ5 (SP4, wrist ±). Slot = 4·shoulder + 2·elbow + wrist.
``three_parallel`` (any axes 1, 5, 6)
    the two equations are linear in (cos θ1, sin θ1, cos θ5, sin θ5): SP6, up to 4 (θ1, θ5),
    in increasing θ1. Slot = 2·(SP6 root) + elbow.

Then, for both: ``rot(h6, θ6)(Zᵀ R1 h) = R5ᵀ h`` gives θ6 (SP1; arbitrary when Zᵀ R1 h ∥ h6,
the wrist singularity), :math:`R_{234} = R_1^\top Z R_6^\top R_5^\top` gives θ234 (SP1 on
``e`` ⊥ h), and :math:`v = R_1^\top(p - a_1) - (a_2 - a_1) - R_{234}\,τ = R_2 u(θ_3)`, with
:math:`τ = (a_5 - a_4) + R_5((a_6 - a_5) + R_6(p_M - a_6))` and
:math:`u = (a_3 - a_2) + R_3(a_4 - a_3)`: ‖u‖ = ‖v‖ gives θ3 (SP3, elbow ±),
``rot(h, θ2) u = v`` gives θ2 (SP1), and θ4 = θ234 − θ2 − θ3 (Hawkins 2013 and Andersen 2018
for the UR arms; Elias & Wen 2022, §IV, for both classes).

Each class has an entry ``solve_<class>(T, plan)``
(:mod:`redik.solvers.analytic.finish`) and a threaded ``batch_<class>``.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from redik.kinematics.compiled import COMPILE
from redik.solvers.analytic.chain import AXES, PERPENDICULAR, POINTS, TIP, target_of
from redik.solvers.analytic.finish import (
    begin,
    invalid,
    labelled,
    scatter_slots,
    select,
    verify,
)
from redik.solvers.analytic.kernels.slots import (
    REGULAR,
    SINGULAR,
    empty,
    fixed,
    new_slots,
    status_of,
    store,
)
from redik.solvers.analytic.labels import arm_and_elbow, shoulder_elbow_wrist
from redik.solvers.analytic.subproblems import FREE, OUT, sp1_cs, sp3_cs, sp4_cs, sp6
from redik.solvers.analytic.vectors import add, dot, mul, mul_t, neg, norm, rotate_cs, row, sub


@numba.njit(**COMPILE)
def _tail(G, c5, s5, c6, s6):
    """``τ = (a5 − a4) + R5((a6 − a5) + R6(p_M − a6))``."""
    a4, a5, a6 = row(G, POINTS + 3), row(G, POINTS + 4), row(G, POINTS + 5)
    inner = add(sub(a6, a5), rotate_cs(row(G, AXES + 5), c6, s6, sub(row(G, TIP), a6)))
    return add(sub(a5, a4), rotate_cs(row(G, AXES + 4), c5, s5, inner))


@numba.njit(**COMPILE)
def _last_two(G, Z, one, five, fix_joint, fix_value, tol):
    """θ6 and θ234 after θ1 and θ5.

    θ6 and θ234 after θ1 and θ5 (module docstring): ``(t6, c6, s6, t234, c234, s234,
    wrist_free)``.
    """
    z0, z1, z2 = Z
    h, h5, h6, e = row(G, AXES + 1), row(G, AXES + 4), row(G, AXES + 5), row(G, PERPENDICULAR)
    R1h = rotate_cs(row(G, AXES), one[1], one[2], h)
    t6, c6, s6, reach = sp1_cs(h6, mul_t(z0, z1, z2, R1h), rotate_cs(h5, five[1], -five[2], h))
    if reach <= tol:
        t6 = fixed(fix_joint, fix_value, 5)
        c6, s6 = math.cos(t6), math.sin(t6)
    image = rotate_cs(h6, c6, -s6, rotate_cs(h5, five[1], -five[2], e))
    back = rotate_cs(row(G, AXES), one[1], -one[2], mul(z0, z1, z2, image))
    t234, c234, s234, _ = sp1_cs(h, e, back)
    return t6, c6, s6, t234, c234, s234, reach <= tol


@numba.njit(**COMPILE)
def _elbows(G, p, one, five, six, one_two_three_four, slots, first, step, arm):
    """The two elbows after θ1, θ5, θ6, θ234: slots ``first`` and ``first + step``.

    ``one, five, six, one_two_three_four`` are ``(value, cos, sin)`` of θ1, θ5, θ6, θ234;
    ``arm = (status, free, fix_joint, fix_value, tol)`` of what came before.
    """
    q, status, free, stage = slots
    arm_status, arm_free, fix_joint, fix_value, tol = arm
    h, a1, a2, a3, a4 = (
        row(G, AXES + 1),
        row(G, POINTS),
        row(G, POINTS + 1),
        row(G, POINTS + 2),
        row(G, POINTS + 3),
    )
    t234, c234, s234 = one_two_three_four
    tail = _tail(G, five[1], five[2], six[1], six[2])
    v = sub(sub(rotate_cs(row(G, AXES), one[1], -one[2], sub(p, a1)), sub(a2, a1)),
            rotate_cs(h, c234, s234, tail))  # fmt: skip
    t3a, t3b, elbow, c3a, s3a, c3b, s3b = sp3_cs(h, sub(a4, a3), sub(a2, a3), norm(v), tol)
    for el in range(2):
        slot = first + step * el
        if elbow == OUT or (elbow == FREE and el == 1):
            empty(slot, 1, 2 if elbow == OUT else 0, status, stage, free)
            continue
        t3, c3, s3 = (t3a, c3a, s3a) if el == 0 else (t3b, c3b, s3b)
        u = add(sub(a3, a2), rotate_cs(h, c3, s3, sub(a4, a3)))
        t2, c2, s2, reach = sp1_cs(h, u, v)
        if reach <= tol:  # the wrist point on axis 2: θ2 is free
            t2 = fixed(fix_joint, fix_value, 1)
            c2, s2 = math.cos(t2), math.sin(t2)
        # θ4 = θ234 − (θ2 + θ3), its cosine and sine by the angle-sum formulas.
        c23, s23 = c2 * c3 - s2 * s3, s2 * c3 + c2 * s3
        c4, s4 = c234 * c23 + s234 * s23, s234 * c23 - c234 * s23
        angles = (one[0], t2, t3, t234 - t2 - t3, five[0], six[0])
        store(q, slot, angles, (one[1], c2, c3, c4, five[1], six[1]),
              (one[2], s2, s3, s4, five[2], six[2]))  # fmt: skip
        status[slot] = (
            SINGULAR if arm_status == SINGULAR else status_of(elbow, 1 if reach <= tol else 0)
        )
        free[slot] = arm_free if arm_free >= 0 else (1 if reach <= tol else -1)
        stage[slot] = 0


@numba.njit(**COMPILE)
def _after_shoulder(G, Z, p, one, shoulder, s, fix_joint, fix_value, tol, slots):
    """The UR class after θ1 (shoulder branch ``s``): θ5 (SP4), then θ6, θ234 and the elbows."""
    _, status, free, stage = slots
    z0, z1, z2 = Z
    h, h5, h6 = row(G, AXES + 1), row(G, AXES + 4), row(G, AXES + 5)
    height = dot(h, rotate_cs(row(G, AXES), one[1], -one[2], mul(z0, z1, z2, h6)))
    t5a, t5b, result5, c5a, s5a, c5b, s5b = sp4_cs(h, h5, h6, height, tol)
    for wrist in range(2):
        if result5 == OUT or (result5 == FREE and wrist == 1):
            stage_code = 3 if result5 == OUT else 0
            empty(4 * s + wrist, 1, stage_code, status, stage, free)
            empty(4 * s + 2 + wrist, 1, stage_code, status, stage, free)
            continue
        five = (t5a, c5a, s5a) if wrist == 0 else (t5b, c5b, s5b)
        t6, c6, s6, t234, c234, s234, wrist_free = _last_two(
            G, Z, one, five, fix_joint, fix_value, tol
        )
        arm_status = status_of(shoulder, result5, 1 if wrist_free else 0)
        arm_free = 0 if shoulder == FREE else (5 if wrist_free else -1)
        _elbows(G, p, one, five, (t6, c6, s6), (t234, c234, s234), slots, 4 * s + wrist, 2,
                (arm_status, arm_free, fix_joint, fix_value, tol))  # fmt: skip


@numba.njit(**COMPILE)
def three_parallel_two_intersecting(T, G, fix_joint, fix_value, tol, q, status, free, stage):
    """Axes 2 ∥ 3 ∥ 4 and axes 5, 6 meeting: the UR class (module docstring)."""
    z0, z1, z2, p = target_of(T, G)
    h1, h, a1, w = row(G, AXES), row(G, AXES + 1), row(G, POINTS), row(G, POINTS + 4)
    pw = sub(p, mul(z0, z1, z2, sub(row(G, TIP), w)))
    t1a, t1b, shoulder, c1a, s1a, c1b, s1b = sp4_cs(
        h, neg(h1), sub(pw, a1), dot(h, sub(w, a1)), tol
    )
    if shoulder == FREE:
        t1a = t1b = fixed(fix_joint, fix_value, 0)
        c1a = c1b = math.cos(t1a)
        s1a = s1b = math.sin(t1a)
    for s in range(2):
        if shoulder == OUT or (shoulder == FREE and s == 1):
            empty(4 * s, 4, 1 if shoulder == OUT else 0, status, stage, free)
            continue
        one = (t1a, c1a, s1a) if s == 0 else (t1b, c1b, s1b)
        _after_shoulder(G, (z0, z1, z2), p, one, shoulder, s, fix_joint, fix_value, tol,
                        (q, status, free, stage))  # fmt: skip


@numba.njit(**COMPILE)
def _sp6_roots(G, Z, p, pairs):
    """θ1, θ5 of the three-parallel class by SP6.

    θ1, θ5 of the three-parallel class by SP6 (module docstring) into ``pairs`` (4, 3:
    θ1, θ5, tangent), in increasing θ1; returns how many.
    """
    z0, z1, z2 = Z
    h1, h, h5, h6 = row(G, AXES), row(G, AXES + 1), row(G, AXES + 4), row(G, AXES + 5)
    a1, a5, a6 = row(G, POINTS), row(G, POINTS + 4), row(G, POINTS + 5)
    P = sub(sub(p, a1), mul(z0, z1, z2, sub(row(G, TIP), a6)))
    count = sp6(h, neg(h1), P, h, h5, sub(a5, a6), h, neg(h1), mul(z0, z1, z2, h6), h, h5,
                neg(h6), dot(h, sub(a5, a1)), 0.0, pairs)  # fmt: skip
    for i in range(1, count):  # insertion sort by θ1 (at most 4 rows)
        j = i
        while j > 0 and pairs[j, 0] < pairs[j - 1, 0]:
            for c in range(3):
                pairs[j, c], pairs[j - 1, c] = pairs[j - 1, c], pairs[j, c]
            j -= 1
    return count


@numba.njit(**COMPILE)
def three_parallel(T, G, fix_joint, fix_value, tol, q, status, free, stage):
    """Axes 2 ∥ 3 ∥ 4 and any axes 1, 5, 6, by SP6 (module docstring)."""
    z0, z1, z2, p = target_of(T, G)
    pairs = np.empty((4, 3))
    count = _sp6_roots(G, (z0, z1, z2), p, pairs)
    empty(2 * count, q.shape[0] - 2 * count, 1, status, stage, free)
    for r in range(count):
        one = (pairs[r, 0], math.cos(pairs[r, 0]), math.sin(pairs[r, 0]))
        five = (pairs[r, 1], math.cos(pairs[r, 1]), math.sin(pairs[r, 1]))
        t6, c6, s6, t234, c234, s234, wrist_free = _last_two(
            G, (z0, z1, z2), one, five, fix_joint, fix_value, tol
        )
        singular = wrist_free or pairs[r, 2] != 0.0
        arm = (
            SINGULAR if singular else REGULAR,
            5 if wrist_free else -1,
            fix_joint,
            fix_value,
            tol,
        )
        _elbows(G, p, one, five, (t6, c6, s6), (t234, c234, s234), (q, status, free, stage),
                2 * r, 1, arm)  # fmt: skip


# --------------------------------------------------------------------------------------
# Entries: one compiled call per class, compiled on first use; written out per class for
# numba's cache (the note in kernels/__init__.py).


@numba.njit(**COMPILE)
def solve_three_parallel_two_intersecting(T, plan):
    """The closed form of ``three_parallel_two_intersecting``.

    The closed form of ``three_parallel_two_intersecting``
    (:mod:`redik.solvers.analytic.finish`).
    """
    valid, target, G, tol, fix_joint, fix_value = begin(T, plan)
    if not valid:
        return invalid()
    q, status, free, stage, codes = new_slots(8)
    three_parallel_two_intersecting(target, G, fix_joint, fix_value, tol, q,
                                    status, free, stage)  # fmt: skip
    verify(target, G, plan, q, status, free, stage)
    if labelled(plan):
        shoulder_elbow_wrist(target, G, q, status, 4, True, codes)
    return select(G, plan, q, status, free, stage, codes)


@numba.njit(**COMPILE)
def solve_three_parallel(T, plan):
    """The closed form of ``three_parallel`` (:mod:`redik.solvers.analytic.finish`)."""
    valid, target, G, tol, fix_joint, fix_value = begin(T, plan)
    if not valid:
        return invalid()
    q, status, free, stage, codes = new_slots(8)
    three_parallel(target, G, fix_joint, fix_value, tol, q, status, free, stage)
    verify(target, G, plan, q, status, free, stage)
    if labelled(plan):
        arm_and_elbow(G, q, status, codes)
    return select(G, plan, q, status, free, stage, codes)


@numba.njit(parallel=True, **COMPILE)
def batch_three_parallel_two_intersecting(T, plan, q, valid, singular):
    """``three_parallel_two_intersecting`` on a stack of targets, threaded.

    Each target of the (B, 4, 4) stack is solved, verified and labelled as by
    :func:`solve_three_parallel_two_intersecting`;
    its solutions go into ``q`` (B, S, 6), ``valid`` and ``singular`` (B, S) by label code.
    """
    for b in numba.prange(T.shape[0]):
        ok, target, G, tol, _, _ = begin(T[b], plan)
        if not ok:
            continue
        slots, status, free, stage, codes = new_slots(8)
        three_parallel_two_intersecting(target, G, -1, 0.0, tol, slots, status, free, stage)
        verify(target, G, plan, slots, status, free, stage)
        shoulder_elbow_wrist(target, G, slots, status, 4, True, codes)
        scatter_slots(G, plan, slots, status, codes, b, q, valid, singular)


@numba.njit(parallel=True, **COMPILE)
def batch_three_parallel(T, plan, q, valid, singular):
    """``three_parallel`` on a stack of targets, threaded.

    Each target of the (B, 4, 4) stack is solved, verified and labelled as by
    :func:`solve_three_parallel`;
    its solutions go into ``q`` (B, S, 6), ``valid`` and ``singular`` (B, S) by label code.
    """
    for b in numba.prange(T.shape[0]):
        ok, target, G, tol, _, _ = begin(T[b], plan)
        if not ok:
            continue
        slots, status, free, stage, codes = new_slots(8)
        three_parallel(target, G, -1, 0.0, tol, slots, status, free, stage)
        verify(target, G, plan, slots, status, free, stage)
        arm_and_elbow(G, slots, status, codes)
        scatter_slots(G, plan, slots, status, codes, b, q, valid, singular)
