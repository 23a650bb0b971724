r"""PUMA-type 6R arm with a spherical wrist: all eight solutions by wrist-centre decoupling.

Standard DH table (Spong, Hutchinson & Vidyasagar §3.3; the PUMA 560 of Craig 3rd ed.
§3.7/§4.7 in standard form), joint offsets 0:

=====  =====  =====  =====  ======
joint  θ      d      a      α
=====  =====  =====  =====  ======
1      θ1     0      0      −π/2
2      θ2     0      a2     0
3      θ3     d3     a3     π/2
4      θ4     d4     0      −π/2
5      θ5     0      0      π/2
6      θ6     d6     0      0
=====  =====  =====  =====  ======

(``d6 = 0`` by default: the tool point is the wrist centre.) Multiplying out,
:math:`R_0^3 = R_z(θ_1) R_y(θ_2 + θ_3)`, :math:`R_3^6 = R_z(θ_4) R_y(θ_5) R_z(θ_6)` and the
wrist centre :math:`p_c = p - d_6 R \hat z` is

.. math::
    p_c = R_z(θ_1) \begin{pmatrix} X \\ d_3 \\ -Z \end{pmatrix},\quad
    X = a_2 c_2 + a_3 c_{23} + d_4 s_{23},\quad Z = a_2 s_2 + a_3 s_{23} - d_4 c_{23}.

Inverse position (Craig §4.7, Paul's solution, rearranged as two planar problems):

1. Shoulder: :math:`X = \pm\sqrt{p_x^2 + p_y^2 - d_3^2}`,
   :math:`θ_1 = \operatorname{atan2}(p_y, p_x) - \operatorname{atan2}(d_3, X)`.
2. Elbow: :math:`(X, Z)` is reached by a 2R arm of lengths :math:`|a_2|` and
   :math:`\sqrt{a_3^2 + d_4^2}` whose second joint is :math:`θ_3 - \operatorname{atan2}(d_4, a_3)`
   (law of cosines, :func:`redik.solvers.analytic.planar.two_link`), two branches.
3. Wrist: :math:`R_3^6 = R_y(θ_{23})^T R_z(θ_1)^T R` gives θ4, θ5, θ6 as ZYZ Euler angles,
   two branches (:func:`redik.solvers.analytic.wrist.zyz_angles`).

Labels ``"{left|right}-{up|down}-{noflip|flip}"``: *left* when the arm's lateral offset d3
lies to the left of the vertical plane through the base axis and the wrist centre, seen from
the base (:math:`X d_3 > 0`; for d3 = 0, :math:`X > 0`); *up* when the elbow is above the
shoulder–wrist-centre line; *noflip* when θ5 ∈ [0, π].
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
    wrist_columns,
)
from redik.solvers.analytic._numeric import Numeric, pose_entries
from redik.solvers.analytic._solution import (
    DEFAULT_TOL,
    BatchSolutions,
    IKSolutions,
    SolutionFamily,
    unreachable,
)
from redik.solvers.analytic.planar import batch_result, two_link, two_link_reason
from redik.solvers.analytic.wrist import wrist_singularity, zyz_pair

REVOLUTE = np.ones(6, bool)


def dh_rows(a2: float, a3: float, d3: float, d4: float, d6: float = 0.0) -> tuple[DHRow, ...]:
    """The standard DH table of this arm (the module docstring's), for
    :func:`redik.models.dh.forward`."""
    half = np.pi / 2.0
    return (
        DHRow(0.0, 0.0, -half),
        DHRow(a2, 0.0, 0.0),
        DHRow(a3, d3, half),
        DHRow(0.0, d4, -half),
        DHRow(0.0, 0.0, half),
        DHRow(0.0, d6, 0.0),
    )


def puma_slots(
    M: Any,
    num: Numeric,
    a2: float,
    a3: float,
    d3: float,
    d4: float,
    d6: float = 0.0,
    tol: float = DEFAULT_TOL,
    theta1: float | None = None,
    theta2: float | None = None,
) -> ArmSlots:
    """The eight slots of the pose entries ``M[i][j]`` (:func:`._numeric.pose_entries`: one
    target or a batch) — the kernel, the module docstring's steps.

    ``theta1`` / ``theta2`` fix that joint instead of solving for it: how the members of a
    family are generated at the base-axis and shoulder-point singularities.
    """
    px, py, pz = (M[i][3] - d6 * M[i][2] for i in range(3))
    # 1. Shoulder: slot 0 ("left") has X·d3 > 0.
    rho, shoulder_ok, shoulder_boundary, reach = shoulder(px, py, d3, tol, num)
    side = 1.0 if d3 >= 0.0 else -1.0
    heading = num.atan2(py, px)
    base_axis = (rho <= tol) & (abs(d3) <= tol)
    # 2. Elbow: a 2R arm (|a2|, ρ3) in the plane of joints 2 and 3.
    rho3, gamma = math.hypot(a3, d4), math.atan2(d4, a3)
    flipped = math.pi if a2 < 0.0 else 0.0
    slots, plane_radius = [], None
    for left_right, X in enumerate((side * reach, -side * reach)):
        if theta1 is None:
            th1 = heading - num.atan2(d3, X)
        else:
            th1 = theta1
            X = math.cos(theta1) * px + math.sin(theta1) * py
        c1, s1 = num.cos(th1), num.sin(th1)
        plane = two_link(X, -pz, abs(a2), rho3, tol, num)
        plane_radius = plane.radius if plane_radius is None else plane_radius
        valid = shoulder_ok & plane.reachable
        for up_down in (0, 1):
            # The 2R slot with the elbow up depends on which side the shoulder is on.
            branch = up_down ^ left_right ^ (side < 0.0)
            th2 = plane.theta1[branch] - flipped if theta2 is None else theta2
            th3 = plane.theta2[branch] + gamma + flipped
            # 3. Wrist: R36 = Ry(θ2 + θ3)ᵀ Rz(θ1)ᵀ R, ZYZ Euler angles.
            th23 = th2 + th3
            columns = wrist_columns(M, c1, s1, num.cos(th23), num.sin(th23))
            for wrist in zyz_pair(*columns, num):
                flags = {
                    "base_axis": base_axis,
                    "shoulder_boundary": shoulder_boundary,
                    "elbow_free": plane.boundary & (plane.radius <= tol),
                    "elbow_boundary": plane.boundary,
                    "wrist": abs(num.sin(wrist[1])) <= tol,
                }
                slots.append(Slot((th1, th2, th3, *wrist), valid, flags))
    return ArmSlots(slots, shoulder_ok, plane_radius)


def puma(
    T: np.ndarray,
    a2: float,
    a3: float,
    d3: float,
    d4: float,
    *,
    d6: float = 0.0,
    limits: tuple[np.ndarray, np.ndarray] | None = None,
    tol: float = DEFAULT_TOL,
    strict: bool = False,
) -> IKSolutions:
    """Every joint vector of a PUMA-type arm (module docstring) that reaches the pose ``T``.

    Args:
        T: 4×4 pose of frame 6 in the base frame (metres).
        a2, a3, d3, d4: DH parameters (metres, signed; ``a2 ≠ 0``).
        d6: Tool offset along the last axis (0: the pose is the wrist centre's).
        limits: Optional ``(lower, upper)`` arrays of 6; angles compared modulo 2π.
        tol: Distance (m) by which the wrist centre may lie outside the workspace and be
            clipped onto its boundary; also the size of ``sin θ5`` reported as singular.
        strict: Refuse a near-rotation instead of projecting it
            (:mod:`~redik.core.rotation_policy`).

    Returns:
        Up to 8 solutions labelled ``"left-up-noflip"`` … ``"right-down-flip"``; fewer where
        branches coincide (singular, with ``singular`` text and a ``family`` where the
        solutions form a continuum); none, with a ``reason``, when the wrist centre is out of
        reach.
    """
    params = puma_parameters(a2, a3, d3, d4, d6)
    return puma_solutions(_checks.pose(T, strict=strict), params, _checks.limits(limits, 6), tol)


def puma_solutions(
    T: np.ndarray,
    params: tuple[float, float, float, float, float],
    limits: tuple[np.ndarray, np.ndarray] | None,
    tol: float = DEFAULT_TOL,
) -> IKSolutions:
    """:func:`puma` on validated inputs, ``params = (a2, a3, d3, d4, d6)``: for a caller that
    validates at its own boundary (:class:`redik.solvers.analytic.AnalyticSolver`)."""
    M, num = pose_entries(T)
    arm = puma_slots(M, num, *params, tol=tol)
    if not any(slot.valid for slot in arm.slots):
        return unreachable(6, _reason(T, arm, *params))

    def resolve(slot: int, **fixed: float) -> np.ndarray:
        return wrapped(puma_slots(M, num, *params, tol=tol, **fixed).slots[slot].q, REVOLUTE)

    describers = {
        "base_axis": lambda q, slot: free_joint(
            "wrist centre on the base axis: θ1 is arbitrary", 0, lambda t: resolve(slot, theta1=t)
        ),
        "elbow_free": lambda q, slot: free_joint(
            "wrist centre at the shoulder: θ2 is arbitrary", 1, lambda t: resolve(slot, theta2=t)
        ),
        "shoulder_boundary": lambda q, slot: (
            f"wrist centre at distance |d3| = {abs(params[2]):.6g} m from the base axis: "
            "left and right coincide",
            None,
        ),
        "elbow_boundary": lambda q, slot: (
            "arm stretched or folded: elbow up and down coincide",
            None,
        ),
        "wrist": _wrist_describer,
    }
    return arm_solutions(arm, ARM_LABELS, describers, REVOLUTE, limits)


def puma_batch(
    T: np.ndarray,
    a2: float,
    a3: float,
    d3: float,
    d4: float,
    *,
    d6: float = 0.0,
    limits: tuple[np.ndarray, np.ndarray] | None = None,
    tol: float = DEFAULT_TOL,
    strict: bool = False,
) -> BatchSolutions:
    """:func:`puma` for a (B, 4, 4) stack of poses, vectorised.

    Returns ``q`` (B, 8, 6) in the slot order of :data:`ARM_LABELS` with a (B, 8) ``valid``
    mask; at a singularity several valid slots may hold the same (or an equivalent) solution.
    """
    T = _checks.poses(T, strict=strict)
    params = puma_parameters(a2, a3, d3, d4, d6)
    checked_limits = _checks.limits(limits, 6)
    M, num = pose_entries(T)
    q, valid, singular = puma_slots(M, num, *params, tol=tol).arrays(T.shape[0])
    return batch_result(q, valid, singular, ARM_LABELS, REVOLUTE, checked_limits)


def puma_parameters(
    a2: float, a3: float, d3: float, d4: float, d6: float
) -> tuple[float, float, float, float, float]:
    """The DH parameters checked (finite, a2 ≠ 0, a forearm), as :func:`puma_solutions` takes."""
    a2 = _checks.nonzero(a2, "a2")
    a3, d3, d4, d6 = (
        _checks.scalar(v, n) for v, n in ((a3, "a3"), (d3, "d3"), (d4, "d4"), (d6, "d6"))
    )
    if a3 == 0.0 and d4 == 0.0:
        raise _checks.InvalidInput("a3 and d4 must not both be 0 (the forearm has no length)")
    return a2, a3, d3, d4, d6


def _reason(
    T: np.ndarray, arm: ArmSlots, a2: float, a3: float, d3: float, d4: float, d6: float
) -> str:
    if not arm.shoulder_ok:
        centre = T[:3, 3] - d6 * T[:3, 2]
        return (
            f"wrist centre is {np.hypot(centre[0], centre[1]):.6g} m from the base axis, "
            f"closer than the shoulder offset |d3| = {abs(d3):.6g} m"
        )
    return two_link_reason(float(arm.plane_radius), abs(a2), math.hypot(a3, d4), "the wrist centre")


def _wrist_describer(q: np.ndarray, slot: int) -> tuple[str, SolutionFamily]:
    text, wrist = wrist_singularity(q[3:], "ZYZ")
    arm = q[:3].copy()
    return text, SolutionFamily(
        (3,), text, lambda t: np.concatenate([arm, wrist.at(t)]), wrist.invariants
    )
