r"""Forward kinematics and Jacobians of a :class:`~redik.kinematics.chain.Chain` over a whole batch.

Frames, twist order ``(v, ω)`` and Jacobian references are those of :mod:`redik.core.conventions`.

Inside, arrays are laid out **batch last** — a rotation batch is ``(3, 3, B)``, a Jacobian
batch ``(6, n, B)`` — so every arithmetic step is one numpy call on contiguous vectors of
length ``B`` and constant 3 × 3 products are a single BLAS call; the public functions return
the usual batch-first arrays. The chain is walked joint by joint (Modern Robotics §4.1 in
product form): at joint ``i`` the current frame's ``z`` column is the joint's world axis
``ω_i`` and its origin a point ``o_i`` on the axis, so the world Jacobian is

.. math::

    J_i = \begin{pmatrix} ω_i × (p − o_i) \\ ω_i \end{pmatrix} \text{(hinge)}, \qquad
    J_i = \begin{pmatrix} ω_i \\ 0 \end{pmatrix} \text{(slide)},

with ``p`` the end-effector position.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import InvalidConfiguration, InvalidInput
from redik.kinematics.chain import Chain
from redik.kinematics.robot import JACOBIAN_REFERENCES
from redik.lie import world_jacobian_to


def chain_poses(chain: Chain, q: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
    """End-effector poses and joint axes for ``q`` given batch last (``n × B``), unchecked.

    Returns:
        ``(R, p, axes, origins)``: rotations ``(3, 3, B)``, positions ``(3, B)``, and each
        joint's world axis and origin ``(n, 3, B)``.
    """
    n, size = q.shape
    base = chain.base
    R = np.empty((3, 3, size))
    R[:] = base[:3, :3, None]
    p = np.empty((3, size))
    p[:] = base[:3, 3, None]
    axes: list[NDArray[np.float64]] = []
    origins: list[NDArray[np.float64]] = []
    cos, sin = np.cos(q), np.sin(q)  # one call each: the trig is a third of the cost
    for i in range(n):
        # Every step below makes new arrays, so the views kept here stay valid.
        axes.append(R[:, 2])
        origins.append(p)
        link = chain.links[i]
        if chain.revolute[i]:
            c, s = cos[i], sin[i]
            moved = np.empty((3, 3, size))
            # R · R_z(q): the x and y columns turn, z stays.
            np.multiply(R[:, 0], c, out=moved[:, 0])
            moved[:, 0] += R[:, 1] * s
            np.multiply(R[:, 1], c, out=moved[:, 1])
            moved[:, 1] -= R[:, 0] * s
            moved[:, 2] = R[:, 2]
        else:
            moved = R
            p = p + R[:, 2] * q[i]
        p = p + np.matmul(link[:3, 3], moved)
        R = np.matmul(link[:3, :3].T, moved)
    return R, p, np.stack(axes), np.stack(origins)


def world_jacobian(
    chain: Chain, p: NDArray[np.float64], axes: NDArray[np.float64], origins: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The ``"world"`` Jacobian ``(6, n, B)`` from :func:`chain_poses`' output, unchecked."""
    n, _, size = axes.shape
    J = np.empty((6, n, size))
    arm = p[None] - origins
    ax, ay, az = axes[:, 0], axes[:, 1], axes[:, 2]
    J[0] = ay * arm[:, 2] - az * arm[:, 1]
    J[1] = az * arm[:, 0] - ax * arm[:, 2]
    J[2] = ax * arm[:, 1] - ay * arm[:, 0]
    J[3:] = axes.transpose(1, 0, 2)
    slide = ~chain.revolute
    if slide.any():
        J[:3, slide] = J[3:, slide]
        J[3:, slide] = 0.0
    return J


def _as_batch(chain: Chain, q: NDArray[np.float64]) -> NDArray[np.float64]:
    q = np.asarray(q, dtype=float)
    if q.ndim == 1:
        q = q[None]
    if q.ndim != 2 or q.shape[1] != chain.dof:
        raise InvalidConfiguration(
            f"q must have shape (B, {chain.dof}) or ({chain.dof},) for {chain.name}, got {q.shape}"
        )
    if not np.all(np.isfinite(q)):
        raise InvalidConfiguration("q holds NaN or inf")
    return np.ascontiguousarray(q.T)


def forward_kinematics(chain: Chain, q: NDArray[np.float64]) -> NDArray[np.float64]:
    """End-effector poses ``T_we`` (B × 4 × 4) for joint vectors ``q`` (B × n, or n)."""
    R, p, _, _ = chain_poses(chain, _as_batch(chain, q))
    T = np.zeros((p.shape[1], 4, 4))
    T[:, :3, :3] = R.transpose(2, 0, 1)
    T[:, :3, 3] = p.T
    T[:, 3, 3] = 1.0
    return T


def jacobian(chain: Chain, q: NDArray[np.float64], reference: str = "space") -> NDArray[np.float64]:
    """End-effector Jacobians (B × 6 × n) in ``reference`` ("space", "body" or "world").

    The references are those of :meth:`redik.Robot.jacobian` (see :mod:`redik.core.conventions`):
    ``space`` adds ``p × ω`` to the linear rows, ``body`` rotates both halves by ``Rᵀ``.
    """
    if reference not in JACOBIAN_REFERENCES:
        raise InvalidInput(f"reference must be one of {JACOBIAN_REFERENCES}, got {reference!r}")
    R, p, axes, origins = chain_poses(chain, _as_batch(chain, q))
    J = world_jacobian(chain, p, axes, origins)
    if reference != "world":
        J = world_jacobian_to(reference, J, R, p, out=J if reference == "space" else None)
    batch: NDArray[np.float64] = J.transpose(2, 0, 1)
    return batch
