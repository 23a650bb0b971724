r"""Hexapod leg: coxa yaw, femur and tibia pitch from the foot position.

Forward kinematics in the leg frame (origin on the coxa yaw axis, z up, x along the coxa at
θ1 = 0). The femur pitch axis sits ``coxa`` out along the coxa and ``z_offset`` above the
leg origin; in the vertical leg plane with outward coordinate ``u``:

.. math::
    u = \text{coxa} + \text{femur}\,\cos θ_2 + \text{tibia}\,\cos(θ_2 + θ_3),\quad
    p_z = z_\text{offset} + \text{femur}\,\sin θ_2 + \text{tibia}\,\sin(θ_2 + θ_3),\quad
    (p_x, p_y) = u\,(\cos θ_1, \sin θ_1).

θ2 is the femur elevation above the horizontal and θ3 the tibia angle relative to the femur,
both positive upward (a hinge axis along :math:`-\hat y` of the leg plane).

Inverse (the usual hexapod IK, a 2R problem in the leg plane, see :mod:`.planar`):
:math:`θ_1 = \operatorname{atan2}(p_y, p_x)`, then the femur–tibia pair reaches
:math:`(\sqrt{p_x^2+p_y^2} - \text{coxa},\; p_z - z_\text{offset})` by the law of cosines.
Rotating the coxa by π (:math:`u = -\sqrt{p_x^2+p_y^2} - \text{coxa}`) gives two more,
"reversed", solutions when the foot is within reach behind the coxa.

Knee labels: ``"knee-up"`` has θ3 < 0, the knee above the femur–foot line for a foot outward
and below; this is the branch a hexapod walks with (``result.preferred``). ``"knee-down"``
has θ3 > 0.

Lecture angles (``convention="lecture"``, :data:`LECTURE`)
    The hexapod example of the course notes (001, "Example: Analytical IK") finds the three
    servo angles of a foot at :math:`(x, y)` on the ground, :math:`Z_\text{offset}` below the
    femur axis, with :math:`L_1 = \sqrt{x^2 + y^2}` and
    :math:`L = \sqrt{Z_\text{offset}^2 + (L_1 - \text{coxa})^2}`:

    .. math::
        γ = \arctan\frac{x}{y},\qquad
        α = \arccos\frac{Z_\text{offset}}{L}
            + \arccos\frac{\text{tibia}^2 - \text{femur}^2 - L^2}{-2\,\text{femur}\,L},
        \qquad
        β = \arccos\frac{L^2 - \text{tibia}^2 - \text{femur}^2}{-2\,\text{tibia}\,
            \text{femur}},

    γ the coxa angle measured from the leg's outward axis (the notes' y), α the femur angle
    measured from the downward vertical and β the interior knee angle between femur and
    tibia (π: the stretched leg). In this module's terms the notes' y is the leg frame's x
    (outward), their x is its y, :math:`L_1 = \sqrt{p_x^2 + p_y^2}` and
    :math:`Z_\text{offset} = z_\text{offset} - p_z`, the height of the femur axis above the
    foot; the notes' foot is ``p = (y, x, z_offset − Z_offset)``. Then

    .. math:: γ = θ_1, \qquad α = θ_2 + π/2, \qquad β = θ_3 + π,

    given per joint (coxa, femur, tibia) as ``(γ, α, β)``: ``β ∈ (0, π)`` is the knee-up
    (walking) branch, ``β ∈ (π, 2π)`` the knee-down one.
    :meth:`LECTURE.from_joints <redik.solvers.analytic.convention.AngleConvention.from_joints>`
    and ``LECTURE.to_joints`` convert either way; with ``convention="lecture"`` the solver
    takes its ``limits`` and returns its solutions in these angles.
"""

from __future__ import annotations

import numpy as np

from redik.solvers.analytic import _checks
from redik.solvers.analytic._numeric import SCALAR
from redik.solvers.analytic.convention import AngleConvention, solve_in
from redik.solvers.analytic.planar import two_link, two_link_candidates, two_link_reason
from redik.solvers.analytic.results import (
    DEFAULT_TOL,
    IKSolutions,
    JointSolution,
    SolutionFamily,
    finalize,
    unreachable,
    wrap_angle,
)

KNEE_LABELS = ("knee-down", "knee-up")  # 2R slot 0 has θ3 ≥ 0
PREFERRED = "knee-up"

LECTURE = AngleConvention(
    name="lecture",
    symbols=("γ", "α", "β"),
    signs=(1.0, 1.0, 1.0),
    offsets=(0.0, np.pi / 2.0, np.pi),
    description=(
        "γ coxa angle from the outward axis, α femur angle from the downward vertical, "
        "β interior knee angle"
    ),
)
"""The course notes' angles ``(γ, α, β) = (θ1, θ2 + π/2, θ3 + π)`` per joint (module
docstring)."""

CONVENTIONS: dict[str, AngleConvention | None] = {"joint": None, "lecture": LECTURE}
"""The values of ``convention=``: the joint angles (θ1, θ2, θ3), or the lecture's angles."""


def hexapod_leg(
    p: np.ndarray,
    coxa: float,
    femur: float,
    tibia: float,
    z_offset: float = 0.0,
    *,
    limits: tuple[np.ndarray, np.ndarray] | None = None,
    tol: float = DEFAULT_TOL,
    convention: str = "joint",
) -> IKSolutions:
    """Every ``(θ_coxa, θ_femur, θ_tibia)`` that puts the foot at ``p`` (leg frame).

    Args:
        p: Foot position (3,) in the leg frame (metres), see the module docstring.
        coxa: Coxa length, from the yaw axis to the femur axis (m, ≥ 0).
        femur: Femur length (m, > 0).
        tibia: Tibia length (m, > 0).
        z_offset: Height of the femur axis above the leg origin (m, signed).
        limits: Optional ``(lower, upper)`` arrays of 3; angles compared modulo 2π.
        tol: Distance (m) within which a target counts as on a boundary or on the yaw axis.
        convention: ``"joint"`` (θ1, θ2, θ3) or ``"lecture"`` (γ, α, β), for the solutions
            and the limits (see the module docstring).

    Returns:
        ``"knee-up"`` (preferred), ``"knee-down"`` and, when reachable, the coxa-reversed
        ``"reversed-knee-up"``/``"reversed-knee-down"``; fewer on a boundary. A foot on the
        yaw axis gives representatives with θ1 free (family).
    """
    px, py, pz = _checks.finite_array(p, "p", (3,))
    coxa = _checks.length(coxa, "coxa", allow_zero=True)
    femur, tibia = _checks.length(femur, "femur"), _checks.length(tibia, "tibia")
    z_offset = _checks.scalar(z_offset, "z_offset")
    return solve_in(
        convention,
        CONVENTIONS,
        "hexapod_leg",
        limits,
        3,
        lambda joint_limits: _solve(px, py, pz, coxa, femur, tibia, z_offset, joint_limits, tol),
    )


def _solve(
    px: float,
    py: float,
    pz: float,
    coxa: float,
    femur: float,
    tibia: float,
    z_offset: float,
    checked_limits: tuple[np.ndarray, np.ndarray] | None,
    tol: float,
) -> IKSolutions:
    r, z = float(np.hypot(px, py)), float(pz - z_offset)
    on_axis = r <= tol
    yaw = 0.0 if on_axis else float(np.arctan2(py, px))
    # Forward coxa, then reversed; on the yaw axis both are members of one family per knee.
    branches = (
        [(yaw, r - coxa, "")]
        if on_axis
        else [(yaw, r - coxa, ""), (yaw + np.pi, -r - coxa, "reversed-")]
    )
    candidates: list[JointSolution] = []
    reasons: list[str] = []
    for theta1, u, prefix in branches:
        plane = two_link(u, z, femur, tibia, tol, SCALAR)
        if not plane.reachable:
            what = f"the foot ({u:.6g}, {z:.6g}) in the {prefix or 'forward '}leg plane"
            reasons.append(two_link_reason(float(plane.radius), femur, tibia, what))
            continue
        labels = (prefix + KNEE_LABELS[0], prefix + KNEE_LABELS[1])
        for q, label, singular, free in two_link_candidates(plane, femur, tibia, tol, labels):
            candidates.append(_leg_solution(q, theta1, label, singular, free, on_axis))
    if not candidates:
        return unreachable(3, reasons[0])
    return finalize(candidates, 3, np.ones(3, bool), checked_limits, PREFERRED)


def _leg_solution(
    knee: tuple[float, float],
    theta1: float,
    label: str,
    singular: str,
    femur_free: bool,
    on_axis: bool,
) -> JointSolution:
    if femur_free:  # foot on the femur axis with femur = tibia
        text = f"foot on the femur axis ({singular}): θ2 is arbitrary, θ3 = π"
        family = SolutionFamily((1,), text, lambda t: wrap_angle(np.array([theta1, t, np.pi])))
        return JointSolution(np.array([theta1, *knee]), label, text, family)
    if on_axis:
        text = "foot on the coxa yaw axis: θ1 is arbitrary"
        if singular:
            text += f"; {singular}"
        family = SolutionFamily((0,), text, lambda t: wrap_angle(np.array([t, *knee])))
        return JointSolution(np.array([theta1, *knee]), label, text, family)
    return JointSolution(np.array([theta1, *knee]), label, singular)
