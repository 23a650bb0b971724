"""Frames of a MuJoCo model: sites, bodies and geoms, resolved by name once and read by id.

A task or a solver names the frame it places (``"ee"``, ``"body:panda_hand"``); the name is
resolved once into a :class:`Frame` (kind and id), and the hot path reads that frame's pose
and world Jacobian from ``MjData`` through it (:func:`frame_pose_views`,
:func:`frame_jacobian`). Frame conventions: :mod:`redik.core.conventions`.
"""

from __future__ import annotations

import dataclasses

import mujoco
import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import InvalidInput
from redik.models import loading

FRAME_KINDS = ("site", "body", "geom")
"""The kinds of MuJoCo object a frame can be, in the order a bare name is looked up."""

FRAME_OBJECTS = {
    "site": mujoco.mjtObj.mjOBJ_SITE,
    "body": mujoco.mjtObj.mjOBJ_BODY,
    "geom": mujoco.mjtObj.mjOBJ_GEOM,
}
FRAME_JACOBIANS = {
    "site": mujoco.mj_jacSite,
    "body": mujoco.mj_jacBody,
    "geom": mujoco.mj_jacGeom,
}
"""MuJoCo's world Jacobian function of each kind (``jac(model, data, jacp, jacr, id)``)."""


@dataclasses.dataclass(frozen=True)
class Frame:
    """A resolved frame: a site, a body or a geom of the model, by id."""

    name: str
    kind: str  # "site", "body" or "geom"
    id: int


def resolve_frame(model: mujoco.MjModel, name: str, owner: str) -> Frame:
    """The site, body or geom called ``name`` (looked up in that order).

    ``"geom:name"`` (or ``"body:"``, ``"site:"``) picks the kind when names collide.

    Raises:
        UnknownFrame: no such frame in ``model`` (the message lists the frames there are,
            naming ``owner``, e.g. ``"model 'panda'"``).
    """
    prefix, _, rest = name.partition(":")
    kinds, bare = ((prefix,), rest) if rest and prefix in FRAME_KINDS else (FRAME_KINDS, name)
    for kind in kinds:
        index = mujoco.mj_name2id(model, FRAME_OBJECTS[kind], bare)
        if index >= 0:
            return Frame(name, kind, index)
    raise loading.unknown_frame(model, name, owner, kinds)


def frame_names(model: mujoco.MjModel, kind: str = "site") -> list[str]:
    """Names of the model's sites, bodies or geoms (``kind`` = "site", "body", "geom")."""
    if kind not in FRAME_KINDS:
        raise InvalidInput(f"kind must be one of {FRAME_KINDS}, got {kind!r}")
    count = {"site": model.nsite, "body": model.nbody, "geom": model.ngeom}
    names = (mujoco.mj_id2name(model, FRAME_OBJECTS[kind], i) for i in range(count[kind]))
    return [n for n in names if n]


def leaf_bodies(model: mujoco.MjModel) -> list[str]:
    """Names of the model's leaf bodies: those no other body hangs from (hands, feet, flanges).

    Args:
        model: The MuJoCo model.

    Returns:
        The named leaf bodies, in model order (the world excluded).
    """
    parents = set(model.body_parentid[1:].tolist())
    names = (
        mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, body)
        for body in range(1, model.nbody)
        if body not in parents
    )
    return [name for name in names if name]


def frame_body(model: mujoco.MjModel, frame: Frame) -> int:
    """Id of the body ``frame`` is attached to (itself for a body)."""
    if frame.kind == "site":
        return int(model.site_bodyid[frame.id])
    if frame.kind == "geom":
        return int(model.geom_bodyid[frame.id])
    return frame.id


def frame_pose_views(
    data: mujoco.MjData, frame: Frame
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Views ``(R, p)`` of ``frame``'s world rotation and position inside ``data``."""
    if frame.kind == "site":
        return data.site_xmat[frame.id].reshape(3, 3), data.site_xpos[frame.id]
    if frame.kind == "geom":
        return data.geom_xmat[frame.id].reshape(3, 3), data.geom_xpos[frame.id]
    return data.xmat[frame.id].reshape(3, 3), data.xpos[frame.id]


def frame_jacobian(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    frame: Frame,
    jacp: NDArray[np.float64],
    jacr: NDArray[np.float64],
) -> None:
    """MuJoCo's world Jacobian of ``frame`` (``mj_jacSite``/``mj_jacBody``/``mj_jacGeom``)."""
    FRAME_JACOBIANS[frame.kind](model, data, jacp, jacr, frame.id)
