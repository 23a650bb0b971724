r"""The classes with a spherical wrist: axes 4, 5, 6 meet at ``w``.

With :math:`Z = R R_M^\top` from the target, the wrist centre is
:math:`p_w = p - Z (p_M - w)`, which joints 1–3 must place; the wrist (:mod:`.wrist`) then
gives θ4–θ6. Each kernel takes ``(T, G, fix_joint, fix_value, tol, q, status, free, stage)``
(:mod:`.slots`) and fills 8 slots, ``2·arm + wrist``.

``spherical_two_intersecting`` (axes 1, 2 meet at ``o``)
    :math:`p_w - o = R_1 R_2 u(θ_3)`, :math:`u = (a_3 - o) + R_3 (w - a_3)`: ‖u‖ = ‖p_w − o‖
    gives θ3 (SP3, elbow ±) and ``rot(−h1, θ1)(p_w − o) = rot(h2, θ2) u`` gives θ1, θ2 (SP2,
    shoulder ±). Slot = 4·shoulder + 2·elbow + wrist.
``spherical_two_parallel`` (axes 2 ∥ 3)
    R2 and R3 keep the component along h2, so ``h2·R1ᵀ(p_w − a1) = h2·(w − a1)`` gives θ1
    (SP4, shoulder ±); then :math:`v = R_1^\top(p_w - a_1) - (a_2 - a_1) = R_2 u(θ_3)` with
    :math:`u = (a_3 - a_2) + R_3 (w - a_3)`: ‖u‖ = ‖v‖ gives θ3 (SP3, elbow ±) and
    ``rot(h2, θ2) u = v`` gives θ2 (SP1).
``spherical`` (any axes 1–3)
    :math:`R_1^\top(p_w - a_1) - (a_2 - a_1) = R_2[(a_3 - a_2) + R_3 (w - a_3)]` is SP5 with
    ``k1 = −h1`` (R1ᵀ = rot(−h1, θ1)): up to 4 (θ1, θ2, θ3), in increasing θ1.
``spherical_two_intersecting_prismatic`` (axes 1, 2 meet at ``o``, joint 3 slides along h3)
    :math:`p_w - o = R_1 R_2 u(d_3)`, :math:`u = (w - o) + d_3 h_3`, so ‖u‖ = ‖p_w − o‖ is the
    intersection of the slide's line with a sphere about ``o`` (the prismatic counterpart of
    SP3): :math:`d_3 = -b·h_3 ± \sqrt{‖p_w - o‖^2 - ‖b_⊥‖^2}`, ``b = w − o`` and ``b⊥`` its
    part across h3; then SP2 as for ``spherical_two_intersecting``.

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
)
from redik.solvers.analytic.kernels.wrist import wrist
from redik.solvers.analytic.labels import (
    arm_and_wrist,
    shoulder_elbow_wrist,
    shoulder_slide_wrist,
)
from redik.solvers.analytic.subproblems import (
    BOUNDARY,
    FREE,
    OK,
    OUT,
    sp1_cs,
    sp2_cs,
    sp3_cs,
    sp4_cs,
    sp5,
)
from redik.solvers.analytic.vectors import add, dot, mul, neg, norm, rotate_cs, row, scale, sub


@numba.njit(**COMPILE)
def _wrist_target(T, G):
    """``(p_w, z, y)``: the wrist centre and the target's images of h6 and of ``e``."""
    z0, z1, z2, p = target_of(T, G)
    pw = sub(p, mul(z0, z1, z2, sub(row(G, TIP), row(G, POINTS + 3))))
    return pw, mul(z0, z1, z2, row(G, AXES + 5)), mul(z0, z1, z2, row(G, PERPENDICULAR))


@numba.njit(**COMPILE)
def _shoulder_then_wrist(G, wrist_frame, o, u, e, third, fix_joint, fix_value, tol, slots):
    """The shoulder (SP2) and the wrist of an arm with axes 1, 2 meeting.

    Slots ``4·shoulder + 2·e + wrist`` of an arm whose axes 1, 2 meet at ``o`` and whose
    third joint has placed the wrist centre at ``o + R1 R2 u``:
    ``rot(−h1, θ1)(p_w − o) = rot(h2, θ2) u`` gives θ1, θ2 (SP2, shoulder ±), then the wrist.

    ``third = (value, cos, sin, status)`` of joint 3 (1 and 0 for a slide);
    ``wrist_frame = (p_w, z, y)`` (:func:`_wrist_target`).
    """
    q, status, free, stage = slots
    pw, z, y = wrist_frame
    t1a, t2a, t1b, t2b, shoulder, which, trig = sp2_cs(
        neg(row(G, AXES)), sub(pw, o), row(G, AXES + 1), u, fixed(fix_joint, fix_value, 0),
        fixed(fix_joint, fix_value, 1), tol,
    )  # fmt: skip
    for s in range(2):
        slot = 4 * s + 2 * e
        if shoulder == OUT:
            empty(slot, 2, 1, status, stage, free)
            continue
        free[slot] = -1 if which == 0 else which - 1
        t1, t2 = (t1a, t2a) if s == 0 else (t1b, t2b)
        cs = (trig[4 * s], trig[4 * s + 1], trig[4 * s + 2], trig[4 * s + 3], third[1], third[2])
        wrist(G, z, y, (t1, t2, third[0]), cs, fix_joint, fix_value, tol, slot, q, status, free,
              stage, status_of(third[3], shoulder))  # fmt: skip
        if shoulder == FREE and s == 1:
            empty(slot, 2, 0, status, stage, free)


@numba.njit(**COMPILE)
def spherical_two_intersecting(T, G, fix_joint, fix_value, tol, q, status, free, stage):
    """Spherical wrist and axes 1, 2 meeting (module docstring)."""
    frame = _wrist_target(T, G)
    h3 = row(G, AXES + 2)
    o, a3, w = row(G, POINTS), row(G, POINTS + 2), row(G, POINTS + 3)
    t3a, t3b, elbow, c3a, s3a, c3b, s3b = sp3_cs(
        h3, sub(w, a3), sub(o, a3), norm(sub(frame[0], o)), tol
    )
    for e in range(2):
        if elbow == OUT:
            empty(2 * e, 2, 2, status, stage, free)
            empty(4 + 2 * e, 2, 2, status, stage, free)
            continue
        t3, c3, s3 = (t3a, c3a, s3a) if e == 0 else (t3b, c3b, s3b)
        u = add(sub(a3, o), rotate_cs(h3, c3, s3, sub(w, a3)))
        _shoulder_then_wrist(G, frame, o, u, e, (t3, c3, s3, elbow), fix_joint, fix_value, tol,
                             (q, status, free, stage))  # fmt: skip
        if elbow == FREE and e == 1:
            empty(2, 2, 0, status, stage, free)
            empty(6, 2, 0, status, stage, free)


@numba.njit(**COMPILE)
def _elbow_sp3(G, v, s, pw_frame, t1, c1, s1, shoulder, fix_joint, fix_value, tol, slots):
    """The two elbows of :func:`spherical_two_parallel` after θ1 (slots ``4·s + 2·e``)."""
    q, status, free, stage = slots
    _, z, y = pw_frame
    h2, h3 = row(G, AXES + 1), row(G, AXES + 2)
    a2, a3, w = row(G, POINTS + 1), row(G, POINTS + 2), row(G, POINTS + 3)
    t3a, t3b, elbow, c3a, s3a, c3b, s3b = sp3_cs(h3, sub(w, a3), sub(a2, a3), norm(v), tol)
    for e in range(2):
        slot = 4 * s + 2 * e
        if elbow == OUT:
            empty(slot, 2, 2, status, stage, free)
            continue
        t3, c3, s3 = (t3a, c3a, s3a) if e == 0 else (t3b, c3b, s3b)
        u = add(sub(a3, a2), rotate_cs(h3, c3, s3, sub(w, a3)))
        t2, c2, s2, reach = sp1_cs(h2, u, v)
        if reach <= tol:  # the wrist centre on axis 2: θ2 is free
            t2 = fixed(fix_joint, fix_value, 1)
            c2, s2 = math.cos(t2), math.sin(t2)
        free[slot] = 0 if shoulder == FREE else (1 if reach <= tol else -1)
        arm = status_of(shoulder, elbow, 1 if reach <= tol else 0)
        wrist(G, z, y, (t1, t2, t3), (c1, s1, c2, s2, c3, s3), fix_joint, fix_value, tol, slot,
              q, status, free, stage, arm)  # fmt: skip
        if elbow == FREE and e == 1:
            empty(slot, 2, 0, status, stage, free)


@numba.njit(**COMPILE)
def spherical_two_parallel(T, G, fix_joint, fix_value, tol, q, status, free, stage):
    """Spherical wrist and axes 2 ∥ 3 (module docstring)."""
    frame = _wrist_target(T, G)
    pw = frame[0]
    h1, h2 = row(G, AXES), row(G, AXES + 1)
    a1, a2, w = row(G, POINTS), row(G, POINTS + 1), row(G, POINTS + 3)
    t1a, t1b, shoulder, c1a, s1a, c1b, s1b = sp4_cs(
        h2, neg(h1), sub(pw, a1), dot(h2, sub(w, a1)), tol
    )
    if shoulder == FREE:
        t1a = t1b = fixed(fix_joint, fix_value, 0)
        c1a = c1b = math.cos(t1a)
        s1a = s1b = math.sin(t1a)
    for s in range(2):
        if shoulder == OUT or (shoulder == FREE and s == 1):
            empty(4 * s, 4, 1 if shoulder == OUT else 0, status, stage, free)
            continue
        t1, c1, s1 = (t1a, c1a, s1a) if s == 0 else (t1b, c1b, s1b)
        v = sub(rotate_cs(h1, c1, -s1, sub(pw, a1)), sub(a2, a1))
        _elbow_sp3(G, v, s, frame, t1, c1, s1, shoulder, fix_joint, fix_value, tol,
                   (q, status, free, stage))  # fmt: skip


@numba.njit(**COMPILE)
def _by_first_angle(arm, count):
    """The order of the first ``count`` rows of ``arm`` by increasing first column."""
    order = np.arange(4)
    for i in range(1, count):
        j = i
        while j > 0 and arm[order[j], 0] < arm[order[j - 1], 0]:
            order[j], order[j - 1] = order[j - 1], order[j]
            j -= 1
    return order


@numba.njit(**COMPILE)
def spherical(T, G, fix_joint, fix_value, tol, q, status, free, stage):
    """Spherical wrist and any axes 1–3, by SP5.

    Spherical wrist and any axes 1–3 by SP5 (module docstring); slot = 2·(arm solution by
    increasing θ1) + wrist.
    """
    pw, z, y = _wrist_target(T, G)
    h1, h2, h3 = row(G, AXES), row(G, AXES + 1), row(G, AXES + 2)
    a1, a2, a3, w = row(G, POINTS), row(G, POINTS + 1), row(G, POINTS + 2), row(G, POINTS + 3)
    arm = np.empty((4, 4))
    count = sp5(sub(a1, a2), neg(h1), sub(pw, a1), h2, sub(a3, a2), h3, sub(w, a3), arm)
    empty(2 * count, q.shape[0] - 2 * count, 1, status, stage, free)
    order = _by_first_angle(arm, count)
    for rank in range(count):
        t1, t2, t3 = arm[order[rank], 0], arm[order[rank], 1], arm[order[rank], 2]
        cs = (math.cos(t1), math.sin(t1), math.cos(t2), math.sin(t2), math.cos(t3), math.sin(t3))
        arm_status = SINGULAR if arm[order[rank], 3] != 0.0 else REGULAR
        wrist(G, z, y, (t1, t2, t3), cs, fix_joint, fix_value, tol, 2 * rank, q, status, free,
              stage, arm_status)  # fmt: skip


@numba.njit(**COMPILE)
def spherical_two_intersecting_prismatic(T, G, fix_joint, fix_value, tol, q, status, free, stage):
    """The Stanford arm's class.

    Axes 1, 2 meeting, joint 3 sliding, spherical wrist: the Stanford arm's class (module
    docstring). Slot = 4·shoulder + 2·slide + wrist.
    """
    frame = _wrist_target(T, G)
    h3 = row(G, AXES + 2)
    o, w = row(G, POINTS), row(G, POINTS + 3)
    b = sub(w, o)
    along = dot(b, h3)
    across = norm(sub(b, scale(h3, along)))  # distance of the slide's line from o
    radius = norm(sub(frame[0], o))
    reach = OUT if radius < across - tol else (BOUNDARY if abs(radius - across) <= tol else OK)
    half = 0.0 if reach != OK else math.sqrt((radius - across) * (radius + across))
    for e in range(2):
        if reach == OUT:
            empty(2 * e, 2, 2, status, stage, free)
            empty(4 + 2 * e, 2, 2, status, stage, free)
            continue
        d3 = -along + half if e == 0 else -along - half
        _shoulder_then_wrist(G, frame, o, add(b, scale(h3, d3)), e, (d3, 1.0, 0.0, reach),
                             fix_joint, fix_value, tol, (q, status, free, stage))  # fmt: skip


# --------------------------------------------------------------------------------------
# Entries: one compiled call per class, compiled on first use; written out per class for
# numba's cache (the note in kernels/__init__.py).


@numba.njit(**COMPILE)
def solve_spherical_two_intersecting(T, plan):
    """The closed form of ``spherical_two_intersecting`` (:mod:`redik.solvers.analytic.finish`)."""
    valid, target, G, tol, fix_joint, fix_value = begin(T, plan)
    if not valid:
        return invalid()
    q, status, free, stage, codes = new_slots(8)
    spherical_two_intersecting(target, G, fix_joint, fix_value, tol, q,
                               status, free, stage)  # fmt: skip
    verify(target, G, plan, q, status, free, stage)
    if labelled(plan):
        shoulder_elbow_wrist(target, G, q, status, 3, False, codes)
    return select(G, plan, q, status, free, stage, codes)


@numba.njit(**COMPILE)
def solve_spherical_two_parallel(T, plan):
    """The closed form of ``spherical_two_parallel`` (:mod:`redik.solvers.analytic.finish`)."""
    valid, target, G, tol, fix_joint, fix_value = begin(T, plan)
    if not valid:
        return invalid()
    q, status, free, stage, codes = new_slots(8)
    spherical_two_parallel(target, G, fix_joint, fix_value, tol, q, status,
                           free, stage)  # fmt: skip
    verify(target, G, plan, q, status, free, stage)
    if labelled(plan):
        shoulder_elbow_wrist(target, G, q, status, 3, False, codes)
    return select(G, plan, q, status, free, stage, codes)


@numba.njit(**COMPILE)
def solve_spherical(T, plan):
    """The closed form of ``spherical`` (:mod:`redik.solvers.analytic.finish`)."""
    valid, target, G, tol, fix_joint, fix_value = begin(T, plan)
    if not valid:
        return invalid()
    q, status, free, stage, codes = new_slots(8)
    spherical(target, G, fix_joint, fix_value, tol, q, status, free, stage)
    verify(target, G, plan, q, status, free, stage)
    if labelled(plan):
        arm_and_wrist(G, q, status, codes)
    return select(G, plan, q, status, free, stage, codes)


@numba.njit(**COMPILE)
def solve_spherical_two_intersecting_prismatic(T, plan):
    """The closed form of ``spherical_two_intersecting_prismatic``.

    The closed form of ``spherical_two_intersecting_prismatic``
    (:mod:`redik.solvers.analytic.finish`).
    """
    valid, target, G, tol, fix_joint, fix_value = begin(T, plan)
    if not valid:
        return invalid()
    q, status, free, stage, codes = new_slots(8)
    spherical_two_intersecting_prismatic(target, G, fix_joint, fix_value,
                                         tol, q, status, free, stage)  # fmt: skip
    verify(target, G, plan, q, status, free, stage)
    if labelled(plan):
        shoulder_slide_wrist(target, G, q, status, codes)
    return select(G, plan, q, status, free, stage, codes)


@numba.njit(parallel=True, **COMPILE)
def batch_spherical_two_intersecting(T, plan, q, valid, singular):
    """``spherical_two_intersecting`` on a stack of targets, threaded.

    Each target of the (B, 4, 4) stack is solved, verified and labelled as by
    :func:`solve_spherical_two_intersecting`;
    its solutions go into ``q`` (B, S, 6), ``valid`` and ``singular`` (B, S) by label code.
    """
    for b in numba.prange(T.shape[0]):
        ok, target, G, tol, _, _ = begin(T[b], plan)
        if not ok:
            continue
        slots, status, free, stage, codes = new_slots(8)
        spherical_two_intersecting(target, G, -1, 0.0, tol, slots, status, free, stage)
        verify(target, G, plan, slots, status, free, stage)
        shoulder_elbow_wrist(target, G, slots, status, 3, False, codes)
        scatter_slots(G, plan, slots, status, codes, b, q, valid, singular)


@numba.njit(parallel=True, **COMPILE)
def batch_spherical_two_parallel(T, plan, q, valid, singular):
    """``spherical_two_parallel`` on a stack of targets, threaded.

    Each target of the (B, 4, 4) stack is solved, verified and labelled as by
    :func:`solve_spherical_two_parallel`;
    its solutions go into ``q`` (B, S, 6), ``valid`` and ``singular`` (B, S) by label code.
    """
    for b in numba.prange(T.shape[0]):
        ok, target, G, tol, _, _ = begin(T[b], plan)
        if not ok:
            continue
        slots, status, free, stage, codes = new_slots(8)
        spherical_two_parallel(target, G, -1, 0.0, tol, slots, status, free, stage)
        verify(target, G, plan, slots, status, free, stage)
        shoulder_elbow_wrist(target, G, slots, status, 3, False, codes)
        scatter_slots(G, plan, slots, status, codes, b, q, valid, singular)


@numba.njit(parallel=True, **COMPILE)
def batch_spherical(T, plan, q, valid, singular):
    """``spherical`` on a stack of targets, threaded.

    Each target of the (B, 4, 4) stack is solved, verified and labelled as by
    :func:`solve_spherical`;
    its solutions go into ``q`` (B, S, 6), ``valid`` and ``singular`` (B, S) by label code.
    """
    for b in numba.prange(T.shape[0]):
        ok, target, G, tol, _, _ = begin(T[b], plan)
        if not ok:
            continue
        slots, status, free, stage, codes = new_slots(8)
        spherical(target, G, -1, 0.0, tol, slots, status, free, stage)
        verify(target, G, plan, slots, status, free, stage)
        arm_and_wrist(G, slots, status, codes)
        scatter_slots(G, plan, slots, status, codes, b, q, valid, singular)


@numba.njit(parallel=True, **COMPILE)
def batch_spherical_two_intersecting_prismatic(T, plan, q, valid, singular):
    """``spherical_two_intersecting_prismatic`` on a stack of targets, threaded.

    Each target of the (B, 4, 4) stack is solved, verified and labelled as by
    :func:`solve_spherical_two_intersecting_prismatic`;
    its solutions go into ``q`` (B, S, 6), ``valid`` and ``singular`` (B, S) by label code.
    """
    for b in numba.prange(T.shape[0]):
        ok, target, G, tol, _, _ = begin(T[b], plan)
        if not ok:
            continue
        slots, status, free, stage, codes = new_slots(8)
        spherical_two_intersecting_prismatic(target, G, -1, 0.0, tol, slots, status, free, stage)
        verify(target, G, plan, slots, status, free, stage)
        shoulder_slide_wrist(target, G, slots, status, codes)
        scatter_slots(G, plan, slots, status, codes, b, q, valid, singular)
