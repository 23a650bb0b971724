r"""A robot's kinematic chain compiled once from the MuJoCo model into plain arrays.

MuJoCo composes a body's pose from its parent's (``body_pos``, ``body_quat``) and then applies
the body's joints in order (``mj_kinematics``): a hinge rotates about ``jnt_axis`` through the
anchor ``jnt_pos`` by ``q − qpos0``, a slide translates along ``jnt_axis`` by ``q − qpos0``, a
ball rotates about the anchor by its quaternion, a free joint sets the pose outright. Folding
every fixed part into constant transforms gives the chain as a product

.. math::

    T_{we}(q) = F_0 \, M_1(q_1) \, F_1 \, M_2(q_2) \cdots M_n(q_n) \, F_n,

where each *joint frame* is chosen with the joint's axis as its local ``z`` and its anchor as
its origin, so ``M_i`` is simply ``R_z(q_i)`` (hinge) or a translation ``q_i`` along ``z``
(slide). The rotation aligning ``z`` with the axis, the anchor offset and the ``qpos0``
reference are all absorbed into the neighbouring ``F``. Joints the robot does not move (those
off the chain, and on it the ball/free joints and the hinges/slides it holds, ``fixed=``) are
frozen at the robot's home ``qpos`` (the held values of ``robot.state.data.qpos``), as
:class:`redik.Robot` does.

The :class:`Chain` holds only numpy arrays, so it pickles cheaply to worker processes and Ray
tasks, which then need neither MuJoCo nor the model.
"""

from __future__ import annotations

import dataclasses

import mujoco
import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import InvalidInput, ModelError
from redik.kinematics.robot import Frame, Robot
from redik.lie import make_pose, matrix_from_quat, periodic_coordinates, so3_exp

_HINGE, _FREE = int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_FREE)
_CHAIN_TYPES = (_HINGE, int(mujoco.mjtJoint.mjJNT_SLIDE))


@dataclasses.dataclass(frozen=True)
class Chain:
    """A serial chain ``T(q) = F_0 M_1(q_1) F_1 ⋯ M_n(q_n) F_n`` as arrays.

    Attributes:
        base: ``F_0`` (4 × 4), world → first joint frame at ``q_1 = 0``.
        links: ``F_1 … F_n`` (n × 4 × 4); ``links[i]`` maps joint ``i``'s moved frame to joint
            ``i + 1``'s frame, and the last one to the end-effector.
        revolute: True for hinges (``M_i = R_z(q_i)``), False for slides (``M_i = T_z(q_i)``).
        lower, upper: Joint limits (``±inf`` where unlimited).
        sampling_lower, sampling_upper: Bounds for random seeds (the limits, or ±π / ±1 m).
        home: The robot's home configuration.
        name: The robot's name.
        columns: Where each joint sits in the robot's ``q``: ``0 … n−1`` for the
            end-effector, fewer for a frame that only some of the robot's joints move.
    """

    base: NDArray[np.float64]
    links: NDArray[np.float64]
    revolute: NDArray[np.bool_]
    lower: NDArray[np.float64]
    upper: NDArray[np.float64]
    sampling_lower: NDArray[np.float64]
    sampling_upper: NDArray[np.float64]
    home: NDArray[np.float64]
    name: str
    columns: NDArray[np.intp]

    @property
    def dof(self) -> int:
        """Number of joints ``n``."""
        return len(self.revolute)

    def reach(self) -> tuple[NDArray[np.float64], float]:
        """``(centre, radius)``: a ball in the world that holds every end-effector position.

        Hinges do not move the first joint's origin ``centre``; each fixed link adds at most
        its length and each slide its largest extent, so ``radius = Σ ‖p(F_i)‖ + Σ max|q|``
        (infinite with an unlimited slide). A sound bound, not a tight one.
        """
        slide = ~self.revolute
        extent = np.maximum(np.abs(self.lower[slide]), np.abs(self.upper[slide])).sum()
        radius = float(np.linalg.norm(self.links[:, :3, 3], axis=1).sum() + extent)
        return self.base[:3, 3].copy(), radius

    def kernel_arrays(self) -> tuple[NDArray[np.float64] | NDArray[np.bool_], ...]:
        """The arrays the compiled DLS kernel takes, in its order.

        Returns:
            ``(base, links, revolute, lower, upper, sampling_lower, sampling_upper,
            periodic)``; ``periodic`` marks the hinges whose range spans a full turn
            (:func:`redik.lie.periodic_coordinates`): the kernel wraps them by 2π, and an
            unlimited one never leaves its range.
        """
        periodic = periodic_coordinates(self.revolute, self.lower, self.upper)
        return (
            self.base, self.links, self.revolute, self.lower, self.upper,
            self.sampling_lower, self.sampling_upper, periodic,
        )  # fmt: skip

    @classmethod
    def from_robot(cls, robot: Robot, frame: str | Frame | None = None) -> Chain:
        """Compile a robot's chain to a frame from its MuJoCo model.

        The chain holds the robot's joints that move ``frame``, in the robot's order
        (:attr:`columns`): all of them for the end-effector or a frame attached below it.
        Joints off the chain stay at home.

        Args:
            robot: A serial-chain robot (``robot.is_chain``).
            frame: The chain's last frame; default the robot's end-effector.

        Returns:
            The chain.

        Raises:
            UnknownFrame: No such frame, or none given and the robot has no end-effector.
            InvalidInput: ``robot`` is a whole-model robot (compile ``robot.chain(frame)``).
            ModelError: A mocap body on the chain.
        """
        frame = robot.frame(frame)
        if not robot.is_chain:
            raise InvalidInput(
                f"{robot!r} is a whole-model robot; compile one of its chains: "
                f"Chain.from_robot(robot.chain({frame.name!r})) (the other joints held)"
            )
        base, links, addresses = _fold(robot, frame)
        columns = np.array(
            [int(np.flatnonzero(robot.qpos_indices == adr)[0]) for adr in addresses], dtype=int
        )
        return cls(
            base,
            links,
            revolute=np.array(robot.revolute[columns], dtype=bool),
            lower=np.array(robot.lower[columns], dtype=float),
            upper=np.array(robot.upper[columns], dtype=float),
            sampling_lower=np.array(robot.sampling_lower[columns], dtype=float),
            sampling_upper=np.array(robot.sampling_upper[columns], dtype=float),
            home=np.array(robot.home[columns], dtype=float),
            name=robot.name if frame == robot.ee else f"{robot.name}:{frame.name}",
            columns=columns,
        )


def _fold(robot: Robot, ee: Frame) -> tuple[NDArray[np.float64], NDArray[np.float64], list[int]]:
    """``(F_0, [F_1 … F_n], qpos addresses)`` by walking the bodies from the world to ``ee``.

    ``current`` is the transform accumulated since the last moved joint's frame: each body
    multiplies in its pose in its parent, each held joint its motion at the held value, and each
    moved joint closes one ``F`` and starts the next from its own frame.
    """
    model = robot.model
    home_qpos = robot.full_qpos(robot.home)
    moved = {int(adr) for adr in robot.qpos_indices}
    fixed: list[NDArray[np.float64]] = []  # one F per joint boundary, built up as we walk
    addresses: list[int] = []
    current = np.eye(4)
    for body in _path_to(model, robot.body_of(ee)):
        if model.body_mocapid[body] >= 0:
            raise ModelError(f"mocap body {body} on the chain of {robot.name!r} is not supported")
        current = current @ make_pose(matrix_from_quat(model.body_quat[body]), model.body_pos[body])
        start = int(model.body_jntadr[body])
        for joint in range(start, start + int(model.body_jntnum[body])):
            adr = int(model.jnt_qposadr[joint])
            if int(model.jnt_type[joint]) in _CHAIN_TYPES and adr in moved:
                F, current = _split_at_moved_joint(model, joint, current)
                fixed.append(F)
                addresses.append(adr)
            elif int(model.jnt_type[joint]) == _FREE:  # sets the body's world pose outright
                current = _free_joint_pose(model, joint, home_qpos)
            else:
                current = current @ _held_joint_motion(model, joint, home_qpos)
    fixed.append(current @ _frame_offset(model, ee))
    return fixed[0], np.stack(fixed[1:]) if addresses else np.empty((0, 4, 4)), addresses


def _path_to(model: mujoco.MjModel, body: int) -> list[int]:
    """The bodies from the world's first child down to ``body``."""
    path = []
    while body > 0:
        path.append(body)
        body = int(model.body_parentid[body])
    return path[::-1]


def _split_at_moved_joint(
    model: mujoco.MjModel, joint: int, current: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Close one fixed transform at a moved joint and start the next.

    Returns:
        ``(F, next)``: ``F`` ends at the joint's frame (its axis as ``z``; for a hinge, its
        anchor as origin); ``next`` undoes that frame and MuJoCo's ``qpos0`` reference, since
        ``M_i`` acts on ``q − qpos0``.
    """
    hinge = int(model.jnt_type[joint]) == _HINGE
    anchor = model.jnt_pos[joint]
    align = make_pose(_z_to(model.jnt_axis[joint]), np.zeros(3))
    to_anchor = make_pose(np.eye(3), anchor if hinge else np.zeros(3))
    reference = float(model.qpos0[int(model.jnt_qposadr[joint])])
    undo = np.eye(4)
    if hinge:
        undo[:3, :3] = _rot_z(-reference)
    else:
        undo[2, 3] = -reference
    after = undo @ align.T @ make_pose(np.eye(3), -anchor if hinge else np.zeros(3))
    return current @ to_anchor @ align, after


def _held_joint_motion(
    model: mujoco.MjModel, joint: int, qpos: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The motion of a hinge, slide or ball joint the robot holds, at its value in ``qpos``.

    As MuJoCo applies it: a hinge or slide turns or shifts by ``q − qpos0`` about or along its
    axis, a ball turns about its anchor by its quaternion.
    """
    kind = int(model.jnt_type[joint])
    adr = int(model.jnt_qposadr[joint])
    anchor = model.jnt_pos[joint]
    if kind in _CHAIN_TYPES:
        value = qpos[adr] - model.qpos0[adr]
        axis = model.jnt_axis[joint] / np.linalg.norm(model.jnt_axis[joint])
        if kind == _HINGE:
            return _about(anchor, make_pose(so3_exp(value * axis), np.zeros(3)))
        return make_pose(np.eye(3), value * axis)
    return _about(anchor, make_pose(matrix_from_quat(qpos[adr : adr + 4]), np.zeros(3)))


def _free_joint_pose(
    model: mujoco.MjModel, joint: int, qpos: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The world pose a held free joint gives its body: position, then quaternion in ``qpos``."""
    adr = int(model.jnt_qposadr[joint])
    return make_pose(matrix_from_quat(qpos[adr + 3 : adr + 7]), qpos[adr : adr + 3])


def _frame_offset(model: mujoco.MjModel, frame: Frame) -> NDArray[np.float64]:
    """The frame's pose in its body: a site's or a geom's offset, the identity for a body."""
    if frame.kind == "site":
        return make_pose(matrix_from_quat(model.site_quat[frame.id]), model.site_pos[frame.id])
    if frame.kind == "geom":
        return make_pose(matrix_from_quat(model.geom_quat[frame.id]), model.geom_pos[frame.id])
    return np.eye(4)


def _about(anchor: NDArray[np.float64], rotation: NDArray[np.float64]) -> NDArray[np.float64]:
    """A rotation about the point ``anchor``: ``T(anchor) · R · T(−anchor)``."""
    return make_pose(np.eye(3), anchor) @ rotation @ make_pose(np.eye(3), -anchor)


def _rot_z(angle: float) -> NDArray[np.float64]:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _z_to(axis: NDArray[np.float64]) -> NDArray[np.float64]:
    """A rotation ``A`` with ``A e_z = axis / ‖axis‖`` (columns: a right-handed frame)."""
    z = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    return np.column_stack((x, np.cross(z, x), z))
