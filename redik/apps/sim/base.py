"""A floating base under the robot: refused when nothing holds it up, or held by request.

A robot whose chain hangs below a free joint (a humanoid or quadruped loaded with
``floating_base=True``, a robosuite or Menagerie model whose root body is free) has a base
that no actuator drives. Under gravity and with nothing supporting it — no contact with the
world and no equality constraint to it at the start — it falls, and the servos' tracking of
a falling robot says nothing about the IK. :func:`~redik.apps.sim.simulate` therefore refuses
such a base unless told ``hold_base=True``, which holds it at its initial pose, as if bolted
down. Refusal is the default because holding silently would report a tracking the robot
could not achieve; the error names the option. A base that stands on something, or floats
without gravity (a free-flying manipulator), is simulated free.

Holding is done in the physics, not by resetting the state alone: the free joint's six
degrees of freedom get an armature (added diagonal inertia) many orders of magnitude above the
robot's mass, so that the coupled equations ``M q̈ = τ`` leave the base's acceleration at
``τ_base / armature`` — zero to round-off — and the joints accelerate as on a fixed base; the
base's position and velocity are then set back to their initial values after every tick, so
that nothing drifts. The armature is on a private copy of the model.
"""

from __future__ import annotations

import copy

import mujoco
import numpy as np

from redik.core.exceptions import ModelError
from redik.kinematics.robot import Robot

HOLD_ARMATURE = 1e9
"""Armature of a held base's degrees of freedom, per kilogram of the robot (kg, kg·m²)."""

FREE = mujoco.mjtJoint.mjJNT_FREE
TIES = {int(mujoco.mjtEq.mjEQ_CONNECT), int(mujoco.mjtEq.mjEQ_WELD)}
"""Equality constraints that can hold a body up."""


def free_base(robot: Robot) -> int | None:
    """The free joint above the robot's joints (its floating base), or None for a fixed base.

    Args:
        robot: The robot; the bodies of its joints are walked up to the world.

    Returns:
        The free joint's id, or None when no body above the robot's joints has one.
    """
    model = robot.model
    for joint in robot.joint_ids:
        body = int(model.jnt_bodyid[joint])
        while body > 0:
            start = model.body_jntadr[body]
            for j in range(start, start + model.body_jntnum[body]):
                if model.jnt_type[j] == FREE:
                    return j
            body = int(model.body_parentid[body])
    return None


def supported(model: mujoco.MjModel, data: mujoco.MjData, joint: int) -> bool:
    """Whether the tree of a free joint is held up at the state of ``data``.

    Held up means: gravity is off, or a geom of the tree touches a geom outside it, or an
    active connect or weld equality ties a body of the tree to a body outside it.

    Args:
        model: The model.
        data: A state on which ``mj_forward`` has run (its contacts are read).
        joint: The free joint's id.
    """
    gravity_off = model.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_GRAVITY
    if gravity_off or not np.any(model.opt.gravity):
        return True
    tree = model.body_rootid == model.body_rootid[model.jnt_bodyid[joint]]
    tree[0] = False
    geoms = data.contact.geom[: data.ncon]
    touching = data.contact.dist[: data.ncon] <= 0.0
    inside = tree[model.geom_bodyid[geoms[touching]]]
    if np.any(inside[:, 0] != inside[:, 1]):
        return True
    return _tied_by_equality(model, data, tree)


def _tied_by_equality(model: mujoco.MjModel, data: mujoco.MjData, tree: np.ndarray) -> bool:
    """An active connect or weld joins a body of ``tree`` (a mask of bodies) to one outside."""
    for e in range(model.neq):
        if not data.eq_active[e] or int(model.eq_type[e]) not in TIES:
            continue
        bodies = [int(model.eq_obj1id[e]), int(model.eq_obj2id[e])]
        if model.eq_objtype[e] == mujoco.mjtObj.mjOBJ_SITE:
            bodies = [int(model.site_bodyid[s]) for s in bodies]
        if tree[bodies[0]] != tree[bodies[1]]:
            return True
    return False


def check_base(robot: Robot, hold: bool, qpos: np.ndarray) -> int | None:
    """The free joint :func:`~redik.apps.sim.simulate` must hold, or None.

    Args:
        robot: The robot to simulate.
        hold: ``hold_base`` of :func:`~redik.apps.sim.simulate`.
        qpos: The run's initial state, at which support is judged.

    Returns:
        The free joint to hold (``hold`` and the robot has a floating base), else None.

    Raises:
        ModelError: the robot moves its free joint itself (no actuator can drive one), or
            its floating base is unsupported under gravity and ``hold`` is False.
    """
    joint = free_base(robot)
    if joint is None:
        return None
    model = robot.model
    name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, joint) or f"#{joint}"
    if joint in set(robot.joint_ids.tolist()):
        raise ModelError(
            f"{robot.name!r} moves its free joint {name!r}, which no actuator can drive: "
            f"simulate() drives joints through actuators. Build the robot with "
            f"fixed=[{name!r}] and simulate it with hold_base=True"
        )
    if hold:
        return joint
    data = mujoco.MjData(model)
    data.qpos[:] = qpos
    mujoco.mj_forward(model, data)
    if not supported(model, data, joint):
        raise ModelError(
            f"{robot.name!r} has a floating base (free joint {name!r}) that nothing supports "
            f"at the start (no contact with the world, no weld): under gravity it would "
            f"fall. Pass hold_base=True to hold the base at its initial pose, or stand the "
            f"robot on the ground"
        )
    return None


class BaseHold:
    """A model whose free joint is held still, and the pinning of that joint's state.

    Args:
        model: The robot's model (left unchanged; the held one is a copy).
        joint: The free joint to hold.
    """

    def __init__(self, model: mujoco.MjModel, joint: int):
        self.model = copy.deepcopy(model)
        self.name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, joint) or f"#{joint}"
        qpos, dof = int(model.jnt_qposadr[joint]), int(model.jnt_dofadr[joint])
        self.qpos, self.dofs = slice(qpos, qpos + 7), slice(dof, dof + 6)
        mass = float(model.body_subtreemass[model.body_rootid[model.jnt_bodyid[joint]]])
        self.model.dof_armature[self.dofs] = HOLD_ARMATURE * max(mass, 1.0)
        self.pose = np.empty(7)

    def start(self, data: mujoco.MjData) -> None:
        """Remember the base's pose in ``data`` (the run's initial state) as the held one."""
        self.pose[:] = data.qpos[self.qpos]
        data.qvel[self.dofs] = 0.0

    def pin(self, data: mujoco.MjData) -> None:
        """Set the base back to its held pose, at rest."""
        data.qpos[self.qpos] = self.pose
        data.qvel[self.dofs] = 0.0
