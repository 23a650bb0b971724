r"""RRP polar (spherical) arm: base yaw, elevation and a prismatic extension.

Forward kinematics, with the shoulder at height :math:`d_1` on the base (yaw) axis and a
boom of fixed length :math:`a_2` that the prismatic joint extends by θ3:

.. math::
    p = \begin{pmatrix} (θ_3 + a_2) \cos θ_2 \cos θ_1 \\ (θ_3 + a_2) \cos θ_2 \sin θ_1 \\
        d_1 + (θ_3 + a_2) \sin θ_2 \end{pmatrix},\qquad θ_3 + a_2 \ge 0,

θ1 the yaw about z, θ2 the elevation above the horizontal plane (the course notes' Stanford-type
arm, 000 "Example 2: Stanford-Type Arms (RRP)"; :math:`a_2 = 0` is Spong, Hutchinson &
Vidyasagar's spherical configuration, §3.3.2). With :math:`r = \sqrt{p_x^2 + p_y^2}` and
:math:`z = p_z - d_1`:

.. math::
    θ_3 = \sqrt{r^2 + z^2} - a_2,\quad
    (θ_1, θ_2) = (\operatorname{atan2}(p_y, p_x),\; \operatorname{atan2}(z, r))
    \;\text{("front")}\ \text{or}\ (θ_1 + π,\; π - θ_2)\;\text{("back", over the top)}.

Singular: on the yaw axis (:math:`r = 0`) θ1 is arbitrary and θ2 = ±π/2; at the shoulder
(:math:`θ_3 + a_2 = 0`) θ1 and θ2 both are.
"""

from __future__ import annotations

import numpy as np

from redik.solvers.analytic import _checks
from redik.solvers.analytic.results import (
    DEFAULT_TOL,
    IKSolutions,
    JointSolution,
    SolutionFamily,
    finalize,
    wrap_angle,
)

#: Which joints are angles (the extension d3 is not wrapped).
REVOLUTE = np.array([True, True, False])


def rrp_polar(
    p: np.ndarray,
    d1: float,
    *,
    a2: float = 0.0,
    limits: tuple[np.ndarray, np.ndarray] | None = None,
    tol: float = DEFAULT_TOL,
) -> IKSolutions:
    """Every ``(θ1, θ2, θ3)`` with ``θ3 + a2 ≥ 0`` of an RRP polar arm that reaches ``p``.

    Args:
        p: Target point (3,) in the base frame (metres).
        d1: Height of the shoulder (the elevation axis) above the base origin (metres).
        a2: Length of the boom at θ3 = 0 (metres, ≥ 0), so that the tip is θ3 + a2 from the
            shoulder (module docstring).
        limits: Optional ``(lower, upper)`` arrays of 3; angles compared modulo 2π.
        tol: Distance (m) from the yaw axis (resp. the shoulder) reported as singular.

    Returns:
        ``"front"`` and ``"back"``; on the yaw axis one representative (θ1 = 0) with θ1 free;
        at the shoulder one (0, 0, −a2) with θ1 and θ2 free. Every point is reachable.
    """
    px, py, pz = _checks.finite_array(p, "p", (3,))
    d1 = _checks.scalar(d1, "d1")
    a2 = _checks.length(a2, "a2", allow_zero=True)
    checked_limits = _checks.limits(limits, 3)
    r, z = float(np.hypot(px, py)), float(pz - d1)
    reach = float(np.hypot(r, z))  # θ3 + a2
    if reach <= tol:
        text = "target at the shoulder: θ3 + a2 = 0 and θ1, θ2 are arbitrary"
        family = SolutionFamily(
            (0, 1), text, lambda t1, t2: np.array([wrap_angle(t1), wrap_angle(t2), -a2])
        )
        candidates = [JointSolution(np.array([0.0, 0.0, -a2]), "front", text, family)]
    elif r <= tol:
        elevation = np.copysign(np.pi / 2.0, z)
        text = f"target on the yaw axis: θ2 = {elevation:+.6g}, θ1 is arbitrary"
        family = SolutionFamily(
            (0,), text, lambda t: np.array([float(wrap_angle(t)), elevation, reach - a2])
        )
        candidates = [JointSolution(np.array([0.0, elevation, reach - a2]), "front", text, family)]
    else:
        yaw, elevation = np.arctan2(py, px), np.arctan2(z, r)
        candidates = [
            JointSolution(np.array([yaw, elevation, reach - a2]), "front"),
            JointSolution(np.array([yaw + np.pi, np.pi - elevation, reach - a2]), "back"),
        ]
    return finalize(candidates, 3, REVOLUTE, checked_limits)
