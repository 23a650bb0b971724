r"""Screw axes (product of exponentials) → the MJCF of their serial arm (:func:`screws_to_mjcf`)."""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import InvalidInput, ModelError
from redik.core.rotation_policy import as_pose
from redik.lie import adjoint
from redik.models.builder.description import screw_numerics
from redik.models.builder.link import Link
from redik.models.builder.serial_arm import serial_arm_to_mjcf

UNIT_TOLERANCE = 1e-6
"""How far ``‖ω‖`` or ``‖v‖`` may be from 1, and the pitch from 0, in a screw column."""


def screws_to_mjcf(
    screws: Any,
    M: Any,
    frame: str = "space",
    limits: Any = None,
    *,
    name: str = "poe_robot",
    home: Any = None,
    radius: float | None = None,
    actuators: bool = True,
    custom: Mapping[str, float | Sequence[float]] | None = None,
    floor_height: float = 0.0,
    comment: str | None = None,
) -> str:
    r"""MJCF of the serial arm given by the product of exponentials (Modern Robotics §4.1).

    .. math:: T(q) = e^{[S_1] q_1} \cdots e^{[S_n] q_n} M = M e^{[B_1] q_1} \cdots e^{[B_n] q_n}

    Body screws are first converted to space screws, :math:`S_i = [\mathrm{Ad}_M] B_i`. The
    bodies are nested and all sit at the world origin with identity orientation at
    ``q = 0``, so each joint is written with its world axis: a revolute joint
    (:math:`\|\omega\| = 1`, zero pitch) at the point :math:`q = \omega \times v` of its
    axis, a prismatic joint (:math:`\omega = 0`, :math:`\|v\| = 1`) along :math:`v`. The
    ``ee`` site is at ``M`` in the last body.

    Args:
        screws: Screw axes, shape ``(6, n)``, each column ``(ω, v)`` (MR order).
        M: End-effector pose at ``q = 0`` (4×4).
        frame: ``"space"`` (``screws`` are :math:`S_i`) or ``"body"`` (:math:`B_i`).
        limits: Joint ranges, n × 2 (as for :func:`~redik.models.builder.dh_to_mjcf`, and
            so are the options below).
        name: The model's name.
        home: The ``home`` keyframe's joint values.
        radius: The links' capsule radius (m); default sized from the arm's reach.
        actuators: Add a position servo per joint.
        custom: Extra ``<numeric>`` entries.
        floor_height: Height of the floor plane (m).
        comment: A comment at the top of the document.

    Returns:
        The MJCF document. The space screws are stored in the numeric ``redik_poe_screws``
        (n × 6, row-major, each row ``(ω, v)``) and ``M`` in ``redik_poe_M`` (row-major).

    Raises:
        ModelError: A column is helical (non-zero pitch) or has a non-unit axis.
        InvalidInput: Bad shape, frame, limits, home, radius or custom entry.
        InvalidPose: ``M`` is not a rigid transform.
    """
    S = space_screws(screws, M, frame)
    M = as_pose(M, "M")
    links = []
    previous_anchor = np.zeros(3)
    for i in range(S.shape[1]):
        omega, v = S[:3, i], S[3:, i]
        prismatic = not np.any(omega)
        anchor = previous_anchor if prismatic else np.cross(omega, v)
        links.append(Link(np.eye(4), prismatic, v if prismatic else omega, anchor.copy()))
        previous_anchor = anchor
    for link, following in itertools.pairwise(links):
        link.next_anchor = following.anchor.copy()
    links[-1].next_anchor = M[:3, 3].copy()
    return serial_arm_to_mjcf(
        links,
        M,
        limits=limits,
        name=name,
        home=home,
        radius=radius,
        actuators=actuators,
        custom=custom,
        stored=screw_numerics(S, M),
        texts={},
        floor_height=floor_height,
        comment=comment,
    )


def space_screws(screws: Any, M: Any, frame: str) -> NDArray[np.float64]:
    r"""Check screw axes and express them in the space frame.

    Body screws are converted by :math:`S_i = [\mathrm{Ad}_M] B_i` (Modern Robotics §4.1.3).

    Args:
        screws: 6 × n, columns ``(ω, v)`` in Modern Robotics' order (a single 6-vector is one
            column).
        M: The end-effector's home pose (4, 4).
        frame: ``"space"`` when the columns are space screws ``S_i``, ``"body"`` when they are
            body screws ``B_i``.

    Returns:
        The space screws :math:`S_i` (6 × n), each revolute (:math:`\|\omega\| = 1`, pitch
        :math:`\omega \cdot v = 0`) or prismatic (:math:`\omega = 0` exactly,
        :math:`\|v\| = 1`) within :data:`UNIT_TOLERANCE`.

    Raises:
        InvalidInput: Not a finite 6 × n array, or a bad ``frame``.
        InvalidPose: ``M`` is not a rigid transform (body screws).
        ModelError: A helical column or a non-unit axis.
    """
    S = _screw_array(screws)
    if frame not in ("space", "body"):
        raise InvalidInput(f"frame must be 'space' or 'body', got {frame!r}")
    if frame == "body":
        # lie.adjoint acts on (v, ω) twists, so swap the halves of the (ω, v) screws around it.
        swap = np.r_[3:6, 0:3]
        S = (adjoint(as_pose(M, "M")) @ S[swap])[swap]
    for i in range(S.shape[1]):
        _check_screw(S[:, i], i)
    return S


def _screw_array(screws: Any) -> NDArray[np.float64]:
    """``screws`` as a finite float (6, n) array, or :class:`InvalidInput` saying why not."""
    try:
        S = np.array(screws, dtype=float)
    except (TypeError, ValueError):
        raise InvalidInput(f"screws must be a 6×n array of numbers, got {screws!r}") from None
    if S.ndim == 1 and S.shape == (6,):
        S = S.reshape(6, 1)
    if S.ndim != 2 or S.shape[0] != 6 or S.shape[1] == 0:
        raise InvalidInput(
            f"screws must have shape (6, n) with columns (ω, v), got {S.shape}"
            + (" (transpose it?)" if S.ndim == 2 and S.shape[1] == 6 else "")
        )
    if not np.all(np.isfinite(S)):
        raise InvalidInput(f"screws must be finite, got\n{S}")
    return S


def _check_screw(screw: NDArray[np.float64], i: int) -> None:
    """Refuse a helical or non-unit column ``i``; zero a prismatic one's tiny ``ω`` in place."""
    omega, v = screw[:3], screw[3:]
    norm_omega = float(np.linalg.norm(omega))
    if norm_omega <= UNIT_TOLERANCE:
        omega[:] = 0.0
        norm_v = float(np.linalg.norm(v))
        if abs(norm_v - 1.0) > UNIT_TOLERANCE:
            raise ModelError(
                f"screw column {i}: a prismatic axis (ω = 0) needs ‖v‖ = 1, got ‖v‖ = {norm_v:.9g}"
            )
        return
    if abs(norm_omega - 1.0) > UNIT_TOLERANCE:
        raise ModelError(
            f"screw column {i}: a revolute axis needs ‖ω‖ = 1, got ‖ω‖ = {norm_omega:.9g}"
        )
    pitch = float(omega @ v)
    if abs(pitch) > UNIT_TOLERANCE:
        raise ModelError(
            f"screw column {i} has pitch ω·v = {pitch:.9g}; only revolute (pitch 0) "
            "and prismatic (ω = 0) joints are supported, not helical ones"
        )
