r"""Spherical wrist: the three angles of a rotation, both solutions.

A spherical wrist has three revolute axes through one point, so its joints are Euler angles of
the wrist rotation (Craig 3rd ed. §2.8 and §4.7; Spong, Hutchinson & Vidyasagar §3.3.4;
Siciliano et al. §2.4 and §2.12.3).

``"ZYZ"`` (the wrist of the PUMA, Stanford and most 6R arms)
    :math:`R = R_z(θ_4)\, R_y(θ_5)\, R_z(θ_6)`, so :math:`r_{33} = \cos θ_5` and

    .. math::
        θ_5 = \operatorname{atan2}(\pm\sqrt{r_{13}^2 + r_{23}^2},\; r_{33}),\quad
        θ_4 = \operatorname{atan2}(\pm r_{23}, \pm r_{13}).

    The second solution is :math:`(θ_4 + π, −θ_5, θ_6 + π)` ("flip"). Singular when
    :math:`\sin θ_5 = 0`: only :math:`θ_4 + θ_6` (θ5 = 0) or :math:`θ_4 − θ_6` (θ5 = π) is
    determined.
``"ZXZ"`` (the other wrist the course notes name, 002 "Inverse kinematics for robots with
spherical wrist")
    :math:`R = R_z(θ_4)\, R_x(θ_5)\, R_z(θ_6)`. Since :math:`R_x(θ) = R_z(-π/2)\, R_y(θ)\,
    R_z(π/2)`, its angles are the ZYZ angles of the same R with
    :math:`(θ_4 + π/2,\; θ_5,\; θ_6 - π/2)`: :math:`θ_4 = \operatorname{atan2}(\pm r_{13},
    \mp r_{23})`, the same flip and the same singularity as ZYZ.
``"ZYX"`` (yaw–pitch–roll)
    :math:`R = R_z(α)\, R_y(β)\, R_x(γ)`, :math:`r_{31} = −\sin β`; the second solution is
    :math:`(α + π, π − β, γ + π)`. Singular when :math:`\cos β = 0`.

The third angle is not read off one more pair of entries but fitted to what the first two
leave, :math:`R_z(θ_6) = R_y(θ_5)^T R_z(θ_4)^T R` (resp. :math:`R_x(γ)`): this keeps the
product exact to rounding even arbitrarily close to the singularity, where the first angle is
ill-conditioned but matters less and less.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from redik.solvers.analytic import _checks
from redik.solvers.analytic._numeric import ARRAY, Numeric, Value
from redik.solvers.analytic.results import (
    DEFAULT_TOL,
    IKSolutions,
    JointSolution,
    SolutionFamily,
    finalize,
    wrap_angle,
)

Convention = Literal["ZYZ", "ZXZ", "ZYX"]

#: The conventions :func:`spherical_wrist` accepts.
CONVENTIONS = ("ZYZ", "ZXZ", "ZYX")

#: Slot labels of :func:`zyz_angles` / :func:`zyx_angles` and :func:`spherical_wrist`.
WRIST_LABELS = ("noflip", "flip")


def zyz_angles(R: np.ndarray) -> np.ndarray:
    """Both ZYZ solutions of rotations.

    Both ZYZ solutions of rotations ``R`` (..., 3, 3) as (..., 2, 3): [noflip, flip],
    with ``sin θ5 ≥ 0`` for noflip. At ``sin θ5 = 0`` noflip has θ4 = 0.
    """
    columns = (R[..., 0, 0], R[..., 1, 0], R[..., 2, 0], R[..., 0, 2], R[..., 1, 2], R[..., 2, 2])
    noflip, flip = zyz_pair(*columns, ARRAY)
    return wrap_angle(np.stack([np.stack(noflip, axis=-1), np.stack(flip, axis=-1)], axis=-2))


Angles = tuple[Value, Value, Value]


def zyz_pair(
    r00: Value, r10: Value, r20: Value, r02: Value, r12: Value, r22: Value, num: Numeric
) -> tuple[Angles, Angles]:
    """Both ZYZ solutions from two columns of R.

    :func:`zyz_angles` from the first and last columns of ``R``, elementwise in
    :mod:`._numeric`'s sense: ``((θ4, θ5, θ6) noflip, (θ4, θ5, θ6) flip)``, not wrapped.
    """
    theta5 = num.atan2(num.hypot(r02, r12), r22)
    theta4 = num.atan2(r12, r02)
    c4, s4 = num.cos(theta4), num.sin(theta4)
    c5, s5 = num.cos(theta5), num.sin(theta5)
    # Rz(θ6) = Ry(θ5)ᵀ Rz(θ4)ᵀ R, read from its first column.
    theta6 = num.atan2(c4 * r10 - s4 * r00, c5 * (c4 * r00 + s4 * r10) - s5 * r20)
    return (theta4, theta5, theta6), (theta4 + np.pi, -theta5, theta6 + np.pi)


def zxz_angles(R: np.ndarray) -> np.ndarray:
    """Both ZXZ solutions of rotations.

    Both ZXZ solutions of rotations ``R`` (..., 3, 3) as (..., 2, 3): :func:`zyz_angles`
    with the first angle turned by +π/2 and the last by −π/2 (module docstring).
    """
    return wrap_angle(zyz_angles(R) + np.array([np.pi / 2.0, 0.0, -np.pi / 2.0]))


def zyx_angles(R: np.ndarray) -> np.ndarray:
    """Both ZYX (yaw, pitch, roll) solutions of rotations.

    Both ZYX (yaw, pitch, roll) solutions of ``R`` (..., 3, 3) as (..., 2, 3):
    [noflip, flip], with ``cos β ≥ 0`` for noflip. At ``cos β = 0`` noflip has α = 0.
    """
    beta = np.arctan2(-R[..., 2, 0], np.hypot(R[..., 0, 0], R[..., 1, 0]))
    alpha = np.arctan2(R[..., 1, 0], R[..., 0, 0])
    ca, sa = np.cos(alpha), np.sin(alpha)
    cb, sb = np.cos(beta), np.sin(beta)
    # Rx(γ) = Ry(β)ᵀ Rz(α)ᵀ R, read from its second column.
    gamma = np.arctan2(
        sb * (ca * R[..., 0, 1] + sa * R[..., 1, 1]) + cb * R[..., 2, 1],
        ca * R[..., 1, 1] - sa * R[..., 0, 1],
    )
    noflip = np.stack([alpha, beta, gamma], axis=-1)
    flip = np.stack([alpha + np.pi, np.pi - beta, gamma + np.pi], axis=-1)
    return wrap_angle(np.stack([noflip, flip], axis=-2))


def wrist_singularity(angles: np.ndarray, convention: Convention) -> tuple[str, SolutionFamily]:
    """Describe a singular wrist and its family.

    Describe the singular wrist whose representative is ``angles`` (first angle 0 or any),
    and the family through it: the first angle is free, the third follows.
    """
    a, b, c = (float(v) for v in angles)
    if convention in ("ZYZ", "ZXZ"):
        same_sign = np.cos(b) > 0.0  # θ5 = 0: θ4 + θ6 fixed; θ5 = π: θ4 − θ6 fixed
        name, middle, names = "θ5", ("0" if same_sign else "π"), ("θ4", "θ6")
        key = "theta4+theta6" if same_sign else "theta4-theta6"
    else:
        same_sign = np.sin(b) < 0.0  # β = −π/2: α + γ fixed; β = π/2: α − γ fixed
        name, middle, names = "β", ("−π/2" if same_sign else "π/2"), ("α", "γ")
        key = "alpha+gamma" if same_sign else "alpha-gamma"
    combined = float(wrap_angle(a + c if same_sign else a - c))
    sign = "+" if same_sign else "−"
    text = (
        f"wrist singular ({name} = {middle}): only {names[0]} {sign} {names[1]} = "
        f"{combined:.6g} is determined"
    )

    def member(t: float) -> np.ndarray:
        third = combined - t if same_sign else t - combined
        return wrap_angle(np.array([t, b, third]))

    return text, SolutionFamily((0,), text, member, {key: combined})


def spherical_wrist(
    R: np.ndarray,
    convention: Convention = "ZYZ",
    *,
    limits: tuple[np.ndarray, np.ndarray] | None = None,
    tol: float = DEFAULT_TOL,
    strict: bool = False,
) -> IKSolutions:
    r"""Both Euler-angle solutions ``(θ4, θ5, θ6)`` of a wrist rotation ``R``.

    Args:
        R: 3×3 rotation matrix (the wrist rotation :math:`R_3^6 = R_3^{0\,T} R_0^6` of an arm).
        convention: ``"ZYZ"``, ``"ZXZ"`` or ``"ZYX"`` (see the module docstring for the
            equations).
        limits: Optional ``(lower, upper)`` arrays of 3; solutions are shifted by 2π into
            range when possible, else dropped.
        tol: Size of ``sin θ5`` (``cos β``) below which the wrist is reported singular.
        strict: Refuse a near-rotation instead of projecting it
            (:mod:`~redik.core.rotation_policy`).

    Returns:
        Two solutions labelled ``"noflip"`` (θ5 ∈ [0, π], resp. |β| ≤ π/2) and ``"flip"``;
        at the singularity one representative with ``singular`` text naming the combined
        angle and a :class:`SolutionFamily` (first angle free).
    """
    R = _checks.rotation(R, strict=strict)
    if convention not in CONVENTIONS:
        raise _checks.InvalidInput(
            f"convention must be one of {list(CONVENTIONS)}, got {convention!r}"
        )
    checked_limits = _checks.limits(limits, 3)
    angles = _ANGLES[convention](R)
    degenerate = np.cos(angles[0, 1]) if convention == "ZYX" else np.sin(angles[0, 1])
    revolute = np.ones(3, bool)
    if abs(degenerate) <= tol:
        text, family = wrist_singularity(angles[0], convention)
        candidates = [JointSolution(angles[0], WRIST_LABELS[0], text, family)]
    else:
        candidates = [
            JointSolution(q, label) for q, label in zip(angles, WRIST_LABELS, strict=True)
        ]
    return finalize(candidates, 3, revolute, checked_limits)


_ANGLES = {"ZYZ": zyz_angles, "ZXZ": zxz_angles, "ZYX": zyx_angles}
