r"""Compiled kernels of :mod:`redik.solvers.analytic.decomposed`: one 6R geometry class each.

The arm is ``T(q) = e^{[S_1]q_1} ⋯ e^{[S_6]q_6} M`` (Modern Robotics §4.1), written as axes
``h_i`` and points ``a_i`` on them (at q = 0, world frame) with the rotations
``R_i = rot(h_i, q_i)`` (IK-Geo's form, Elias & Wen 2022 §II):

.. math::
    p(q) = a_1 + R_1 (a_2 - a_1) + R_1 R_2 (a_3 - a_2) + ⋯ + R_1 ⋯ R_6 (p_M - a_6),\qquad
    R(q) = R_1 ⋯ R_6 R_M .

With :math:`Z = R R_M^\top = R_1 ⋯ R_6` known from the target, each kernel peels the chain
with the subproblems of :mod:`.subproblems`; the derivations are in the docstring of each.
The geometry is packed in one (19, 3) array ``G``: rows 0–5 the axes (a slide's direction for a
prismatic joint), 6–11 the points (where
axes meet, the same point), 12 ``p_M``, 13–15 the rows of ``R_M``, 16 a unit vector
perpendicular to the axis of the last SP1 (``h_6`` for a spherical wrist, the parallel axis of
the three-parallel class), 17–18 one flag per joint, non-zero for a prismatic joint (which
translates by its value along ``h_i``; only the Stanford-type class has one).

A kernel fills slots: ``q`` (S, 18), the six unwrapped angles then their cosines and sines
(which the subproblems produce with each root, so that the FK check needs no trigonometric
call: every angle is the ``atan2`` of its cosine and sine, or ``φ ± arccos c`` with both
formed by the angle-sum formulas, equal to rounding), ``status`` (S,) — :data:`EMPTY`,
:data:`REGULAR` or :data:`SINGULAR` (a subproblem was at its boundary or free) — ``free``
(S,), the joint a degenerate subproblem left arbitrary (−1 if none; it takes ``fix_value``
when ``fix_joint`` names it, else 0), and ``stage`` (S,), the step at which an empty slot
failed (1 shoulder, 2 elbow, 3 wrist).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from redik.core.rotation_policy import ROTATION_TOLERANCE
from redik.kinematics.compiled import COMPILE, valid_target
from redik.solvers.analytic.subproblems import (
    BOUNDARY,
    FREE,
    OK,
    OUT,
    add,
    cross,
    dot,
    norm,
    rotate,
    rotate_cs,
    scale,
    sp1,
    sp1_cs,
    sp2_cs,
    sp3,
    sp3_cs,
    sp4,
    sp4_cs,
    sub,
)

EMPTY, REGULAR, SINGULAR = 0, 1, 2

#: Settings at the end of the ``plan`` array of :func:`solve_raw`.
KIND, REVERSE, TOL, VERIFY, DUPLICATE = range(5)

#: Entries of the packed geometry at the start of a ``plan`` (17 rows of 3).
GEOMETRY_SIZE = 57

#: Kernel identifiers (``kind`` of :func:`solve_raw`).
(
    SPHERICAL_TWO_INTERSECTING,
    SPHERICAL_TWO_PARALLEL,
    SPHERICAL,
    THREE_PARALLEL_TWO_INTERSECTING,
    SPHERICAL_TWO_INTERSECTING_PRISMATIC,
) = range(5)

#: Slots per kernel: 8 for the closed forms, 16 for the searched one (up to 8 arm roots).
SLOTS = (8, 8, 16, 8, 8)

#: FK errors (m / rotation entries) a closed-form slot may have and still be polished by
#: Gauss–Newton (:func:`_polish`), and the steps taken.
POLISH_RANGE = 1e-4
POLISH_STEPS = 3

#: Samples of θ1 on [−π, π) for the 1-D search, and bisection steps per root.
SEARCH_SAMPLES = 720
BISECTIONS = 60

#: Golden-section steps refining a local minimum of ``|f|`` (a possible double root; 0.618⁸⁰
#: of the two-sample bracket is below rounding), and how small ``|f|`` (m) must get there to
#: count as a root. The branch built there is then checked by FK like any other.
GOLDEN_STEPS = 80
TOUCH_TOL = 1e-9


@numba.njit(**COMPILE)
def _row(G, i):
    return (G[i, 0], G[i, 1], G[i, 2])


@numba.njit(**COMPILE)
def _prismatic(G, i):
    """Whether chain joint ``i`` slides (rows 17–18 of ``G`` hold the six flags)."""
    return G[17 + i // 3, i % 3] != 0.0


@numba.njit(**COMPILE)
def _neg(a):
    return (-a[0], -a[1], -a[2])


@numba.njit(**COMPILE)
def _fixed(fix_joint, fix_value, joint):
    return fix_value if fix_joint == joint else 0.0


@numba.njit(**COMPILE)
def _target(T, G):
    """``(Z rows, p)`` with ``Z = R R_Mᵀ``."""
    m0, m1, m2 = _row(G, 13), _row(G, 14), _row(G, 15)
    r0, r1, r2 = (
        (T[0, 0], T[0, 1], T[0, 2]),
        (T[1, 0], T[1, 1], T[1, 2]),
        (T[2, 0], T[2, 1], T[2, 2]),
    )
    return (
        (dot(r0, m0), dot(r0, m1), dot(r0, m2)),
        (dot(r1, m0), dot(r1, m1), dot(r1, m2)),
        (dot(r2, m0), dot(r2, m1), dot(r2, m2)),
        (T[0, 3], T[1, 3], T[2, 3]),
    )


@numba.njit(**COMPILE)
def _mul(z0, z1, z2, v):
    """``Z v`` for the rows of Z."""
    return (dot(z0, v), dot(z1, v), dot(z2, v))


@numba.njit(**COMPILE)
def _mul_t(z0, z1, z2, v):
    """``Zᵀ v``."""
    return add(add(scale(z0, v[0]), scale(z1, v[1])), scale(z2, v[2]))


@numba.njit(**COMPILE)
def _wrist(G, z, y, t, cs, fix_joint, fix_value, tol, slot, q, status, free, stage, pos):
    r"""Fill slots ``slot`` (noflip) and ``slot + 1`` (flip) of a spherical wrist after the arm
    angles ``t = (θ1, θ2, θ3)`` with cosines and sines ``cs = (c1, s1, c2, s2, c3, s3)``
    (``pos`` = the arm's status: REGULAR or SINGULAR, ``free`` already set for an arm
    singularity).

    :math:`R_{36} = R_3^\top R_2^\top R_1^\top Z = R_4 R_5 R_6`, so
    ``rot(−h4, θ4) R36 h6 = rot(h5, θ5) h6`` (SP2) and ``rot(h6, θ6) e = R5ᵀ R4ᵀ R36 e`` (SP1)
    for ``z = Z h6``, ``y = Z e``.
    """
    h1, h2, h3 = _row(G, 0), _row(G, 1), _row(G, 2)
    h4, h5, h6, e = _row(G, 3), _row(G, 4), _row(G, 5), _row(G, 16)
    c1, s1, c2, s2, c3, s3 = cs
    zw = rotate_cs(h3, c3, -s3, rotate_cs(h2, c2, -s2, rotate_cs(h1, c1, -s1, z)))
    yw = rotate_cs(h3, c3, -s3, rotate_cs(h2, c2, -s2, rotate_cs(h1, c1, -s1, y)))
    t4a, t5a, t4b, t5b, result, which, trig = sp2_cs(
        _neg(h4), zw, h5, h6, _fixed(fix_joint, fix_value, 3), 0.0, tol
    )
    arm_free = free[slot]
    for branch in range(2):
        index = slot + branch
        t4 = t4a if branch == 0 else t4b
        t5 = t5a if branch == 0 else t5b
        # θ4 is an angle about −h4: R4ᵀ = rot(−h4, θ4).
        c4, s4 = trig[4 * branch], trig[4 * branch + 1]
        c5, s5 = trig[4 * branch + 2], trig[4 * branch + 3]
        t6, c6, s6, _ = sp1_cs(h6, e, rotate_cs(h5, c5, -s5, rotate_cs(h4, c4, -s4, yw)))
        _store(
            q,
            index,
            (t[0], t[1], t[2], t4, t5, t6),
            (c1, c2, c3, c4, c5, c6),
            (s1, s2, s3, s4, s5, s6),
        )
        free[index] = arm_free
        if result == OUT:
            status[index], stage[index] = EMPTY, 3
        elif result == FREE and branch == 1:
            status[index], stage[index] = EMPTY, 0  # the same family as the noflip slot
        elif result == FREE:
            status[index] = SINGULAR
            free[index] = 3 if which == 1 else 5
        elif result == BOUNDARY:
            status[index] = SINGULAR
        else:
            status[index] = pos


@numba.njit(**COMPILE)
def _store(q, slot, angles, cosines, sines):
    """Write a slot: its six angles, then their cosines, then their sines (a row of 18)."""
    for j in range(6):
        q[slot, j] = angles[j]
        q[slot, 6 + j] = cosines[j]
        q[slot, 12 + j] = sines[j]


@numba.njit(**COMPILE)
def _empty(slot, count, stage_code, status, stage, free):
    for index in range(slot, slot + count):
        status[index], stage[index], free[index] = EMPTY, stage_code, -1


@numba.njit(**COMPILE)
def _status_of(*codes):
    for code in codes:
        if code != 0:
            return SINGULAR
    return REGULAR


@numba.njit(**COMPILE)
def spherical_two_intersecting(T, G, fix_joint, fix_value, tol, q, status, free, stage):
    r"""Spherical wrist (axes 4, 5, 6 meet at ``w``) and axes 1, 2 meeting at ``o``.

    The wrist centre :math:`p_w = p - Z (p_M - w)` satisfies
    :math:`p_w - o = R_1 R_2 u(θ_3)`, :math:`u = (a_3 - o) + R_3 (w - a_3)`, so
    ‖u‖ = ‖p_w − o‖ gives θ3 (SP3, elbow ±) and ``rot(−h1, θ1)(p_w − o) = rot(h2, θ2) u``
    gives θ1, θ2 (SP2, shoulder ±). Slot = 4·shoulder + 2·elbow + wrist.
    """
    z0, z1, z2, p = _target(T, G)
    h3 = _row(G, 2)
    o, a3, w, pM = _row(G, 6), _row(G, 8), _row(G, 9), _row(G, 12)
    pw = sub(p, _mul(z0, z1, z2, sub(pM, w)))
    z = _mul(z0, z1, z2, _row(G, 5))
    y = _mul(z0, z1, z2, _row(G, 16))
    t3a, t3b, elbow, c3a, s3a, c3b, s3b = sp3_cs(h3, sub(w, a3), sub(o, a3), norm(sub(pw, o)), tol)
    for e in range(2):
        t3, c3, s3 = (t3a, c3a, s3a) if e == 0 else (t3b, c3b, s3b)
        if elbow == OUT:
            _empty(2 * e, 2, 2, status, stage, free)
            _empty(4 + 2 * e, 2, 2, status, stage, free)
            continue
        u = add(sub(a3, o), rotate_cs(h3, c3, s3, sub(w, a3)))
        _shoulder_then_wrist(
            G, z, y, pw, o, u, e, t3, c3, s3, elbow, fix_joint, fix_value, tol, q, status,
            free, stage,
        )  # fmt: skip


@numba.njit(**COMPILE)
def _shoulder_then_wrist(
    G, z, y, pw, o, u, e, t3, c3, s3, third, fix_joint, fix_value, tol, q, status, free, stage
):
    """Slots ``4·shoulder + 2·e + wrist`` of an arm whose axes 1, 2 meet at ``o`` and whose
    third joint (value ``t3``; cosine and sine ``c3``, ``s3`` of its rotation, 1 and 0 for a
    slide; ``third`` its status code) has placed the wrist centre at ``o + R1 R2 u``:
    ``rot(−h1, θ1)(p_w − o) = rot(h2, θ2) u`` gives θ1, θ2 (SP2, shoulder ±), then the
    spherical wrist.
    """
    # θ1 is the angle about −h1 here: rot(−h1, θ1) = R1ᵀ.
    t1a, t2a, t1b, t2b, shoulder, which, trig = sp2_cs(
        _neg(_row(G, 0)),
        sub(pw, o),
        _row(G, 1),
        u,
        _fixed(fix_joint, fix_value, 0),
        _fixed(fix_joint, fix_value, 1),
        tol,
    )
    for s in range(2):
        slot = 4 * s + 2 * e
        if shoulder == OUT:
            _empty(slot, 2, 1, status, stage, free)
            continue
        free[slot] = -1 if which == 0 else which - 1
        t1, t2 = (t1a, t2a) if s == 0 else (t1b, t2b)
        c1, s1, c2, s2 = trig[4 * s], trig[4 * s + 1], trig[4 * s + 2], trig[4 * s + 3]
        _wrist(
            G,
            z,
            y,
            (t1, t2, t3),
            (c1, s1, c2, s2, c3, s3),
            fix_joint,
            fix_value,
            tol,
            slot,
            q,
            status,
            free,
            stage,
            _status_of(third, shoulder),
        )
        if shoulder == FREE and s == 1:
            _empty(slot, 2, 0, status, stage, free)


@numba.njit(**COMPILE)
def _shoulder_sp4(G, pw, fix_joint, fix_value, tol, parallel):
    """θ1 (two roots) from ``h·rot(−h1, θ1)(p_w − a1) = h·(w − a1)``, h the axis parallel to the
    next ones (axis 2): everything after joint 1 keeps its offset along h."""
    h1, h, a1, w = _row(G, 0), _row(G, parallel), _row(G, 6), _row(G, 9)
    t1a, t1b, result = sp4(h, _neg(h1), sub(pw, a1), dot(h, sub(w, a1)), tol)
    if result == FREE:
        t1a = t1b = _fixed(fix_joint, fix_value, 0)
    return t1a, t1b, result


@numba.njit(**COMPILE)
def spherical_two_parallel(T, G, fix_joint, fix_value, tol, q, status, free, stage):
    r"""Spherical wrist (axes 4, 5, 6 meet at ``w``) and axes 2 ∥ 3.

    R2 and R3 keep the component along h2, so ``h2·R1ᵀ(p_w − a1) = h2·(w − a1)`` gives θ1
    (SP4, shoulder ±); then :math:`v = R_1^\top(p_w - a_1) - (a_2 - a_1) = R_2 u(θ_3)` with
    :math:`u = (a_3 - a_2) + R_3 (w - a_3)`: ‖u‖ = ‖v‖ gives θ3 (SP3, elbow ±) and
    ``rot(h2, θ2) u = v`` gives θ2 (SP1).
    """
    z0, z1, z2, p = _target(T, G)
    h1, h2, h3 = _row(G, 0), _row(G, 1), _row(G, 2)
    a1, a2, a3, w, pM = _row(G, 6), _row(G, 7), _row(G, 8), _row(G, 9), _row(G, 12)
    pw = sub(p, _mul(z0, z1, z2, sub(pM, w)))
    z = _mul(z0, z1, z2, _row(G, 5))
    y = _mul(z0, z1, z2, _row(G, 16))
    t1a, t1b, shoulder = _shoulder_sp4(G, pw, fix_joint, fix_value, tol, 1)
    for s in range(2):
        if shoulder == OUT:
            _empty(4 * s, 4, 1, status, stage, free)
            continue
        t1 = t1a if s == 0 else t1b
        c1, s1 = math.cos(t1), math.sin(t1)
        v = sub(rotate_cs(h1, c1, -s1, sub(pw, a1)), sub(a2, a1))
        t3a, t3b, elbow, c3a, s3a, c3b, s3b = sp3_cs(h3, sub(w, a3), sub(a2, a3), norm(v), tol)
        for e in range(2):
            slot = 4 * s + 2 * e
            if elbow == OUT:
                _empty(slot, 2, 2, status, stage, free)
                continue
            t3, c3, s3 = (t3a, c3a, s3a) if e == 0 else (t3b, c3b, s3b)
            u = add(sub(a3, a2), rotate_cs(h3, c3, s3, sub(w, a3)))
            t2, c2, s2, reach = sp1_cs(h2, u, v)
            elbow_free = reach <= tol
            if elbow_free:
                t2 = _fixed(fix_joint, fix_value, 1)
                c2, s2 = math.cos(t2), math.sin(t2)
            free[slot] = 0 if shoulder == FREE else (1 if elbow_free else -1)
            pos = _status_of(shoulder, elbow, 1 if elbow_free else 0)
            _wrist(
                G,
                z,
                y,
                (t1, t2, t3),
                (c1, s1, c2, s2, c3, s3),
                fix_joint,
                fix_value,
                tol,
                slot,
                q,
                status,
                free,
                stage,
                pos,
            )
            if (shoulder == FREE and s == 1) or (elbow == FREE and e == 1):
                _empty(slot, 2, 0, status, stage, free)


@numba.njit(**COMPILE)
def _search_residual(G, pw, t1, tol):
    """The two residuals ``h2·v − h2·u±`` of the 1-D search at θ1 (SP3 clipped, so both are
    continuous in θ1), with the two θ3 and whether SP3 was within reach."""
    h1, h2, h3 = _row(G, 0), _row(G, 1), _row(G, 2)
    a1, a2, a3, w = _row(G, 6), _row(G, 7), _row(G, 8), _row(G, 9)
    v = sub(rotate(h1, -t1, sub(pw, a1)), sub(a2, a1))
    t3a, t3b, elbow = sp3(h3, sub(w, a3), sub(a2, a3), norm(v), tol)
    hv = dot(h2, v)
    ra = hv - dot(h2, add(sub(a3, a2), rotate(h3, t3a, sub(w, a3))))
    rb = hv - dot(h2, add(sub(a3, a2), rotate(h3, t3b, sub(w, a3))))
    return ra, rb, t3a, t3b, elbow


@numba.njit(**COMPILE)
def _branch_residual(G, pw, t1, tol, branch):
    """``f+`` (branch 0) or ``f−`` (branch 1) of :func:`_search_residual` at θ1."""
    ra, rb, _, _, _ = _search_residual(G, pw, t1, tol)
    return ra if branch == 0 else rb


@numba.njit(**COMPILE)
def _touch(G, pw, low, high, tol, branch):
    r"""``(θ1, f(θ1))`` at the minimum of ``|f|`` on [low, high] by golden-section search.

    At a double root :math:`f ≈ c(θ - θ^*)^2`, so θ* is found only to about √ε, but the pose
    error of the branch built there is ``|f|`` itself (every other constraint is met by the
    subproblems), which this drives to rounding.
    """
    ratio = 0.5 * (math.sqrt(5.0) - 1.0)
    x1 = high - ratio * (high - low)
    x2 = low + ratio * (high - low)
    f1 = abs(_branch_residual(G, pw, x1, tol, branch))
    f2 = abs(_branch_residual(G, pw, x2, tol, branch))
    for _ in range(GOLDEN_STEPS):
        if f1 <= f2:
            high, x2, f2 = x2, x1, f1
            x1 = high - ratio * (high - low)
            f1 = abs(_branch_residual(G, pw, x1, tol, branch))
        else:
            low, x1, f1 = x1, x2, f2
            x2 = low + ratio * (high - low)
            f2 = abs(_branch_residual(G, pw, x2, tol, branch))
    root = x1 if f1 <= f2 else x2
    return root, _branch_residual(G, pw, root, tol, branch)


@numba.njit(**COMPILE)
def spherical(T, G, fix_joint, fix_value, tol, q, status, free, stage):
    r"""Spherical wrist (axes 4, 5, 6 meet at ``w``), general axes 1–3: a 1-D search on θ1.

    For a given θ1, :math:`v = R_1^\top(p_w - a_1) - (a_2 - a_1) = R_2 u(θ_3)` needs
    ‖u‖ = ‖v‖ (SP3 → θ3±) and equal components along h2 (R2 keeps them):
    :math:`f_±(θ_1) = h_2·v - h_2·u(θ_{3±}) = 0`, then θ2 by SP1 (IK-Geo's 1-D search, Elias
    & Wen 2022 §IV). Each ``f±`` is sampled at :data:`SEARCH_SAMPLES` points of θ1 and every
    sign change refined by bisection; a root is kept only if SP3 was within reach there
    (the clipped residual is continuous, so roots at the edge of reach are not lost). A root
    where ``f`` touches zero without changing sign (a double root, where two arm solutions
    merge at the boundary between 2 and 0 of them) is found at each local minimum of ``|f|``
    between samples of one sign: golden-section search (:func:`_touch`) drives ``|f|`` down
    and the root is kept if it falls below :data:`TOUCH_TOL`. Slot = 2·(root index, by θ1)
    + wrist.
    """
    z0, z1, z2, p = _target(T, G)
    h2, h3 = _row(G, 1), _row(G, 2)
    a2, a3, w, pM = _row(G, 7), _row(G, 8), _row(G, 9), _row(G, 12)
    pw = sub(p, _mul(z0, z1, z2, sub(pM, w)))
    z = _mul(z0, z1, z2, _row(G, 5))
    y = _mul(z0, z1, z2, _row(G, 16))
    n_slots = q.shape[0]
    _empty(0, n_slots, 1, status, stage, free)
    roots = np.empty(n_slots // 2)
    branches = np.empty(n_slots // 2, np.int64)
    found = 0
    step = 2.0 * math.pi / SEARCH_SAMPLES
    start = -math.pi
    samples = np.empty((2, SEARCH_SAMPLES + 1))
    for k in range(SEARCH_SAMPLES + 1):
        samples[0, k], samples[1, k], _, _, _ = _search_residual(G, pw, start + k * step, tol)
    for k in range(1, SEARCH_SAMPLES + 1):
        t = start + k * step
        for branch in range(2):
            before, now = samples[branch, k - 1], samples[branch, k]
            if before == 0.0 or (before < 0.0) != (now < 0.0):
                low, high, f_low = t - step, t, before
                for _ in range(BISECTIONS):
                    middle = 0.5 * (low + high)
                    f_middle = _branch_residual(G, pw, middle, tol, branch)
                    if (f_middle < 0.0) == (f_low < 0.0):
                        low, f_low = middle, f_middle
                    else:
                        high = middle
                root = 0.5 * (low + high)
                _, _, _, _, elbow = _search_residual(G, pw, root, tol)
                if elbow != OUT and found < roots.shape[0] and now != 0.0:
                    roots[found], branches[found] = root, branch
                    found += 1
            elif abs(now) <= abs(before):
                # A local minimum of |f| with no sign change on either side: f may touch zero
                # between the samples (a double root, where two arm solutions merge). The
                # residual is 2π-periodic: the sample after θ1 = π is the one after −π.
                after = samples[branch, k + 1 if k < SEARCH_SAMPLES else 1]
                # Near its minimum f ≈ m + c(θ − θ*)², so |f(θk)| − |m| ≤ c h² = D/2 with D the
                # second difference of |f|: a zero is possible only if |f(θk)| ≤ D/2 (factor
                # 4 of margin for the curvature varying across the bracket).
                curvature = abs(before) - 2.0 * abs(now) + abs(after)
                plausible = abs(now) <= 2.0 * curvature
                if abs(now) <= abs(after) and (now < 0.0) == (after < 0.0) and plausible:
                    root, value = _touch(G, pw, t - step, t + step, tol, branch)
                    _, _, _, _, elbow = _search_residual(G, pw, root, tol)
                    if abs(value) <= TOUCH_TOL and elbow != OUT and found < roots.shape[0]:
                        roots[found], branches[found] = root, branch + 2  # + 2: a double root
                        found += 1
    h1, a1 = _row(G, 0), _row(G, 6)
    order = np.argsort(roots[:found])
    for index in range(found):
        t1, branch = roots[order[index]], branches[order[index]] % 2
        double = branches[order[index]] >= 2
        _, _, t3a, t3b, elbow = _search_residual(G, pw, t1, tol)
        t3 = t3a if branch == 0 else t3b
        v = sub(rotate(h1, -t1, sub(pw, a1)), sub(a2, a1))
        u = add(sub(a3, a2), rotate(h3, t3, sub(w, a3)))
        t2, _ = sp1(h2, u, v)
        slot = 2 * index
        free[slot] = -1
        pos = _status_of(1 if (elbow == BOUNDARY or double) else 0)
        cs = (math.cos(t1), math.sin(t1), math.cos(t2), math.sin(t2), math.cos(t3), math.sin(t3))
        _wrist(
            G, z, y, (t1, t2, t3), cs, fix_joint, fix_value, tol, slot, q, status, free, stage, pos
        )


@numba.njit(**COMPILE)
def three_parallel_two_intersecting(T, G, fix_joint, fix_value, tol, q, status, free, stage):
    r"""Axes 2 ∥ 3 ∥ 4 (direction h) and axes 5, 6 meeting at ``w`` (the UR class).

    1. :math:`p_w = p - Z(p_M - w)`; R2 R3 R4 keep the component along h:
       ``h·R1ᵀ(p_w − a1) = h·(w − a1)`` gives θ1 (SP4, shoulder ±).
    2. :math:`R_1^\top Z = R_{234} R_5 R_6` and :math:`R_6 h_6 = h_6`:
       ``h·rot(h5, θ5) h6 = h·R1ᵀ Z h6`` gives θ5 (SP4, wrist ±).
    3. ``hᵀ R5 R6 = hᵀ R1ᵀ Z``: ``rot(h6, θ6) (Zᵀ R1 h) = R5ᵀ h`` gives θ6 (SP1; arbitrary
       when Zᵀ R1 h ∥ h6, the wrist singularity).
    4. :math:`R_{234} = R_1^\top Z R_6^\top R_5^\top` gives θ234 (SP1 on e ⊥ h);
       :math:`v = R_1^\top(p_w - a_1) - (a_2 - a_1) - R_{234}(w - a_4) = R_2 u(θ_3)`,
       :math:`u = (a_3 - a_2) + R_3(a_4 - a_3)`: ‖u‖ = ‖v‖ gives θ3 (SP3, elbow ±),
       ``rot(h, θ2) u = v`` gives θ2 (SP1), θ4 = θ234 − θ2 − θ3.

    Slot = 4·shoulder + 2·elbow + wrist.
    """
    z0, z1, z2, p = _target(T, G)
    h1, h, h5, h6, e = _row(G, 0), _row(G, 1), _row(G, 4), _row(G, 5), _row(G, 16)
    a1, a2, a3, a4, w, pM = _row(G, 6), _row(G, 7), _row(G, 8), _row(G, 9), _row(G, 10), _row(G, 12)
    pw = sub(p, _mul(z0, z1, z2, sub(pM, w)))
    # Cosines and sines come with each root (sp*_cs), saving a call to cos and sin per use.
    t1a, t1b, result1, c1a, s1a, c1b, s1b = sp4_cs(
        h, _neg(h1), sub(pw, a1), dot(h, sub(w, a1)), tol
    )
    if result1 == FREE:
        t1a = t1b = _fixed(fix_joint, fix_value, 0)
        c1a = c1b = math.cos(t1a)
        s1a = s1b = math.sin(t1a)
    zh6 = _mul(z0, z1, z2, h6)
    for s in range(2):
        if result1 == OUT:
            _empty(4 * s, 4, 1, status, stage, free)
            continue
        t1, c1, s1 = (t1a, c1a, s1a) if s == 0 else (t1b, c1b, s1b)
        t5a, t5b, result5, c5a, s5a, c5b, s5b = sp4_cs(
            h, h5, h6, dot(h, rotate_cs(h1, c1, -s1, zh6)), tol
        )
        zt = _mul_t(z0, z1, z2, rotate_cs(h1, c1, s1, h))
        arm = sub(rotate_cs(h1, c1, -s1, sub(pw, a1)), sub(a2, a1))
        for wrist in range(2):
            if result5 == OUT:
                for el in range(2):
                    _empty(4 * s + 2 * el + wrist, 1, 3, status, stage, free)
                continue
            t5, c5, s5 = (t5a, c5a, -s5a) if wrist == 0 else (t5b, c5b, -s5b)
            t6, c6, s6, reach6 = sp1_cs(h6, zt, rotate_cs(h5, c5, s5, h))
            wrist_free = reach6 <= tol
            if wrist_free:
                t6 = _fixed(fix_joint, fix_value, 5)
                c6, s6 = math.cos(t6), math.sin(t6)
            image = rotate_cs(h6, c6, -s6, rotate_cs(h5, c5, s5, e))
            t234, c234, s234, _ = sp1_cs(h, e, rotate_cs(h1, c1, -s1, _mul(z0, z1, z2, image)))
            v = sub(arm, rotate_cs(h, c234, s234, sub(w, a4)))
            t3a, t3b, elbow, c3a, s3a, c3b, s3b = sp3_cs(h, sub(a4, a3), sub(a2, a3), norm(v), tol)
            for el in range(2):
                slot = 4 * s + 2 * el + wrist
                if elbow == OUT:
                    _empty(slot, 1, 2, status, stage, free)
                    continue
                t3, c3, s3 = (t3a, c3a, s3a) if el == 0 else (t3b, c3b, s3b)
                u = add(sub(a3, a2), rotate_cs(h, c3, s3, sub(a4, a3)))
                t2, c2, s2, reach2 = sp1_cs(h, u, v)
                elbow_free = reach2 <= tol
                if elbow_free:
                    t2 = _fixed(fix_joint, fix_value, 1)
                    c2, s2 = math.cos(t2), math.sin(t2)
                # θ4 = θ234 − (θ2 + θ3), its cosine and sine by the angle-sum formulas.
                c23, s23 = c2 * c3 - s2 * s3, s2 * c3 + c2 * s3
                c4, s4 = c234 * c23 + s234 * s23, s234 * c23 - c234 * s23
                _store(
                    q,
                    slot,
                    (t1, t2, t3, t234 - t2 - t3, t5, t6),
                    (c1, c2, c3, c4, c5, c6),
                    (s1, s2, s3, s4, -s5, s6),
                )
                stage[slot] = 0
                free[slot] = (
                    0 if result1 == FREE else (5 if wrist_free else (1 if elbow_free else -1))
                )
                status[slot] = _status_of(
                    result1, result5, elbow, 1 if wrist_free else 0, 1 if elbow_free else 0
                )
                duplicate = (
                    (result1 == FREE and s == 1)
                    or (result5 == FREE and wrist == 1)
                    or (elbow == FREE and el == 1)
                )
                if duplicate:
                    _empty(slot, 1, 0, status, stage, free)


@numba.njit(**COMPILE)
def spherical_two_intersecting_prismatic(T, G, fix_joint, fix_value, tol, q, status, free, stage):
    r"""Axes 1, 2 meeting at ``o``, joint 3 sliding along ``h3``, spherical wrist (axes 4, 5,
    6 meeting at ``w`` when joint 3 is at 0): the Stanford arm's class.

    The slide carries the wrist: :math:`p_w - o = R_1 R_2 u(d_3)`,
    :math:`u = (w - o) + d_3 h_3`, so ‖u‖ = ‖p_w − o‖ is the intersection of the slide's line
    with a sphere about ``o`` (the prismatic counterpart of SP3):
    :math:`d_3 = -b·h_3 ± \sqrt{‖p_w - o‖^2 - ‖b_⊥‖^2}`, ``b = w − o`` and ``b⊥`` its part
    across ``h3`` (two roots, "d±"; none when the sphere misses the line, one when it
    touches it, within ``tol``); then SP2 gives θ1, θ2 (shoulder ±) and the wrist as in
    :func:`spherical_two_intersecting`. Slot = 4·shoulder + 2·slide + wrist.
    """
    z0, z1, z2, p = _target(T, G)
    h3 = _row(G, 2)
    o, w, pM = _row(G, 6), _row(G, 9), _row(G, 12)
    pw = sub(p, _mul(z0, z1, z2, sub(pM, w)))
    z = _mul(z0, z1, z2, _row(G, 5))
    y = _mul(z0, z1, z2, _row(G, 16))
    b = sub(w, o)
    along = dot(b, h3)
    across = norm(sub(b, scale(h3, along)))  # distance of the slide's line from o
    radius = norm(sub(pw, o))
    reach = OK
    if radius < across - tol:
        reach = OUT
    elif abs(radius - across) <= tol:
        reach = BOUNDARY
    half = 0.0 if reach != OK else math.sqrt((radius - across) * (radius + across))
    for e in range(2):
        if reach == OUT:
            _empty(2 * e, 2, 2, status, stage, free)
            _empty(4 + 2 * e, 2, 2, status, stage, free)
            continue
        d3 = -along + half if e == 0 else -along - half
        u = add(b, scale(h3, d3))
        # The slide's "cosine and sine" are those of no rotation: _wrist's R3 is I.
        _shoulder_then_wrist(
            G, z, y, pw, o, u, e, d3, 1.0, 0.0, reach, fix_joint, fix_value, tol, q, status,
            free, stage,
        )  # fmt: skip


@numba.njit(**COMPILE)
def solve_kind(kind, T, G, fix_joint, fix_value, tol):
    """Run kernel ``kind`` on the 4×4 target ``T``: ``(q, status, free, stage)``, ``q`` of
    shape (S, 18) (module docstring)."""
    n_slots = SLOTS[kind]
    q = np.zeros((n_slots, 18))
    flags = np.zeros((3, n_slots), np.int64)
    status, free, stage = flags[0], flags[1], flags[2]
    free[:] = -1
    if kind == SPHERICAL_TWO_INTERSECTING:
        spherical_two_intersecting(T, G, fix_joint, fix_value, tol, q, status, free, stage)
    elif kind == SPHERICAL_TWO_PARALLEL:
        spherical_two_parallel(T, G, fix_joint, fix_value, tol, q, status, free, stage)
    elif kind == SPHERICAL:
        spherical(T, G, fix_joint, fix_value, tol, q, status, free, stage)
    elif kind == THREE_PARALLEL_TWO_INTERSECTING:
        three_parallel_two_intersecting(T, G, fix_joint, fix_value, tol, q, status, free, stage)
    else:
        spherical_two_intersecting_prismatic(
            T, G, fix_joint, fix_value, tol, q, status, free, stage
        )
    return q, status, free, stage


@numba.njit(**COMPILE)
def fk_error(G, row, T):
    r"""``max(‖p(q) − p‖, max |R(q) − R| over the first two columns)`` for the chain of ``G``
    at the slot ``row`` (joint values, then the cosines and sines of the angles; the third
    column of a rotation follows from the first two). A prismatic joint (:func:`_prismatic`)
    translates by its value along its direction instead of rotating.

    Evaluated from the tip inwards, :math:`p = a_1 + R_1(a_2 - a_1 + R_2(⋯ + R_6(p_M - a_6)))`
    and :math:`R\,\hat x = R_1(⋯ R_6 (R_M \hat x))`, three vectors rotated per joint.
    """
    p = sub(_row(G, 12), _row(G, 11))
    x = (G[13, 0], G[14, 0], G[15, 0])
    y = (G[13, 1], G[14, 1], G[15, 1])
    for i in range(5, -1, -1):
        k = _row(G, i)
        if _prismatic(G, i):
            p = add(p, scale(k, row[i]))
        else:
            c, s = row[6 + i], row[12 + i]
            p = rotate_cs(k, c, s, p)
            x = rotate_cs(k, c, s, x)
            y = rotate_cs(k, c, s, y)
        if i > 0:
            p = add(p, sub(_row(G, 6 + i), _row(G, 5 + i)))
    p = add(p, _row(G, 6))
    error = norm(sub(p, (T[0, 3], T[1, 3], T[2, 3])))
    for i in range(3):
        error = max(error, max(abs(x[i] - T[i, 0]), abs(y[i] - T[i, 1])))
    return error


@numba.njit(**COMPILE)
def _wrap(angle):
    """``angle`` wrapped to (−π, π], equal bit for bit to :func:`redik.lie.wrap_angle` at any
    magnitude: within a few turns (every kernel angle) by exact shifts of 2π, which is what
    ``fmod`` then one shift give there, and beyond by that algorithm itself (a call to
    ``fmod`` per angle cost a tenth of a solve)."""
    if -math.pi < angle <= math.pi:
        return angle
    two_pi = 2.0 * math.pi
    if abs(angle) > 8.0 * math.pi:
        r = np.fmod(angle, two_pi)
        return r - two_pi if r > math.pi else (r + two_pi if r <= -math.pi else r)
    while angle > math.pi:
        angle -= two_pi
    while angle <= -math.pi:
        angle += two_pi
    return angle


@numba.njit(**COMPILE)
def _inverse(T):
    """``T⁻¹`` of a rigid transform."""
    inverse = np.zeros((4, 4))
    for i in range(3):
        for j in range(3):
            inverse[i, j] = T[j, i]
        inverse[i, 3] = -(T[0, i] * T[0, 3] + T[1, i] * T[1, 3] + T[2, i] * T[2, 3])
    inverse[3, 3] = 1.0
    return inverse


@numba.njit(**COMPILE)
def _polish(G, row, T, fixed):
    """:func:`newton` with :data:`POLISH_STEPS` steps: a closed-form slot near a singularity."""
    return newton(G, row, T, fixed, POLISH_STEPS, 0.0)


@numba.njit(**COMPILE)
def _jacobian(G, row, J):
    """Fill ``J`` (6 × 6) with the world Jacobian of the chain of ``G`` at the slot ``row``,
    rows ``(ω, v)`` (a slide's column is ``(0, axis)``); returns ``(R, P)``, the rotation and
    the tip point (before ``R_M``)."""
    R = np.eye(3)
    P = _row(G, 6)
    for i in range(6):
        axis = (
            R[0, 0] * G[i, 0] + R[0, 1] * G[i, 1] + R[0, 2] * G[i, 2],
            R[1, 0] * G[i, 0] + R[1, 1] * G[i, 1] + R[1, 2] * G[i, 2],
            R[2, 0] * G[i, 0] + R[2, 1] * G[i, 1] + R[2, 2] * G[i, 2],
        )
        if _prismatic(G, i):  # J = (ω, v) = (0, axis); the slide moves what follows
            J[0, i], J[1, i], J[2, i] = 0.0, 0.0, 0.0
            J[3, i], J[4, i], J[5, i] = axis
            P = add(P, scale(axis, row[i]))
        else:
            J[0, i], J[1, i], J[2, i] = axis
            J[3, i], J[4, i], J[5, i] = P  # joint origin for now: J_v = ω × (p − o) below
        step = np.empty((3, 3))
        slide = _prismatic(G, i)
        c, s = (1.0, 0.0) if slide else (math.cos(row[i]), math.sin(row[i]))
        for j in range(3):
            column = rotate_cs(_row(G, i), c, s, (1.0 * (j == 0), 1.0 * (j == 1), 1.0 * (j == 2)))
            step[0, j], step[1, j], step[2, j] = column
        R = R @ step
        following = _row(G, 12) if i == 5 else _row(G, 7 + i)
        offset = sub(following, _row(G, 6 + i))
        P = add(
            P,
            (
                dot((R[0, 0], R[0, 1], R[0, 2]), offset),
                dot((R[1, 0], R[1, 1], R[1, 2]), offset),
                dot((R[2, 0], R[2, 1], R[2, 2]), offset),
            ),
        )
    for i in range(6):
        if _prismatic(G, i):
            continue
        omega = (J[0, i], J[1, i], J[2, i])
        linear = cross(omega, sub(P, (J[3, i], J[4, i], J[5, i])))
        J[3, i], J[4, i], J[5, i] = linear
    return R, P


@numba.njit(**COMPILE)
def condition(G, row):
    """``σ_min/σ_max`` of the world Jacobian (:func:`_jacobian`) at the slot ``row``: 0 at a
    singular configuration."""
    J = np.empty((6, 6))
    _jacobian(G, row, J)
    sigma = np.linalg.svd(J)[1]
    return sigma[-1] / sigma[0]


@numba.njit(**COMPILE)
def newton(G, row, T, fixed, steps, stop):
    r"""Gauss–Newton steps on the chain of ``G`` from the slot ``row`` (angles, cosines, sines;
    updated in place) towards ``T``; returns the final :func:`fk_error`. At most ``steps``
    steps, fewer once the error is at most ``stop`` (checked only when ``stop > 0``).

    Next to a singularity a subproblem can be ill-conditioned (SP4 with ``C ≈ ±r`` gives θ
    to only √ε): the closed form is then within :data:`POLISH_RANGE` and these steps,
    :math:`Δq = J^+ e` with the world Jacobian of the chain and
    :math:`e = (p_d - p,\; \tfrac12 \sum_j R_{:j} × R_{d,:j})` (least squares, so a singular
    direction takes no step), bring it back to rounding. Joint ``fixed`` (a family's free
    joint, or −1) is held.
    """
    J = np.empty((6, 6))
    e = np.empty(6)
    for _ in range(steps):
        if stop > 0.0 and fk_error(G, row, T) <= stop:
            break
        R, P = _jacobian(G, row, J)
        R = R @ G[13:16]  # rows 13–15 hold R_M
        rotation = (0.0, 0.0, 0.0)
        for j in range(3):
            rotation = add(
                rotation, cross((R[0, j], R[1, j], R[2, j]), (T[0, j], T[1, j], T[2, j]))
            )
        e[0], e[1], e[2] = scale(rotation, 0.5)
        e[3], e[4], e[5] = T[0, 3] - P[0], T[1, 3] - P[1], T[2, 3] - P[2]
        if fixed >= 0:
            J[:, fixed] = 0.0
        step_q = np.linalg.lstsq(J, e, 1e-10)[0]
        for i in range(6):
            row[i] += step_q[i]
            if not _prismatic(G, i):
                row[6 + i], row[12 + i] = math.cos(row[i]), math.sin(row[i])
    return fk_error(G, row, T)


@numba.njit(**COMPILE)
def solve_slots(kind, reverse, T, G, fix_joint, fix_value, tol, verify_tol):
    """:func:`solve_kind` on the robot's joint order (``reverse``: the chain of ``G`` is the
    robot's run backwards, solved for ``T⁻¹``), each non-empty slot checked by FK (of the
    chain, at the cosines and sines that come with the angles): ``(q, status, free, stage)``,
    ``q`` (S, 6) wrapped to (−π, π], a slot whose FK misses by more than ``verify_tol``
    emptied (stage 4)."""
    target = _inverse(T) if reverse else T
    chain_fix = 5 - fix_joint if reverse and fix_joint >= 0 else fix_joint
    q, status, free, stage = solve_kind(kind, target, G, chain_fix, fix_value, tol)
    for slot in range(q.shape[0]):
        if status[slot] == EMPTY:
            continue
        error = fk_error(G, q[slot], target)
        if verify_tol < error <= POLISH_RANGE:
            error = _polish(G, q[slot], target, free[slot])
        if error > verify_tol:
            status[slot], stage[slot] = EMPTY, 4
    angles = np.empty((q.shape[0], 6))
    for slot in range(q.shape[0]):
        for j in range(6):
            joint = 5 - j if reverse else j
            value = q[slot, joint]
            angles[slot, j] = value if _prismatic(G, joint) else _wrap(value)
        if reverse and free[slot] >= 0:
            free[slot] = 5 - free[slot]
    return angles, status, free, stage


@numba.njit(**COMPILE)
def _select(q, status, lower, upper, duplicate_tol, slots, G, reverse):
    """Compact the slots of :func:`solve_slots` in place: each non-empty slot moved by the
    smallest multiple of 2π per angle into the limits (dropped if there is none), duplicates
    (within ``duplicate_tol`` per joint, modulo 2π) dropped; ``slots[row]`` is the slot of
    each kept row (``G`` and ``reverse`` say which robot joints slide). Returns the number
    kept."""
    out = q  # compacted in place: row ``count`` ≤ ``slot`` is written after ``slot`` is read
    count = 0
    two_pi = 2.0 * math.pi
    for slot in range(q.shape[0]):
        if status[slot] == EMPTY:
            continue
        inside = True
        for j in range(6):
            value = q[slot, j]
            if lower[j] <= value <= upper[j]:  # the usual case: no turn to find
                out[count, j] = value
                continue
            if _prismatic(G, 5 - j if reverse else j):  # a slide out of range: no turn helps
                inside = False
                break
            turns = min(
                max(np.ceil((lower[j] - value) / two_pi), 0.0),
                np.floor((upper[j] - value) / two_pi),
            )
            shifted = value + two_pi * turns
            clipped = min(max(shifted, lower[j]), upper[j])
            if abs(clipped - shifted) > duplicate_tol:
                inside = False
                break
            out[count, j] = clipped
        if not inside:
            continue
        repeated = False
        for other in range(count):
            same = True
            for j in range(6):
                difference = out[other, j] - out[count, j]
                slide = _prismatic(G, 5 - j if reverse else j)
                if abs(difference if slide else _wrap(difference)) >= duplicate_tol:
                    same = False
                    break
            if same:
                repeated = True
                break
        if not repeated:
            slots[count] = slot
            count += 1
    return count


@numba.njit(**COMPILE)
def _solve_planned(T, plan, slots):
    """:func:`solve_slots` then :func:`_select` with everything read from ``plan``:
    ``(q, count, status, free, stage)``, or ``count = −1`` (nothing solved) when ``T`` is not
    a rigid transform to be used as it is."""
    G = plan[:GEOMETRY_SIZE].reshape(19, 3)
    lower = plan[GEOMETRY_SIZE : GEOMETRY_SIZE + 6]
    upper = plan[GEOMETRY_SIZE + 6 : GEOMETRY_SIZE + 12]
    settings = plan[GEOMETRY_SIZE + 12 :]
    kind, reverse = int(settings[KIND]), settings[REVERSE] != 0.0
    tol, verify_tol, duplicate_tol = settings[TOL], settings[VERIFY], settings[DUPLICATE]
    if T.shape[0] != 4 or T.shape[1] != 4 or not valid_target(T, ROTATION_TOLERANCE):
        empty = np.empty(0, np.int64)
        return np.empty((0, 6)), -1, empty, empty, empty
    q, status, free, stage = solve_slots(kind, reverse, T, G, -1, 0.0, tol, verify_tol)
    count = _select(q, status, lower, upper, duplicate_tol, slots, G, reverse)
    return q, count, status, free, stage


@numba.njit(numba.float64[:, :](numba.float64[:, ::1], numba.float64[::1]), **COMPILE)
def solve_raw(T, plan):
    """The fast path: every verified solution within the limits (each angle moved by the
    smallest multiple of 2π that brings it into range), duplicates (within the duplicate
    tolerance per joint, modulo 2π) dropped, as a (k, 6) array in slot order — or a (0, 0)
    array when ``T`` is not a 4 × 4 finite rigid transform to be used as it is — the one rule
    of :func:`redik.kinematics.compiled.valid_target` at
    :data:`~redik.core.rotation_policy.ROTATION_TOLERANCE`, which is
    :func:`~redik.core.rotation_policy.as_pose`'s "use as it is" (nothing is solved: the caller
    raises, or projects a near-rotation as :mod:`~redik.core.rotation_policy` does and calls again).
    Compiled for one signature only (C-contiguous float64 ``T``): any other array or object raises
    ``TypeError`` at the call instead of compiling a new specialisation, and the caller converts it
    after its checks.

    ``plan`` packs everything but the target into one array (one argument keeps the call
    cheap): the (19, 3) geometry ``G`` row by row, the lower and upper limits, then the
    settings (:data:`KIND`, :data:`REVERSE`, :data:`TOL`, :data:`VERIFY`, :data:`DUPLICATE`).
    """
    slots = np.empty(SLOTS[int(plan[GEOMETRY_SIZE + 12 + KIND])], np.int64)
    q, count, _, _, _ = _solve_planned(T, plan, slots)
    if count < 0:
        return np.empty((0, 0))
    return q[:count]


@numba.njit(
    numba.types.Tuple((numba.float64[:, :], numba.int64[:], numba.int64[:, ::1]))(
        numba.float64[:, ::1], numba.float64[::1]
    ),
    **COMPILE,
)
def solve_labelled(T, plan):
    """:func:`solve_raw` with what labels need: ``(q, slots, flags)``, ``q`` (k, 6) the kept
    solutions, ``slots`` (k,) the slot of each and ``flags`` (3, S) the ``status``, ``free``
    and ``stage`` of every slot (:func:`solve_slots`); ``flags`` has no column when ``T`` is
    not to be used as it is (compiled for one signature, like :func:`solve_raw`; three
    arrays, as each returned array costs the caller a box)."""
    slots = np.empty(SLOTS[int(plan[GEOMETRY_SIZE + 12 + KIND])], np.int64)
    q, count, status, free, stage = _solve_planned(T, plan, slots)
    flags = np.empty((3, status.shape[0]), np.int64)
    flags[0], flags[1], flags[2] = status, free, stage
    return q[: max(count, 0)], slots[: max(count, 0)], flags
