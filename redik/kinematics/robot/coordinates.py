"""Where a set of joints lives in MuJoCo's position and velocity vectors.

``q`` holds the joints' entries of ``model.qpos`` (7 per free joint, 4 per ball joint, 1 per
hinge or slide), a tangent step ``Δq`` their entries of ``model.qvel`` (6, 3, 1): see
:mod:`redik.kinematics.robot.robot` for how the two are related. :class:`JointCoordinates`
is the bookkeeping between them — addresses, per-coordinate names, limits and kinds, and
where the quaternions sit — computed once from the model.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import mujoco
import numpy as np
from numpy.typing import NDArray

from redik.kinematics.robot.selection import (
    BALL,
    CHAIN_JOINT_TYPES,
    FREE,
    HINGE,
    JOINT_TYPE_NAMES,
    SLIDE,
    joint_name,
)

JOINT_NQ = {FREE: 7, BALL: 4, SLIDE: 1, HINGE: 1}
"""Entries of ``qpos`` per joint type."""

JOINT_NV = {FREE: 6, BALL: 3, SLIDE: 1, HINGE: 1}
"""Entries of ``qvel`` (tangent coordinates) per joint type."""


@dataclasses.dataclass(frozen=True)
class JointCoordinates:
    """The position and tangent coordinates of a set of joints, in the given order.

    Attributes:
        joint_ids: The joints' MuJoCo ids.
        joint_names: Their names.
        joint_types: Their types, ``"hinge"``, ``"slide"``, ``"ball"``, ``"free"``.
        qpos_adr: Index in ``model.qpos`` of each entry of ``q``.
        dof_adr: Index in ``model.qvel`` of each tangent coordinate.
        dof_names: One name per tangent coordinate (``"base:wx"`` for a free joint's).
        dof_joints: The joint of each tangent coordinate.
        revolute: Per tangent coordinate, True for rotations (hinge, ball, a free joint's
            angular part).
        lower, upper: Joint limits per tangent coordinate (``±inf`` where a joint has no
            range, and on ball and free joints).
        scalar_dofs, scalar_q: The hinge and slide joints' tangent coordinate and index in q.
        quaternion_q: Where a ball or free joint's quaternion starts in ``q``.
        quaternion_dofs: The tangent coordinate where its rotation vector starts.
        free_q: Where a free joint's position starts in ``q``.
        free_dofs: The tangent coordinate where it starts.
    """

    joint_ids: NDArray[np.intp]
    joint_names: tuple[str, ...]
    joint_types: tuple[str, ...]
    qpos_adr: NDArray[np.intp]
    dof_adr: NDArray[np.intp]
    dof_names: tuple[str, ...]
    dof_joints: tuple[str, ...]
    revolute: NDArray[np.bool_]
    lower: NDArray[np.float64]
    upper: NDArray[np.float64]
    scalar_dofs: NDArray[np.intp]
    scalar_q: NDArray[np.intp]
    quaternion_q: tuple[int, ...]
    quaternion_dofs: tuple[int, ...]
    free_q: tuple[int, ...]
    free_dofs: tuple[int, ...]

    @classmethod
    def of(
        cls, model: mujoco.MjModel, joint_ids: Sequence[int] | NDArray[np.intp]
    ) -> JointCoordinates:
        """The coordinates of ``joint_ids`` (in that order) in ``model``."""
        names = tuple(joint_name(model, j) for j in joint_ids)
        types = [int(model.jnt_type[j]) for j in joint_ids]
        qpos_adr = np.concatenate(
            [
                model.jnt_qposadr[j] + np.arange(JOINT_NQ[t])
                for j, t in zip(joint_ids, types, strict=True)
            ]
        ).astype(int)
        dof_adr = np.concatenate(
            [
                model.jnt_dofadr[j] + np.arange(JOINT_NV[t])
                for j, t in zip(joint_ids, types, strict=True)
            ]
        ).astype(int)
        dof_names: list[str] = []
        dof_joints: list[str] = []
        revolute: list[bool] = []
        lower: list[float] = []
        upper: list[float] = []
        scalar_dofs: list[int] = []
        scalar_q: list[int] = []
        quaternion_q: list[int] = []
        quaternion_dofs: list[int] = []
        free_q: list[int] = []
        free_dofs: list[int] = []
        q_offset = 0
        for j, t, name in zip(joint_ids, types, names, strict=True):
            if t == FREE:
                free_q.append(q_offset)
                free_dofs.append(len(dof_names))
            if t in (FREE, BALL):
                quaternion_q.append(q_offset + (3 if t == FREE else 0))
                quaternion_dofs.append(len(dof_names) + (3 if t == FREE else 0))
            if t in CHAIN_JOINT_TYPES:
                scalar_dofs.append(len(dof_names))
                scalar_q.append(q_offset)
                dof_names.append(name)
                dof_joints.append(name)
                revolute.append(t == HINGE)
                limited = bool(model.jnt_limited[j])
                lower.append(model.jnt_range[j, 0] if limited else -np.inf)
                upper.append(model.jnt_range[j, 1] if limited else np.inf)
            else:
                axes = ("wx", "wy", "wz") if t == BALL else ("x", "y", "z", "wx", "wy", "wz")
                dof_names.extend(f"{name}:{axis}" for axis in axes)
                dof_joints.extend([name] * len(axes))
                revolute.extend(axis.startswith("w") for axis in axes)
                lower.extend([-np.inf] * len(axes))
                upper.extend([np.inf] * len(axes))
            q_offset += JOINT_NQ[t]
        coordinates = cls(
            joint_ids=np.array(joint_ids, dtype=int),
            joint_names=names,
            joint_types=tuple(JOINT_TYPE_NAMES[t] for t in types),
            qpos_adr=qpos_adr,
            dof_adr=dof_adr,
            dof_names=tuple(dof_names),
            dof_joints=tuple(dof_joints),
            revolute=np.array(revolute, dtype=bool),
            lower=np.array(lower, dtype=float),
            upper=np.array(upper, dtype=float),
            scalar_dofs=np.array(scalar_dofs, dtype=int),
            scalar_q=np.array(scalar_q, dtype=int),
            quaternion_q=tuple(quaternion_q),
            quaternion_dofs=tuple(quaternion_dofs),
            free_q=tuple(free_q),
            free_dofs=tuple(free_dofs),
        )
        for array in (coordinates.lower, coordinates.upper, coordinates.revolute):
            array.setflags(write=False)
        return coordinates
