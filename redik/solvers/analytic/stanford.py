r"""Stanford arm (RRP with a spherical wrist): every solution with :math:`d_3 \ge 0`.

Standard DH table (Spong, Hutchinson & Vidyasagar §3.3.5), joint offsets 0, q3 = d3:

=====  =====  =====  =====  ======
joint  θ      d      a      α
=====  =====  =====  =====  ======
1      θ1     d1     0      −π/2
2      θ2     d2     0      π/2
3      0      d3     0      0
4      θ4     0      0      −π/2
5      θ5     0      0      π/2
6      θ6     d6     0      0
=====  =====  =====  =====  ======

(``d1 = 0`` in Spong: base frame at the shoulder.) Multiplying out,
:math:`R_0^3 = R_z(θ_1) R_y(θ_2)`, :math:`R_3^6 = R_z(θ_4) R_y(θ_5) R_z(θ_6)`, and the wrist
centre :math:`p_c = p - d_6 R\hat z` is
:math:`R_z(θ_1)\,(d_3 s_2,\; d_2,\; d_1 + d_3 c_2)`. Inverse (Spong §3.3.5):

1. :math:`X = \pm\sqrt{p_{cx}^2 + p_{cy}^2 - d_2^2}`,
   :math:`θ_1 = \operatorname{atan2}(p_{cy}, p_{cx}) - \operatorname{atan2}(d_2, X)`.
2. :math:`d_3 = \sqrt{X^2 + (p_{cz} - d_1)^2} \ge 0`, :math:`θ_2 = \operatorname{atan2}(X,
   p_{cz} - d_1)` (the other sign of d3 is excluded).
3. :math:`R_3^6 = R_y(θ_2)^T R_z(θ_1)^T R`, ZYZ Euler angles, two branches.

Labels ``"{left|right}-{noflip|flip}"``: *left* when the offset d2 lies to the left of the
vertical plane through the base axis and the wrist centre, seen from the base
(:math:`X d_2 > 0`; for d2 = 0, :math:`X > 0`); *noflip* when θ5 ∈ [0, π].
Singular: the wrist centre on the shoulder cylinder (left = right), at the shoulder
(d3 = 0, θ2 free), on the base axis when d2 = 0 (θ1 free), and the wrist.

Course angles (``convention="course"``, :data:`COURSE`): DH measures θ2 from the vertical
base axis ``z0`` (θ2 = 0: boom straight up); the course measures the shoulder as the boom's
elevation above the horizontal plane, :math:`β = π/2 - θ_2` (positive up, the boom's
``atan2(p_{cz} - d_1, X)``), the other joints as DH:
``(θ1, β, d3, θ4, θ5, θ6) = COURSE.from_joints(q)``; ``COURSE.to_joints`` goes back.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from redik.models.dh import DHRow
from redik.solvers.analytic import _checks
from redik.solvers.analytic._arm import (
    SHOULDER_WRIST_LABELS,
    ArmSlots,
    Slot,
    arm_solutions,
    free_joint,
    shoulder,
    wrapped,
    wrist_columns,
)
from redik.solvers.analytic._numeric import Numeric, pose_entries
from redik.solvers.analytic._solution import (
    DEFAULT_TOL,
    IKSolutions,
    SolutionFamily,
    unreachable,
)
from redik.solvers.analytic.convention import AngleConvention, solve_in
from redik.solvers.analytic.wrist import wrist_singularity, zyz_pair

#: Which joints are angles (q3 = d3 is a length).
REVOLUTE = np.array([True, True, False, True, True, True])


def dh_rows(d2: float, d6: float, d1: float = 0.0) -> tuple[DHRow, ...]:
    """The standard DH table of this arm (the module docstring's), for
    :func:`redik.models.dh.forward`;
    row 3 is prismatic with offset 0, so q3 = d3."""
    half = np.pi / 2.0
    return (
        DHRow(0.0, d1, -half),
        DHRow(0.0, d2, half),
        DHRow(0.0, 0.0, 0.0, 0.0, "prismatic"),
        DHRow(0.0, 0.0, -half),
        DHRow(0.0, 0.0, half),
        DHRow(0.0, d6, 0.0),
    )


def stanford_slots(
    M: Any,
    num: Numeric,
    d2: float,
    d6: float,
    d1: float = 0.0,
    tol: float = DEFAULT_TOL,
    theta1: float | None = None,
    theta2: float | None = None,
) -> ArmSlots:
    """The four slots (shoulder × wrist) of the pose entries ``M[i][j]``
    (:func:`._numeric.pose_entries`) — the kernel, the module docstring's steps.

    ``theta1`` / ``theta2`` fix that joint instead of solving for it (family members).
    """
    px, py, pz = (M[i][3] - d6 * M[i][2] for i in range(3))
    rho, shoulder_ok, shoulder_boundary, reach = shoulder(px, py, d2, tol, num)
    side = 1.0 if d2 >= 0.0 else -1.0
    heading = num.atan2(py, px)
    base_axis = (rho <= tol) & (abs(d2) <= tol)
    slots, extension = [], None
    for X in (side * reach, -side * reach):
        if theta1 is None:
            th1 = heading - num.atan2(d2, X)
        else:
            th1 = theta1
            X = math.cos(theta1) * px + math.sin(theta1) * py
        Z = pz - d1
        d3 = num.hypot(X, Z)
        extension = d3 if extension is None else extension
        th2 = num.atan2(X, Z) if theta2 is None else theta2
        # R36 = Ry(θ2)ᵀ Rz(θ1)ᵀ R, ZYZ Euler angles.
        columns = wrist_columns(M, num.cos(th1), num.sin(th1), num.cos(th2), num.sin(th2))
        for wrist in zyz_pair(*columns, num):
            flags = {
                "base_axis": base_axis,
                "shoulder_boundary": shoulder_boundary,
                "elbow_free": d3 <= tol,
                "wrist": abs(num.sin(wrist[1])) <= tol,
            }
            slots.append(Slot((th1, th2, d3, *wrist), shoulder_ok, flags))
    return ArmSlots(slots, shoulder_ok, extension)


def stanford(
    T: np.ndarray,
    d2: float,
    d6: float,
    *,
    d1: float = 0.0,
    limits: tuple[np.ndarray, np.ndarray] | None = None,
    tol: float = DEFAULT_TOL,
    strict: bool = False,
    convention: str = "dh",
) -> IKSolutions:
    """Every ``(θ1, θ2, d3, θ4, θ5, θ6)`` with ``d3 ≥ 0`` of a Stanford arm reaching ``T``.

    Args:
        T: 4×4 pose of frame 6 in the base frame (metres).
        d2: Shoulder offset (m, signed). d6: Tool length along the last axis (m, signed).
        d1: Height of the shoulder above the base frame (m; 0 in Spong's table).
        limits: Optional ``(lower, upper)`` arrays of 6; angles compared modulo 2π, d3 as is.
        tol: Distance (m) from a singular set reported as singular.
        strict: Refuse a near-rotation instead of projecting it
            (:mod:`~redik.core.rotation_policy`).
        convention: ``"dh"`` or ``"course"`` (θ2 as the boom's elevation, module docstring)
            for the solutions and the limits.

    Returns:
        Up to 4 solutions ``"left-noflip"`` … ``"right-flip"``; none, with a ``reason``,
        when the wrist centre is closer to the base axis than ``|d2|``.
    """
    return solve_in(
        convention,
        CONVENTIONS,
        "stanford",
        limits,
        6,
        lambda joint_limits: _stanford(T, d2, d6, d1, joint_limits, tol, strict),
    )


def _stanford(
    T: np.ndarray,
    d2: float,
    d6: float,
    d1: float,
    checked_limits: tuple[np.ndarray, np.ndarray] | None,
    tol: float,
    strict: bool,
) -> IKSolutions:
    T = _checks.pose(T, strict=strict)
    d2, d6, d1 = (_checks.scalar(v, n) for v, n in ((d2, "d2"), (d6, "d6"), (d1, "d1")))
    M, num = pose_entries(T)
    arm = stanford_slots(M, num, d2, d6, d1, tol)
    if not arm.shoulder_ok:
        centre = T[:3, 3] - d6 * T[:3, 2]
        return unreachable(
            6,
            f"wrist centre is {np.hypot(centre[0], centre[1]):.6g} m from the base axis, "
            f"closer than the shoulder offset |d2| = {abs(d2):.6g} m",
        )

    def resolve(slot: int, **fixed: float) -> np.ndarray:
        return wrapped(stanford_slots(M, num, d2, d6, d1, tol, **fixed).slots[slot].q, REVOLUTE)

    describers = {
        "base_axis": lambda q, slot: free_joint(
            "wrist centre on the base axis (d2 = 0): θ1 is arbitrary",
            0,
            lambda t: resolve(slot, theta1=t),
        ),
        "elbow_free": lambda q, slot: free_joint(
            "wrist centre at the shoulder (d3 = 0): θ2 is arbitrary",
            1,
            lambda t: resolve(slot, theta1=q[0], theta2=t),
        ),
        "shoulder_boundary": lambda q, slot: (
            f"wrist centre at distance |d2| = {abs(d2):.6g} m from the base axis: "
            "left and right coincide",
            None,
        ),
        "wrist": _wrist_describer,
    }
    return arm_solutions(arm, SHOULDER_WRIST_LABELS, describers, REVOLUTE, checked_limits)


def _wrist_describer(q: np.ndarray, slot: int) -> tuple[str, SolutionFamily]:
    text, wrist = wrist_singularity(q[3:], "ZYZ")
    arm = q[:3].copy()
    return text, SolutionFamily(
        (3,), text, lambda t: np.concatenate([arm, wrist.at(t)]), wrist.invariants
    )


# --------------------------------------------------------------------------------------
# The course's angle convention (module docstring), a thin map over the DH solution.

COURSE = AngleConvention(
    name="course",
    symbols=("θ1", "β", "d3", "θ4", "θ5", "θ6"),
    signs=(1.0, -1.0, 1.0, 1.0, 1.0, 1.0),
    offsets=(0.0, np.pi / 2.0, 0.0, 0.0, 0.0, 0.0),
    description="β = π/2 − θ2, the boom's elevation above the horizontal; the rest as DH",
)
"""The course's Stanford-arm angles ``(θ1, π/2 − θ2, d3, θ4, θ5, θ6)``."""

CONVENTIONS: dict[str, AngleConvention | None] = {"dh": None, "course": COURSE}
"""The values of :func:`stanford`'s ``convention=``."""
