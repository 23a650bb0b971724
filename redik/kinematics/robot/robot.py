r"""The kinematic model: a MuJoCo model plus the joints redik may move.

Every robot in redik is a :class:`mujoco.MjModel`, however it was described (MJCF, URDF,
a Denavit–Hartenberg table, screw axes), so every feature works on every robot. Frames,
twist order and Jacobian references are those of :mod:`redik.core.conventions`.

**Two kinds of robot.** A *chain* (``Robot(model, ee)``, or ``Robot(model)`` of a model with
a site named ``ee``, :data:`NATURAL_FRAME`) moves the hinge and slide joints on the path from
the root to one end-effector; every other joint stays at its value in ``state.data.qpos``.
All of redik works on a chain, including the serial-chain fast paths (compiled DLS, batch,
closed forms, self-motion). A *whole-model* robot (``Robot(model)`` of a model that names no
end-effector, as :func:`redik.load` gives for a third-party file; ``Robot(model,
joints="all")``; or a list of joint names and ``fnmatch`` patterns such as
``["left/*", "right/*"]`` with ``fixed=["*finger*"]``) moves any set of hinge, slide, ball
and free joints — two arms, a floating base — for the task/limit :class:`redik.Problem`.
Frames are named where they are used; :meth:`Robot.chain` cuts the chain to one out of it for
the fast paths, the other joints held, and what needs a chain and is given no frame lists
the frames a user would pick (:meth:`Robot.suggested_frames`).

**Configuration and tangent space.** ``q`` holds the moved joints' entries of
``model.qpos`` (``robot.nq`` values: 7 for a free joint, position then unit quaternion
``(w, x, y, z)``; 4 for a ball joint; 1 for a hinge or slide), while a step ``Δq``, a
Jacobian column, a limit bound, a task cost live in the tangent space (``robot.dof`` values,
MuJoCo's velocity coordinates: for a free joint the linear velocity in world axes then the
angular velocity in the body frame). They are related by MuJoCo's exponential map,

.. math::

    q \oplus Δq = \texttt{mj\_integratePos}(q, Δq, 1), \qquad
    q_1 \ominus q_0 = \texttt{mj\_differentiatePos}(q_0, q_1, 1),

(:meth:`Robot.integrate`, :meth:`Robot.difference`: for a quaternion
:math:`Q \oplus ω = Q \otimes \exp(ω/2)`, Solà et al., *A micro Lie theory*, 2018),
which reduce to ``q + Δq`` and ``q₁ − q₀`` for hinge and slide joints. A robot without
ball or free joints is ``flat`` (``nq == dof``) and takes the plain-vector shortcuts.
Joint position boxes exist for hinge and slide joints only: ``lower``/``upper`` are per
tangent coordinate, ``±inf`` on ball and free joints. A ball joint's range is a cone on its
rotation angle, which :class:`redik.BallJointLimit` enforces; a free joint has none.

A :class:`Robot` is the model side and does not change once built: joints, coordinates,
limits, frames, names. Forward kinematics runs on its kinematic state :attr:`Robot.state`
(:class:`~redik.kinematics.robot.state.RobotState`, one ``MjData``): the public
:meth:`Robot.fk` and :meth:`Robot.jacobian` check their input and return fresh arrays, while
solvers and tasks call ``robot.state`` in their loops, which checks nothing and writes into
caller-owned buffers. The constructors from files, strings, DH tables and screws are
:class:`~redik.kinematics.robot.loader.RobotLoading`'s.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import InvalidConfiguration, InvalidInput, ModelError, UnknownFrame
from redik.core.validate import MAX_COORDINATE, real_array
from redik.kinematics.robot.coordinates import JointCoordinates
from redik.kinematics.robot.frames import (
    Frame,
    frame_body,
    frame_names,
    leaf_bodies,
    resolve_frame,
)
from redik.kinematics.robot.loader import RobotLoading
from redik.kinematics.robot.selection import (
    BALL,
    chain_joints,
    joint_name,
    literal,
    match_joints,
    selected_joints,
)
from redik.kinematics.robot.state import RobotState
from redik.lie import periodic_coordinates, world_jacobian_to

JACOBIAN_REFERENCES = ("space", "body", "world")
"""The references a Jacobian can be expressed in (:mod:`redik.core.conventions`)."""

NATURAL_FRAME = "ee"
"""The site by which a model names its end-effector: every bundled scene and every model
redik's builders write has one. A robot of such a model is the chain to it unless told
otherwise; a model without one loads whole, with no frame named."""

_LISTED_FRAMES = 40  # per kind in a message, so that a humanoid's stays readable


class Robot(RobotLoading):
    """The joints of a MuJoCo model that redik moves: a serial chain, or any set of joints.

    See the module docstring for the two kinds and for ``q`` versus the tangent space.

    Args:
        model: The MuJoCo model.
        ee: The robot's end-effector: a site, body or geom name, the frame solvers and tasks
            use when they are given none. Default the site named :data:`NATURAL_FRAME`
            (``"ee"``) when the model has one, else none: frames are then named where they
            are used (``FrameTask(frame, …)``, ``solve_pose(…, frame=…)``, ``robot.chain(frame)``).
        name: A label for printing; default the model's name.
        joints: What moves. None: the chain from the root to ``ee`` when there is an
            end-effector, else every joint (a whole model, as :func:`redik.load` gives for a
            third-party file). ``"all"``: every hinge, slide, ball and free joint. Or joint
            names and ``fnmatch`` patterns (``"left/*"``) selecting a subset, kept in model
            order.
        fixed: Joint names or patterns never moved (``["*finger*"]``); they keep their
            value in ``data.qpos``. On a chain, a ball joint on the path must be fixed.

    Attributes:
        model: The :class:`mujoco.MjModel`.
        state: The robot's kinematic state (:class:`~redik.kinematics.robot.state.RobotState`,
            which ``fk``/``jacobian`` write); ``state.data.qpos`` holds the values of the
            joints the robot does not move.
        ee: The end-effector :class:`Frame`, or None when the model names none.
        is_chain: True for a serial chain to ``ee`` (the fast paths need one).
        dof: Tangent dimension ``n``: entries of ``Δq`` and Jacobian columns.
        nq: Entries of ``q`` (``dof`` plus one per ball joint and free joint).
        flat: True when ``nq == dof`` (no ball or free joint): ``q ⊕ Δq = q + Δq``.
        joint_names: The moved joints, root first (a chain) or in model order.
        joint_types: Their MuJoCo types, ``"hinge"``, ``"slide"``, ``"ball"``, ``"free"``.
        dof_names: One name per tangent coordinate (``"base:wx"`` for a free joint's).
        dof_joints: The joint of each tangent coordinate.
        lower, upper: Joint limits per tangent coordinate (``±inf`` where a joint has no
            range, and on ball and free joints).
        revolute: Per tangent coordinate, True for rotations (hinge, ball, a free joint's
            angular part).
        home: The ``home`` keyframe's values (else ``qpos0``), clipped into the limits.

    Threads: see :mod:`redik.kinematics.robot.state`.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        ee: str | None = None,
        *,
        name: str | None = None,
        joints: str | Sequence[str] | None = None,
        fixed: Sequence[str] | None = None,
    ):
        self.model = model
        self.name = name or _model_name(model)
        self._frames: dict[str, Frame] = {}
        fixed_ids = set(match_joints(model, fixed or (), "fixed", self.name))
        if ee is None and mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, NATURAL_FRAME) >= 0:
            ee = NATURAL_FRAME
        self.ee = None if ee is None else self.frame(ee)
        self.is_chain = joints is None and self.ee is not None
        if self.ee is not None and self.is_chain:
            joint_ids = chain_joints(model, frame_body(model, self.ee), fixed_ids, self.name)
            if not joint_ids:
                raise ModelError(
                    f"no hinge or slide joint between the root and end-effector "
                    f"{self.ee.name!r} in model {self.name!r}"
                )
        else:
            joint_ids = selected_joints(
                model, "all" if joints is None else joints, fixed, fixed_ids, self.name
            )
        coordinates = JointCoordinates.of(model, joint_ids)
        self._joint_ids = coordinates.joint_ids
        self.joint_names = coordinates.joint_names
        self.joint_types = coordinates.joint_types
        self._qpos_adr = coordinates.qpos_adr
        self._dof_adr = coordinates.dof_adr
        self.dof = len(self._dof_adr)
        self.nq = len(self._qpos_adr)
        self.flat = self.nq == self.dof
        self.dof_names = coordinates.dof_names
        self.dof_joints = coordinates.dof_joints
        self.revolute = coordinates.revolute
        self.lower = coordinates.lower
        self.upper = coordinates.upper
        # Hinge and slide entries: their tangent coordinate and their index in q.
        self._scalar_dofs = coordinates.scalar_dofs
        self._scalar_q = coordinates.scalar_q
        # Where a ball or free joint's quaternion, and a free joint's position, start in q.
        self._quaternion_q = coordinates.quaternion_q
        self._free_q = coordinates.free_q

        key = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_KEY, "home")
        qpos = model.key_qpos[key] if key >= 0 else model.qpos0
        self.home = self.clip(qpos[self._qpos_adr])
        self.home.setflags(write=False)
        self.state = RobotState(model, self._qpos_adr, self._dof_adr, qpos)
        # Scratch of integrate/difference on manifold joints (full qpos and qvel).
        self._qpos_a = np.zeros(model.nq)
        self._qpos_b = np.zeros(model.nq)
        self._qvel = np.zeros(model.nv)

    # ----------------------------------------------------------------------------------
    # Frames

    def frame(self, name: str | Frame | None = None) -> Frame:
        """Resolve a frame name.

        Args:
            name: A site, body or geom name (looked up in that order; ``"geom:name"``,
                ``"body:"`` or ``"site:"`` picks the kind when names collide), a resolved
                :class:`Frame`, or None for the end-effector.

        Returns:
            The frame.

        Raises:
            UnknownFrame: No such frame (the message lists the closest names); or None was
                given and the robot has no end-effector (the message lists the frames its
                joints move, :meth:`suggested_frames`).
        """
        if name is None:
            if self.ee is None:
                raise UnknownFrame(self._no_end_effector())
            return self.ee
        if isinstance(name, Frame):
            return name
        if not isinstance(name, str):
            raise UnknownFrame(f"a frame is named by a string, got {name!r}")
        cached = self._frames.get(name)
        if cached is None:
            cached = self._frames[name] = resolve_frame(self.model, name, f"model {self.name!r}")
        return cached

    def frame_names(self, kind: str = "site") -> list[str]:
        """Names of the model's sites, bodies or geoms (``kind`` = "site", "body", "geom")."""
        return frame_names(self.model, kind)

    def suggested_frames(self) -> list[str]:
        """The frames a user would pick for a task or a chain.

        Returns:
            The model's sites, then its leaf bodies (those no body hangs from: hands, feet,
            flanges; ``"body:name"`` where a site has the same name), each of them moved by
            some joint of the robot, in model order.
        """
        sites = self.frame_names("site")
        taken = set(sites)
        bodies = [f"body:{b}" if b in taken else b for b in leaf_bodies(self.model)]
        return [name for name in (*sites, *bodies) if self.moves(name)]

    def _no_end_effector(self) -> str:
        suggested = self.suggested_frames()
        sites = set(self.frame_names("site"))
        listed = []
        for kind, names in (
            ("sites", [n for n in suggested if n in sites]),
            ("leaf bodies", [n for n in suggested if n not in sites]),
        ):
            more = len(names) - _LISTED_FRAMES
            listed.append(
                f"{kind} {names[:_LISTED_FRAMES]}" + (f" and {more} more" if more > 0 else "")
            )
        return (
            f"{self.name!r} names no end-effector (no site {NATURAL_FRAME!r}), so the frame "
            f"must be named where it is used (frame=…, FrameTask(frame, …), "
            f"robot.chain(frame), ee=…); the frames its joints move: {'; '.join(listed)}"
        )

    def body_of(self, frame: str | Frame) -> int:
        """Id of the body ``frame`` is attached to (itself for a body)."""
        return frame_body(self.model, self.frame(frame))

    def moves(self, frame: str | Frame) -> bool:
        """True when some joint of the robot moves ``frame``."""
        body = frame_body(self.model, self.frame(frame))
        moved = set(self._joint_ids.tolist())
        while body > 0:
            start, count = self.model.body_jntadr[body], self.model.body_jntnum[body]
            if moved.intersection(range(start, start + count)):
                return True
            body = int(self.model.body_parentid[body])
        return False

    # ----------------------------------------------------------------------------------
    # Chains of a whole model

    def chain(
        self,
        frame: str | Frame | None = None,
        q: NDArray[np.float64] | None = None,
        *,
        name: str | None = None,
    ) -> Robot:
        """The serial chain from the root to a frame, the other joints held.

        The chain moves this robot's hinge and slide joints on the path to ``frame``; every
        other joint (the other arm, the fingers, a floating base, and ball joints on the path,
        which the fast paths cannot move) is held at its value in ``q``. The chain shares the
        model and runs every serial-chain method (compiled DLS, batch, closed forms,
        self-motion); :meth:`embed` writes its solution back into a ``q`` of this robot.

        Args:
            frame: The chain's end-effector; default this robot's.
            q: This robot's configuration, at which the other joints are held; default the
                values in its state's ``data.qpos``.
            name: A label; default ``"<robot>:<frame>"``.

        Returns:
            The chain, a :class:`Robot` whose ``ee`` is ``frame``.

        Raises:
            UnknownFrame: No such frame, or none given and this robot has no end-effector
                (the message lists :meth:`suggested_frames`).
            ModelError: No hinge or slide joint of this robot moves ``frame``.
        """
        resolved = self.frame(frame)
        moved = set(self._joint_ids.tolist())
        fixed = [
            literal(joint_name(self.model, j))
            for j in range(self.model.njnt)
            if j not in moved or int(self.model.jnt_type[j]) == BALL
        ]
        chain = Robot(self.model, resolved.name, name=name or f"{self.name}:{resolved.name}",
                      joints=None, fixed=fixed)  # fmt: skip
        qpos = self.state.data.qpos.copy() if q is None else self.full_qpos(self.check_q(q))
        chain.state.data.qpos[:] = qpos
        return chain

    def embed(
        self, chain: Robot, q_chain: NDArray[np.float64], q: NDArray[np.float64] | None = None
    ) -> NDArray[np.float64]:
        """Write a chain's solution back into a configuration of this robot.

        Args:
            chain: A chain of this robot (:meth:`chain`).
            q_chain: The chain's configuration.
            q: This robot's configuration to write into; default the values the chain holds
                (those it was cut at).

        Returns:
            This robot's ``q`` with the joints of ``chain`` set to ``q_chain``.

        Raises:
            InvalidInput: ``chain`` is of another model, or moves joints this robot does not.
            InvalidConfiguration: A configuration of the wrong length or not finite.
        """
        if chain.model is not self.model:
            raise InvalidInput(f"{chain!r} is not a chain of {self!r}'s model")
        outside = sorted(set(chain.joint_names) - set(self.joint_names))
        if outside:
            raise InvalidInput(
                f"{chain!r} moves joints {outside} that {self!r} does not: their values "
                "would be lost"
            )
        qpos = chain.state.data.qpos.copy() if q is None else self.full_qpos(self.check_q(q))
        qpos[chain.qpos_indices] = chain.check_q(q_chain, "q_chain")
        return qpos[self._qpos_adr]

    # ----------------------------------------------------------------------------------
    # Joint vectors

    def check_q(self, q: NDArray[np.float64], name: str = "q") -> NDArray[np.float64]:
        """Check a configuration of this robot.

        Args:
            q: The configuration as given.
            name: Its name, for the message.

        Returns:
            ``q`` as a float vector of length ``nq``.

        Raises:
            InvalidConfiguration: Not a finite real vector of length ``nq`` within
                ``±``:data:`~redik.core.validate.MAX_COORDINATE` (complex, string and object
                arrays are refused, not cast), or a zero quaternion of a ball or free joint.
        """
        q = real_array(q, name, InvalidConfiguration)
        if q.shape != (self.nq,):
            what = f"joints {list(self.joint_names)}"
            if not self.flat:
                what += f" of types {list(self.joint_types)}; nq = {self.nq}, dof = {self.dof}"
            raise InvalidConfiguration(
                f"{name} must have shape ({self.nq},) for {self.name} ({what}), got shape {q.shape}"
            )
        if not np.all(np.isfinite(q)):
            raise InvalidConfiguration(f"{name} holds NaN or inf: {q.tolist()}")
        if np.any(np.abs(q) > MAX_COORDINATE):
            raise InvalidConfiguration(
                f"{name} holds values beyond ±{MAX_COORDINATE:g} (MuJoCo's mjMAXVAL): {q.tolist()}"
            )
        if not self.flat:
            for start in self._quaternion_q:
                if np.linalg.norm(q[start : start + 4]) < 1e-9:
                    raise InvalidConfiguration(
                        f"{name}[{start}:{start + 4}] is a zero quaternion (a ball or free "
                        "joint's orientation must be a unit quaternion (w, x, y, z))"
                    )
        return q

    def scalar_values(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Per tangent coordinate: the hinge and slide values of ``q``, 0 on ball/free dofs.

        What a joint position limit (per tangent coordinate) compares with; ``q`` itself
        (not a copy) on a flat robot.
        """
        if self.flat:
            return q
        values = np.zeros(self.dof)
        values[self._scalar_dofs] = q[self._scalar_q]
        return values

    def with_scalar_values(
        self, q: NDArray[np.float64], values: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """A copy of ``q`` whose hinge and slide entries are taken from ``values`` (``dof``,).

        The inverse of :meth:`scalar_values` on those joints; ball and free joints keep
        their values in ``q``.
        """
        if self.flat:
            return np.array(values, dtype=float)
        q = np.array(q, dtype=float)
        q[self._scalar_q] = values[self._scalar_dofs]
        return q

    def within_limits(self, q: NDArray[np.float64], tol: float = 0.0) -> bool:
        """Whether a configuration is inside the joint limits.

        Args:
            q: A configuration (unchecked).
            tol: How far outside a limit still counts as inside.

        Returns:
            True when ``lower − tol ≤ q ≤ upper + tol`` for every hinge and slide joint.
        """
        values = self.scalar_values(q)
        return bool(np.all(values >= self.lower - tol) and np.all(values <= self.upper + tol))

    def clip(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Clip a configuration into the joint limits.

        Args:
            q: A configuration (unchecked).

        Returns:
            A copy with each hinge and slide value clipped to ``[lower, upper]`` and each
            quaternion normalised.
        """
        if self.flat:
            return np.clip(q, self.lower, self.upper)
        q = np.array(q, dtype=float)
        index = self._scalar_q
        q[index] = np.clip(q[index], self.lower[self._scalar_dofs], self.upper[self._scalar_dofs])
        for start in self._quaternion_q:
            q[start : start + 4] /= np.linalg.norm(q[start : start + 4])
        return q

    def integrate(self, q: NDArray[np.float64], dq: NDArray[np.float64]) -> NDArray[np.float64]:
        """The configuration reached by a tangent step: ``q ⊕ Δq``.

        ``q + dq`` on a flat robot, else ``mj_integratePos`` (the exponential map of each
        ball and free joint; see the module docstring).

        Args:
            q: A configuration (``nq``,), unchecked.
            dq: A tangent step (``dof``,), unchecked.

        Returns:
            ``q ⊕ dq`` (``nq``,).
        """
        if self.flat:
            return q + dq
        qpos, qvel = self._qpos_a, self._qvel
        qpos[self._qpos_adr] = q
        qvel.fill(0.0)
        qvel[self._dof_adr] = dq
        mujoco.mj_integratePos(self.model, qpos, qvel, 1.0)
        return qpos[self._qpos_adr]

    def difference(
        self, q_from: NDArray[np.float64], q_to: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """The tangent step between two configurations: ``q_to ⊖ q_from``.

        ``q_to − q_from`` on a flat robot, else ``mj_differentiatePos``; the inverse of
        :meth:`integrate`: ``integrate(a, difference(a, b)) = b``.

        Args:
            q_from: A configuration (``nq``,), unchecked.
            q_to: A configuration (``nq``,), unchecked.

        Returns:
            The step (``dof``,).
        """
        if self.flat:
            return q_to - q_from
        self._qpos_a[self._qpos_adr] = q_from
        self._qpos_b[self._qpos_adr] = q_to
        mujoco.mj_differentiatePos(self.model, self._qvel, 1.0, self._qpos_a, self._qpos_b)
        step: NDArray[np.float64] = self._qvel[self._dof_adr]
        return step.copy()

    @property
    def sampling_lower(self) -> NDArray[np.float64]:
        """Lower bound used for random sampling: the limit, or −π (or −1 m) where unlimited."""
        return np.where(np.isfinite(self.lower), self.lower, np.where(self.revolute, -np.pi, -1.0))

    @property
    def sampling_upper(self) -> NDArray[np.float64]:
        """Upper bound used for random sampling: the limit, or π (or 1 m) where unlimited."""
        return np.where(np.isfinite(self.upper), self.upper, np.where(self.revolute, np.pi, 1.0))

    @property
    def periodic(self) -> NDArray[np.bool_]:
        """Per tangent coordinate, True for the rotations taken modulo 2π.

        Those whose range spans a full turn (:func:`redik.lie.periodic_coordinates`,
        :mod:`redik.core.conventions`).
        """
        return periodic_coordinates(self.revolute, self.lower, self.upper)

    def random_q(
        self, rng: np.random.Generator | int | None = None, size: int | None = None
    ) -> NDArray[np.float64]:
        """Draw configurations uniformly within the sampling bounds.

        Hinges and slides uniformly in ``[sampling_lower, sampling_upper]``; ball and free
        joints a uniformly random orientation (a normalised Gaussian quaternion; Shoemake,
        *Uniform random rotations*, Graphics Gems III, 1992), a free joint a position within
        ±1 m of its home position.

        Args:
            rng: A generator, or a seed for one.
            size: How many; None for one.

        Returns:
            One configuration (``nq``,), or ``size`` × ``nq``.
        """
        rng = np.random.default_rng(rng)
        shape = (self.dof,) if size is None else (size, self.dof)
        tangent = rng.uniform(self.sampling_lower, self.sampling_upper, size=shape)
        if self.flat:
            return tangent
        rows = np.atleast_2d(tangent)
        out = np.tile(self.home, (rows.shape[0], 1))
        out[:, self._scalar_q] = rows[:, self._scalar_dofs]
        for start in self._free_q:
            out[:, start : start + 3] += rng.uniform(-1.0, 1.0, (rows.shape[0], 3))
        for start in self._quaternion_q:
            quat = rng.normal(size=(rows.shape[0], 4))
            out[:, start : start + 4] = quat / np.linalg.norm(quat, axis=1, keepdims=True)
        return out[0] if size is None else out

    @property
    def midrange(self) -> NDArray[np.float64]:
        """The middle of each joint's sampling range (``home`` on ball and free joints)."""
        return self.with_scalar_values(self.home, 0.5 * (self.sampling_lower + self.sampling_upper))

    # ----------------------------------------------------------------------------------
    # Kinematics, checked

    def fk(self, q: NDArray[np.float64], frame: str | Frame | None = None) -> NDArray[np.float64]:
        """Forward kinematics: the pose ``T_wf`` of a frame in the world.

        Args:
            q: A configuration (``nq``,).
            frame: A frame name or :class:`Frame`; default the end-effector.

        Returns:
            ``T_wf`` (4, 4), a fresh array.

        Raises:
            InvalidConfiguration: A bad ``q`` (:meth:`check_q`).
            UnknownFrame: No such frame, or none given and the robot has no end-effector.
        """
        q = self.check_q(q)
        resolved = self.frame(frame)
        self.state.update(q)
        return self.state.pose_into(resolved, np.eye(4))

    def jacobian(
        self, q: NDArray[np.float64], frame: str | Frame | None = None, reference: str = "space"
    ) -> NDArray[np.float64]:
        """The Jacobian of a frame, ``ξ = J q̇`` with ``ξ = (v, ω)``.

        Args:
            q: A configuration (``nq``,).
            frame: A frame name or :class:`Frame`; default the end-effector.
            reference: ``"space"`` (spatial twist, Modern Robotics §5.1.1), ``"body"`` (body
                twist, §5.1.2) or ``"world"`` (origin velocity and angular velocity in world
                axes, MuJoCo's); see :mod:`redik.core.conventions`.

        Returns:
            ``J`` (6, ``dof``), a fresh array.

        Raises:
            InvalidConfiguration: A bad ``q`` (:meth:`check_q`).
            UnknownFrame: No such frame, or none given and the robot has no end-effector.
            InvalidInput: An unknown ``reference``.
        """
        q = self.check_q(q)
        resolved = self.frame(frame)
        if reference not in JACOBIAN_REFERENCES:
            raise InvalidInput(f"reference must be one of {JACOBIAN_REFERENCES}, got {reference!r}")
        self.state.update(q)
        J = self.state.world_jacobian_into(resolved, np.empty((6, self.dof)))
        R, p = self.state.pose_views(resolved)
        return world_jacobian_to(reference, J, R, p, out=J)

    @property
    def qpos_indices(self) -> NDArray[np.intp]:
        """Indices of ``q``'s entries in ``model.qpos`` (for embedding ``q`` into a full qpos)."""
        return self._qpos_adr

    @property
    def dof_indices(self) -> NDArray[np.intp]:
        """Indices of the tangent coordinates in the model's velocity space (Jacobian columns)."""
        return self._dof_adr

    @property
    def joint_ids(self) -> NDArray[np.intp]:
        """MuJoCo ids of the moved joints."""
        return self._joint_ids

    def q_of(self, qpos: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
        """Read this robot's ``q`` from a full ``qpos``.

        Args:
            qpos: The model's ``qpos`` (``model.nq``,); default the state's ``data.qpos``: the
                last forward kinematics' configuration or, for a fresh chain of
                :meth:`chain`, the values it was cut at.

        Returns:
            A copy of the robot's entries.

        Raises:
            InvalidConfiguration: ``qpos`` is not a real vector of length ``model.nq``.
        """
        if qpos is None:
            qpos = self.state.data.qpos
        qpos = real_array(qpos, "qpos", InvalidConfiguration)
        if qpos.shape != (self.model.nq,):
            raise InvalidConfiguration(
                f"qpos must have shape ({self.model.nq},) (model.nq), got {qpos.shape}"
            )
        values: NDArray[np.float64] = qpos[self._qpos_adr]
        return values.copy()

    def full_qpos(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """The model's full ``qpos`` with the robot's joints set to ``q``, the rest as held."""
        qpos: NDArray[np.float64] = self.state.data.qpos.copy()
        qpos[self._qpos_adr] = q
        return qpos

    def __repr__(self) -> str:
        ee = self.ee.name if self.ee is not None else None
        if self.is_chain:
            return f"Robot({self.name!r}, dof={self.dof}, ee={ee!r})"
        return (
            f"Robot({self.name!r}, joints={len(self.joint_names)}, nq={self.nq}, "
            f"dof={self.dof}, ee={ee!r})"
        )


def _model_name(model: mujoco.MjModel) -> str:
    # MuJoCo stores the model's own name first in its names buffer.
    return bytes(model.names).split(b"\0", 1)[0].decode() or "robot"
