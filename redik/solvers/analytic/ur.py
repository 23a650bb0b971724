r"""UR-type 6R arm (Universal Robots): all eight solutions in closed form.

Standard DH table as published by Universal Robots (joint offsets 0; for the UR5e
a2 = −0.425, a3 = −0.3922 m, negative because the arm points along −x at q = 0):

=====  =====  =====  =====  ======
joint  θ      d      a      α
=====  =====  =====  =====  ======
1      θ1     d1     0      π/2
2      θ2     0      a2     0
3      θ3     0      a3     0
4      θ4     d4     0      π/2
5      θ5     d5     0      −π/2
6      θ6     d6     0      0
=====  =====  =====  =====  ======

Joints 2, 3 and 4 are parallel to :math:`\hat z_1 = (s_1, -c_1, 0)`, so everything after
joint 1 keeps a constant offset :math:`d_4` along it. Following Hawkins (2013), "Analytic
Inverse Kinematics for the Universal Robots UR-5/UR-10 Arms", and Andersen (2018),
"Kinematics of a UR5":

1. :math:`p_5 = p - d_6 R\hat z` satisfies :math:`\hat z_1 \cdot p_5 = d_4`, so with
   :math:`X = \pm\sqrt{p_{5x}^2 + p_{5y}^2 - d_4^2}`,
   :math:`θ_1 = \operatorname{atan2}(p_{5y}, p_{5x}) + \operatorname{atan2}(d_4, X)`.
2. :math:`\hat z_1` seen from frame 6 is :math:`(s_5 c_6, -s_5 s_6, c_5)`:
   :math:`c_5 = \hat z_1\cdot\hat z_6`,
   :math:`θ_5 = \pm\operatorname{atan2}(s_5, c_5)` with
   :math:`s_5 = \sqrt{(\hat z_1\cdot\hat x_6)^2 + (\hat z_1\cdot\hat y_6)^2}`, and
   :math:`θ_6 = \operatorname{atan2}(-\hat z_1\cdot\hat y_6 / s_5,\;
   \hat z_1\cdot\hat x_6 / s_5)`; at :math:`s_5 = 0` θ6 is free.
3. :math:`T_1^4 = A_1^{-1}\, T\, (A_5 A_6)^{-1}` gives the frame-4 origin
   :math:`(a_2 c_2 + a_3 c_{23},\; a_2 s_2 + a_3 s_{23})` and :math:`θ_{234}`; θ2, θ3 by the
   law of cosines (:func:`redik.solvers.analytic.planar.two_link`, with :math:`|a_2|, |a_3|` and
   shifts of π for negative lengths), :math:`θ_4 = θ_{234} - θ_2 - θ_3`.

Labels ``"{left|right}-{up|down}-{noflip|flip}"``: *left* when the lateral offset d4 lies to
the left of the vertical plane through the base axis and :math:`p_5`, seen from the base
(:math:`X d_4 < 0`); *up* when the elbow lies above the shoulder–wrist line with
:math:`p_5` in front (:math:`X > 0`) of the shoulder (the same branch is kept behind);
*noflip* when θ5 ∈ [0, π].
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from redik.models.dh import DHRow
from redik.solvers.analytic import _checks
from redik.solvers.analytic._arm import (
    ARM_LABELS,
    ArmSlots,
    Slot,
    arm_solutions,
    free_joint,
    shoulder,
    wrapped,
)
from redik.solvers.analytic._numeric import Numeric, pose_entries
from redik.solvers.analytic._solution import (
    DEFAULT_TOL,
    BatchSolutions,
    IKSolutions,
    unreachable,
)
from redik.solvers.analytic.planar import batch_result, two_link, two_link_reason

REVOLUTE = np.ones(6, bool)

#: UR5e parameters (d1, a2, a3, d4, d5, d6) from Universal Robots' DH table, in metres.
UR5E = (0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996)


def dh_rows(d1: float, a2: float, a3: float, d4: float, d5: float, d6: float) -> tuple[DHRow, ...]:
    """The standard DH table of this arm (the module docstring's), for
    :func:`redik.models.dh.forward`."""
    half = np.pi / 2.0
    return (
        DHRow(0.0, d1, half),
        DHRow(a2, 0.0, 0.0),
        DHRow(a3, 0.0, 0.0),
        DHRow(0.0, d4, half),
        DHRow(0.0, d5, -half),
        DHRow(0.0, d6, 0.0),
    )


def ur_slots(
    M: Any,
    num: Numeric,
    d1: float,
    a2: float,
    a3: float,
    d4: float,
    d5: float,
    d6: float,
    tol: float = DEFAULT_TOL,
    theta1: float | None = None,
    theta2: float | None = None,
    theta6: float | None = None,
) -> ArmSlots:
    """The eight slots of the pose entries ``M[i][j]`` (:func:`._numeric.pose_entries`: one
    target or a batch) — the kernel, the module docstring's steps.

    ``theta1`` / ``theta2`` / ``theta6`` fix that joint instead of solving for it: how the
    members of a family are generated at a singularity.
    """
    x6, y6, z6, p = ([M[i][j] for i in range(3)] for j in range(4))
    # 1. Shoulder: slot 0 ("left") has X·d4 < 0.
    p5x, p5y = p[0] - d6 * z6[0], p[1] - d6 * z6[1]
    rho, shoulder_ok, shoulder_boundary, reach = shoulder(p5x, p5y, d4, tol, num)
    side = -1.0 if d4 > 0.0 else 1.0
    heading = num.atan2(p5y, p5x)
    base_axis = (rho <= tol) & (abs(d4) <= tol)
    shift2 = math.pi if a2 < 0.0 else 0.0
    shift3 = (math.pi if a3 < 0.0 else 0.0) - shift2
    planes, rows = [], []  # per (shoulder, wrist): the 2R sub-problem; per slot: q and flags
    for X in (side * reach, -side * reach):
        th1 = heading + num.atan2(d4, X) if theta1 is None else theta1
        c1, s1 = num.cos(th1), num.sin(th1)
        # 2. Wrist: ẑ1 = (s1, −c1, 0) seen from frame 6 is (s5 c6, −s5 s6, c5).
        u6, v6, cos5 = (s1 * axis[0] - c1 * axis[1] for axis in (x6, y6, z6))
        sin5 = num.hypot(u6, v6)  # ≥ 0, accurate near the singularity
        theta5 = num.atan2(sin5, cos5)
        for sign in (1.0, -1.0):  # noflip, flip
            th5 = sign * theta5
            th6 = num.atan2(-sign * v6, sign * u6) if theta6 is None else theta6
            # 3. Frame 4: o4 = p + d5 (s6 x̂6 + c6 ŷ6) − d6 ẑ6, x̂4 = c5 c6 x̂6 − c5 s6 ŷ6 − s5 ẑ6.
            c5, s5, c6, s6 = num.cos(th5), num.sin(th5), num.cos(th6), num.sin(th6)
            o4 = [p[i] + d5 * (s6 * x6[i] + c6 * y6[i]) - d6 * z6[i] for i in range(3)]
            x4 = [c5 * c6 * x6[i] - c5 * s6 * y6[i] - s5 * z6[i] for i in range(3)]
            th234 = num.atan2(x4[2], c1 * x4[0] + s1 * x4[1])
            plane = two_link(c1 * o4[0] + s1 * o4[1], o4[2] - d1, abs(a2), abs(a3), tol, num)
            planes.append(plane)
            rows.append((th1, th5, th6, th234, plane, sin5 <= tol))
    slots = []
    for left_right in (0, 1):
        for up_down in (0, 1):
            # The 2R slot with the elbow up depends on which side the shoulder is on.
            branch = up_down ^ left_right ^ (side > 0.0)
            for wrist in (0, 1):
                th1, th5, th6, th234, plane, wrist_singular = rows[2 * left_right + wrist]
                th2 = plane.theta1[branch] - shift2 if theta2 is None else theta2
                th3 = plane.theta2[branch] - shift3
                q = (th1, th2, th3, th234 - th2 - th3, th5, th6)
                flags = {
                    "base_axis": base_axis,
                    "shoulder_boundary": shoulder_boundary,
                    # The elbow sub-problem is solved per (shoulder, wrist).
                    "elbow_free": plane.boundary & (plane.radius <= tol),
                    "elbow_boundary": plane.boundary,
                    "wrist": wrist_singular,
                }
                valid = shoulder_ok & plane.reachable
                slots.append(Slot(q, valid, flags))
    return ArmSlots(slots, shoulder_ok, planes[0].radius)


def ur(
    T: np.ndarray,
    d1: float,
    a2: float,
    a3: float,
    d4: float,
    d5: float,
    d6: float,
    *,
    limits: tuple[np.ndarray, np.ndarray] | None = None,
    tol: float = DEFAULT_TOL,
    strict: bool = False,
) -> IKSolutions:
    """Every joint vector of a UR-type arm (module docstring) that reaches the pose ``T``.

    Args:
        T: 4×4 pose of frame 6 (the flange) in the base frame (metres).
        d1, a2, a3, d4, d5, d6: DH parameters as published (metres, signed; a2, a3, d6 ≠ 0),
            e.g. :data:`UR5E`.
        limits: Optional ``(lower, upper)`` arrays of 6; angles compared modulo 2π (UR
            joints span ±2π: the in-range representative nearest the wrapped angle is kept).
        tol: Distance (m) by which a sub-problem may be out of reach and be clipped onto its
            boundary; also the size of ``sin θ5`` reported as singular.
        strict: Refuse a near-rotation instead of projecting it
            (:mod:`~redik.core.rotation_policy`).

    Returns:
        Up to 8 solutions ``"left-up-noflip"`` … ``"right-down-flip"``; at ``sin θ5 = 0`` one
        representative per arm branch with θ6 free (``family``); none, with a ``reason``,
        when the pose is out of reach.
    """
    params = ur_parameters(d1, a2, a3, d4, d5, d6)
    return ur_solutions(_checks.pose(T, strict=strict), params, _checks.limits(limits, 6), tol)


def ur_solutions(
    T: np.ndarray,
    params: tuple[float, ...],
    limits: tuple[np.ndarray, np.ndarray] | None,
    tol: float = DEFAULT_TOL,
) -> IKSolutions:
    """:func:`ur` on validated inputs, ``params = (d1, a2, a3, d4, d5, d6)``: for a caller that
    validates at its own boundary (:class:`redik.solvers.analytic.AnalyticSolver`)."""
    M, num = pose_entries(T)
    arm = ur_slots(M, num, *params, tol=tol)
    if not any(slot.valid for slot in arm.slots):
        return unreachable(6, _reason(T, arm, *params))

    def resolve(slot: int, **fixed: float) -> np.ndarray:
        return wrapped(ur_slots(M, num, *params, tol=tol, **fixed).slots[slot].q, REVOLUTE)

    describers = {
        "base_axis": lambda q, slot: free_joint(
            "wrist point p − d6·ẑ on the base axis (d4 = 0): θ1 is arbitrary",
            0,
            lambda t: resolve(slot, theta1=t),
        ),
        "elbow_free": lambda q, slot: free_joint(
            "frame-4 origin on the shoulder axis (|a2| = |a3|): θ2 is arbitrary",
            1,
            lambda t: resolve(slot, theta1=q[0], theta2=t, theta6=q[5]),
        ),
        "shoulder_boundary": lambda q, slot: (
            f"wrist point at distance |d4| = {abs(params[3]):.6g} m from the base axis: "
            "left and right coincide",
            None,
        ),
        "elbow_boundary": lambda q, slot: (
            "arm stretched or folded: elbow up and down coincide",
            None,
        ),
        "wrist": lambda q, slot: free_joint(
            f"wrist singular (θ5 = {'0' if np.cos(q[4]) > 0 else 'π'}): axes 4 and 6 "
            "aligned, θ6 is arbitrary",
            5,
            lambda t: resolve(slot, theta1=q[0], theta6=t),
        ),
    }
    return arm_solutions(arm, ARM_LABELS, describers, REVOLUTE, limits)


def ur_batch(
    T: np.ndarray,
    d1: float,
    a2: float,
    a3: float,
    d4: float,
    d5: float,
    d6: float,
    *,
    limits: tuple[np.ndarray, np.ndarray] | None = None,
    tol: float = DEFAULT_TOL,
    strict: bool = False,
) -> BatchSolutions:
    """:func:`ur` for a (B, 4, 4) stack of poses, vectorised.

    Returns ``q`` (B, 8, 6) in the slot order of :data:`ARM_LABELS` with a (B, 8) ``valid``
    mask; at a singularity several valid slots may hold equivalent solutions.
    """
    T = _checks.poses(T, strict=strict)
    params = ur_parameters(d1, a2, a3, d4, d5, d6)
    checked_limits = _checks.limits(limits, 6)
    M, num = pose_entries(T)
    q, valid, singular = ur_slots(M, num, *params, tol=tol).arrays(T.shape[0])
    return batch_result(q, valid, singular, ARM_LABELS, REVOLUTE, checked_limits)


def ur_parameters(
    d1: float, a2: float, a3: float, d4: float, d5: float, d6: float
) -> tuple[float, ...]:
    """The DH parameters checked (finite; a2, a3, d6 ≠ 0), as :func:`ur_solutions` takes."""
    d1, d4, d5 = (_checks.scalar(v, n) for v, n in ((d1, "d1"), (d4, "d4"), (d5, "d5")))
    a2, a3, d6 = (_checks.nonzero(v, n) for v, n in ((a2, "a2"), (a3, "a3"), (d6, "d6")))
    return d1, a2, a3, d4, d5, d6


def _reason(
    T: np.ndarray,
    arm: ArmSlots,
    d1: float,
    a2: float,
    a3: float,
    d4: float,
    d5: float,
    d6: float,
) -> str:
    if not arm.shoulder_ok:
        p5 = T[:3, 3] - d6 * T[:3, 2]
        return (
            f"wrist point p − d6·ẑ is {np.hypot(p5[0], p5[1]):.6g} m from the base axis, "
            f"closer than the lateral offset |d4| = {abs(d4):.6g} m"
        )
    return two_link_reason(
        float(arm.plane_radius), abs(a2), abs(a3), "the frame-4 origin (every branch)"
    )
