r"""The kinematic model: a MuJoCo model plus the joints redik may move.

Every robot in redik is a :class:`mujoco.MjModel`, however it was described (MJCF, URDF,
a Denavit–Hartenberg table, screw axes), so every feature works on every robot. Frames,
twist order and Jacobian references are those of :mod:`redik.core.conventions`.

**Two kinds of robot.** A *chain* (``Robot(model, ee)``, the default) moves the hinge and
slide joints on the path from the root to one end-effector; every other joint stays at its
value in ``data.qpos``. All of redik works on a chain, including the serial-chain fast
paths (compiled DLS, batch, closed forms, self-motion). A *whole-model* robot
(``Robot(model, joints="all")``, or a list of joint names and ``fnmatch`` patterns such as
``["left/*", "right/*"]`` with ``fixed=["*finger*"]``) moves any set of hinge, slide, ball
and free joints — two arms, a floating base — for the task/limit :class:`redik.Problem`;
:meth:`Robot.chain` cuts a chain out of it for the fast paths, the other joints fixed.

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

Forward kinematics runs ``mj_kinematics`` and ``mj_comPos`` (the latter fills the ``cdof``
that ``mj_jac*`` reads) on the robot's own ``MjData`` and reads the Jacobian with
``mj_jacSite``/``mj_jacBody`` into preallocated buffers. The public ``fk``/``jacobian`` check
their input and return fresh arrays; solvers use :meth:`Robot.kinematics`, which skips the
checks and writes into caller-owned buffers.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import mujoco
import numpy as np

from redik.core.exceptions import InvalidConfiguration, InvalidInput, ModelError, UnknownFrame
from redik.core.validate import MAX_COORDINATE, real_array
from redik.kinematics.robot.coordinates import JointCoordinates
from redik.kinematics.robot.frames import (
    FRAME_JACOBIANS,
    Frame,
    frame_body,
    frame_names,
    frame_pose_views,
    resolve_frame,
)
from redik.kinematics.robot.selection import (
    BALL,
    chain_joints,
    joint_name,
    literal,
    match_joints,
    selected_joints,
)
from redik.kinematics.robot.solver_cache import SolverCache
from redik.lie import periodic_coordinates, world_jacobian_to
from redik.models import loading

JACOBIAN_REFERENCES = ("space", "body", "world")
"""The references a Jacobian can be expressed in (:mod:`redik.core.conventions`)."""


class Robot:
    """The joints of a MuJoCo model that redik moves: a serial chain, or any set of joints.

    See the module docstring for the two kinds and for ``q`` versus the tangent space.

    Args:
        model: The MuJoCo model.
        ee: Name of the end-effector site, body or geom. For a chain (``joints=None``) it
            ends the chain; default the site named ``ee``. For a whole-model robot it is
            only the default frame of tasks (default ``ee`` when the model has it, else
            none: tasks must then name their frame).
        name: A label for printing; default the model's name.
        joints: None for the chain from the root to ``ee``; ``"all"`` for every hinge,
            slide, ball and free joint; or joint names and ``fnmatch`` patterns
            (``"left/*"``) selecting a subset, kept in model order.
        fixed: Joint names or patterns never moved (``["*finger*"]``); they keep their
            value in ``data.qpos``. On a chain, a ball joint on the path must be fixed.

    Attributes:
        model: The :class:`mujoco.MjModel`.
        data: The robot's own :class:`mujoco.MjData` (scratch space of ``fk``/``jacobian``);
            its ``qpos`` holds the values of the joints redik does not move.
        ee: The end-effector :class:`Frame` (None for a whole-model robot without one).
        is_chain: True for a serial chain (the fast paths need one).
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
        solver_cache: What solvers compile once per robot and frame (e.g. the chain of
            :func:`redik.solve_pose`'s ``"dls"`` kernel), kept here so it lives and dies
            with the robot; a :class:`~redik.kinematics.robot.solver_cache.SolverCache`,
            safe to share between threads.

    Threads: :attr:`data` is the scratch space of every forward kinematics, so one robot
    serves one thread at a time, except for what never touches :attr:`data` after the
    robot is built: :func:`redik.solve_pose` with ``method="dls"`` (the default) and
    ``respect_limits=True``, and :func:`redik.solvers.batch.solve_batch`. Other solvers need
    one :class:`Robot` per thread (build each from the same ``model``).
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
        self.data = mujoco.MjData(model)
        self.name = name or _model_name(model)
        self._frames: dict[str, Frame] = {}
        fixed_ids = set(match_joints(model, fixed or (), "fixed", self.name))
        self.is_chain = joints is None
        if self.is_chain:
            self.ee = self.frame(ee if ee is not None else "ee")
            joint_ids = chain_joints(model, frame_body(model, self.ee), fixed_ids, self.name)
            if not joint_ids:
                raise ModelError(
                    f"no hinge or slide joint between the root and end-effector "
                    f"{self.ee.name!r} in model {self.name!r}"
                )
        else:
            self.ee = None
            if ee is not None:
                self.ee = self.frame(ee)
            elif mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, "ee") >= 0:
                self.ee = self.frame("ee")
            joint_ids = selected_joints(model, joints, fixed, fixed_ids, self.name)
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
        if key >= 0:
            self.data.qpos[:] = model.key_qpos[key]
        else:
            self.data.qpos[:] = model.qpos0
        self.home = self.clip(self.data.qpos[self._qpos_adr])
        self.home.setflags(write=False)

        self._jacp = np.zeros((3, model.nv))
        self._jacr = np.zeros((3, model.nv))
        # Hot-path shortcuts: a slice instead of fancy indexing when the joints are
        # contiguous in qpos, and MuJoCo writing straight into the caller's J when they are
        # every dof.
        self._qpos_index = _as_slice(self._qpos_adr)
        self._jacobian_is_direct = model.nv == self.dof and np.array_equal(
            self._dof_adr, np.arange(self.dof)
        )
        self._views: dict[Frame, tuple[np.ndarray, np.ndarray]] = {}
        # Scratch of integrate/difference on manifold joints (full qpos and qvel).
        self._qpos_a = np.zeros(model.nq)
        self._qpos_b = np.zeros(model.nq)
        self._qvel = np.zeros(model.nv)
        self.solver_cache = SolverCache()

    # ----------------------------------------------------------------------------------
    # Construction

    @classmethod
    def from_file(
        cls,
        path: str | Path,
        ee: str | None = None,
        *,
        name: str | None = None,
        joints: str | Sequence[str] | None = None,
        fixed: Sequence[str] | None = None,
        **options,
    ) -> Robot:
        """Load an MJCF (``.xml``) or URDF (``.urdf``) file.

        ``joints`` and ``fixed`` choose what moves (the class docstring):
        ``Robot.from_file(path, joints="all", floating_base=True)`` is a whole humanoid.

        ``options`` go to :func:`redik.models.loading.load_spec`: ``meshes=False`` for a
        kinematics-only model, ``visual``, ``package_paths`` for ``package://`` meshes,
        ``floating_base``, ``keep_fixed_links``. Fixed URDF links stay bodies, so ``tool0`` or
        ``panda_hand`` can be the end-effector.

        Raises:
            ModelError: the file or a mesh is missing, or MuJoCo cannot compile the model.
        """
        model = loading.compile_spec(loading.load_spec(path, **options), str(path))
        return cls(model, ee=ee, name=name or Path(path).stem, joints=joints, fixed=fixed)

    @classmethod
    def from_xml_string(
        cls,
        xml: str,
        ee: str | None = None,
        name: str | None = None,
        *,
        joints: str | Sequence[str] | None = None,
        fixed: Sequence[str] | None = None,
        **options,
    ) -> Robot:
        """Build from an MJCF or URDF string (``options`` as for :func:`load_spec_from_string`;
        ``joints``, ``fixed`` as for the class).

        Raises:
            ModelError: MuJoCo cannot compile the string.
        """
        spec = loading.load_spec_from_string(xml, **options)
        model = loading.compile_spec(spec, "the model string")
        return cls(model, ee=ee, name=name, joints=joints, fixed=fixed)

    @classmethod
    def from_dh(
        cls,
        rows: Sequence,
        convention: str = "standard",
        limits: Sequence[Sequence[float]] | None = None,
        tool: np.ndarray | None = None,
        *,
        name: str = "dh_robot",
        home: Sequence[float] | None = None,
        **builder_options,
    ) -> Robot:
        """Build from a Denavit–Hartenberg table (see :func:`redik.models.dh.parse_rows`).

        ``convention`` is ``"standard"`` (Spong/Paul: ``Rz(θ) Tz(d) Tx(a) Rx(α)``) or
        ``"modified"`` (Craig: ``Rx(α) Tx(a) Rz(θ) Tz(d)``); ``limits`` is n × 2; ``tool`` a
        4 × 4 flange transform or a row. The generated MJCF places the ``ee`` site at the
        last frame, so ``robot.fk(q)`` equals the table's ``T_0n(q) · tool``.
        ``builder_options`` (``radius``, ``actuators``, ``custom``, …) go to
        :func:`redik.models.builder.dh_to_mjcf`.
        """
        from redik.models.builder import dh_to_mjcf

        xml = dh_to_mjcf(rows, convention, limits, tool, name=name, home=home, **builder_options)
        return cls.from_xml_string(xml, name=name)

    @classmethod
    def from_screws(
        cls,
        screws: np.ndarray,
        M: np.ndarray,
        frame: str = "space",
        limits: Sequence[Sequence[float]] | None = None,
        *,
        name: str = "poe_robot",
        home: Sequence[float] | None = None,
        **builder_options,
    ) -> Robot:
        """Build from a product of exponentials (Modern Robotics §4.1).

        ``screws`` is 6 × n with columns ``S_i = (ω_i, v_i)`` (Modern Robotics order) in the
        space frame, or body screws ``B_i`` when ``frame="body"``; ``M`` is the home pose of the
        end-effector. ``robot.fk(q) = e^{[S_1] q_1} ⋯ e^{[S_n] q_n} M``.
        ``builder_options`` go to :func:`redik.models.builder.screws_to_mjcf`.
        """
        from redik.models.builder import screws_to_mjcf

        xml = screws_to_mjcf(screws, M, frame, limits, name=name, home=home, **builder_options)
        return cls.from_xml_string(xml, name=name)

    # ----------------------------------------------------------------------------------
    # Frames

    def frame(self, name: str | Frame | None = None) -> Frame:
        """Resolve a site, body or geom name (in that order); ``None`` is the end-effector.

        ``"geom:name"`` (or ``"body:"``, ``"site:"``) picks the kind when names collide.
        """
        if name is None:
            if self.ee is None:
                raise UnknownFrame(
                    f"{self.name!r} has no end-effector (a whole-model robot): name the frame, "
                    f"e.g. one of the sites {self.frame_names('site')[:8]}"
                )
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
        self, frame: str | Frame, q: np.ndarray | None = None, *, name: str | None = None
    ) -> Robot:
        """The serial chain from the root to ``frame``, the other joints fixed.

        The chain moves this robot's hinge and slide joints on the path to ``frame``; every
        other joint (the other arm, the fingers, a floating base) is held at its value in
        ``q`` (this robot's configuration; default its current ``data.qpos``). The chain
        shares the model and runs every serial-chain method (compiled DLS, batch, closed
        forms, self-motion); :meth:`embed` writes its solution back into a ``q`` of this
        robot. Ball joints on the path are fixed too (the fast paths need hinges/slides).
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
        qpos = self.data.qpos.copy() if q is None else self.full_qpos(self.check_q(q))
        chain.data.qpos[:] = qpos
        return chain

    def embed(self, chain: Robot, q_chain: np.ndarray, q: np.ndarray | None = None) -> np.ndarray:
        """This robot's ``q`` with the joints of ``chain`` set to ``q_chain``.

        ``q`` defaults to the values held by the chain (those of :meth:`chain`).
        """
        if chain.model is not self.model:
            raise InvalidInput(f"{chain!r} is not a chain of {self!r}'s model")
        outside = sorted(set(chain.joint_names) - set(self.joint_names))
        if outside:
            raise InvalidInput(
                f"{chain!r} moves joints {outside} that {self!r} does not: their values "
                "would be lost"
            )
        qpos = chain.data.qpos.copy() if q is None else self.full_qpos(self.check_q(q))
        qpos[chain.qpos_indices] = chain.check_q(q_chain, "q_chain")
        return qpos[self._qpos_adr]

    # ----------------------------------------------------------------------------------
    # Joint vectors

    def check_q(self, q: np.ndarray, name: str = "q") -> np.ndarray:
        """``q`` as a finite real vector of length ``nq``, within ``±``
        :data:`~redik.core.validate.MAX_COORDINATE`, or raise :class:`InvalidConfiguration`
        naming the value (complex, string and object arrays are refused, not cast)."""
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

    def scalar_values(self, q: np.ndarray) -> np.ndarray:
        """Per tangent coordinate: the hinge and slide values of ``q``, 0 on ball/free dofs.

        What a joint position limit (per tangent coordinate) compares with; ``q`` itself
        (not a copy) on a flat robot.
        """
        if self.flat:
            return q
        values = np.zeros(self.dof)
        values[self._scalar_dofs] = q[self._scalar_q]
        return values

    def with_scalar_values(self, q: np.ndarray, values: np.ndarray) -> np.ndarray:
        """A copy of ``q`` whose hinge and slide entries are taken from ``values`` (``dof``,).

        The inverse of :meth:`scalar_values` on those joints; ball and free joints keep
        their values in ``q``.
        """
        if self.flat:
            return np.array(values, dtype=float)
        q = np.array(q, dtype=float)
        q[self._scalar_q] = values[self._scalar_dofs]
        return q

    def within_limits(self, q: np.ndarray, tol: float = 0.0) -> bool:
        """True when ``lower − tol ≤ q ≤ upper + tol`` for every hinge and slide joint."""
        values = self.scalar_values(q)
        return bool(np.all(values >= self.lower - tol) and np.all(values <= self.upper + tol))

    def clip(self, q: np.ndarray) -> np.ndarray:
        """``q`` clipped into the joint limits (quaternions normalised)."""
        if self.flat:
            return np.clip(q, self.lower, self.upper)
        q = np.array(q, dtype=float)
        index = self._scalar_q
        q[index] = np.clip(q[index], self.lower[self._scalar_dofs], self.upper[self._scalar_dofs])
        for start in self._quaternion_q:
            q[start : start + 4] /= np.linalg.norm(q[start : start + 4])
        return q

    def integrate(self, q: np.ndarray, dq: np.ndarray) -> np.ndarray:
        """``q ⊕ Δq``: the configuration reached by the tangent step ``dq`` (no checks).

        ``q + dq`` on a flat robot, else ``mj_integratePos`` (the exponential map of each
        ball and free joint; see the module docstring).
        """
        if self.flat:
            return q + dq
        qpos, qvel = self._qpos_a, self._qvel
        qpos[self._qpos_adr] = q
        qvel.fill(0.0)
        qvel[self._dof_adr] = dq
        mujoco.mj_integratePos(self.model, qpos, qvel, 1.0)
        return qpos[self._qpos_adr]

    def difference(self, q_from: np.ndarray, q_to: np.ndarray) -> np.ndarray:
        """``q_to ⊖ q_from`` (``dof``,): the tangent step from ``q_from`` to ``q_to``.

        ``q_to − q_from`` on a flat robot, else ``mj_differentiatePos``; the inverse of
        :meth:`integrate`: ``integrate(a, difference(a, b)) = b``.
        """
        if self.flat:
            return q_to - q_from
        self._qpos_a[self._qpos_adr] = q_from
        self._qpos_b[self._qpos_adr] = q_to
        mujoco.mj_differentiatePos(self.model, self._qvel, 1.0, self._qpos_a, self._qpos_b)
        return self._qvel[self._dof_adr].copy()

    @property
    def sampling_lower(self) -> np.ndarray:
        """Lower bound used for random sampling: the limit, or −π (or −1 m) where unlimited."""
        return np.where(np.isfinite(self.lower), self.lower, np.where(self.revolute, -np.pi, -1.0))

    @property
    def sampling_upper(self) -> np.ndarray:
        """Upper bound used for random sampling: the limit, or π (or 1 m) where unlimited."""
        return np.where(np.isfinite(self.upper), self.upper, np.where(self.revolute, np.pi, 1.0))

    @property
    def periodic(self) -> np.ndarray:
        """Per tangent coordinate, True for the rotations taken modulo 2π: those whose
        range spans a full turn (:func:`redik.lie.periodic_coordinates`,
        :mod:`redik.core.conventions`)."""
        return periodic_coordinates(self.revolute, self.lower, self.upper)

    def random_q(self, rng: np.random.Generator | int | None = None, size: int | None = None):
        """Configurations drawn uniformly within the sampling bounds (one, or ``size`` × nq).

        Ball and free joints get a uniformly random orientation (Shoemake 1992) and a free
        joint a position within ±1 m of its home position.
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
    def midrange(self) -> np.ndarray:
        """The middle of each joint's sampling range (``home`` on ball and free joints)."""
        return self.with_scalar_values(self.home, 0.5 * (self.sampling_lower + self.sampling_upper))

    # ----------------------------------------------------------------------------------
    # Kinematics, checked

    def fk(self, q: np.ndarray, frame: str | Frame | None = None) -> np.ndarray:
        """Pose ``T_wf`` (4 × 4) of ``frame`` (default the end-effector) at ``q``."""
        q = self.check_q(q)
        resolved = self.frame(frame)
        self.update(q)
        T = np.eye(4)
        R, p = self._pose_views(resolved)
        T[:3, :3] = R
        T[:3, 3] = p
        return T

    def jacobian(
        self, q: np.ndarray, frame: str | Frame | None = None, reference: str = "space"
    ) -> np.ndarray:
        """The 6 × n Jacobian of ``frame`` at ``q`` in the given reference.

        ``reference`` is ``"space"`` (spatial twist), ``"body"`` (body twist) or ``"world"``
        (origin velocity and angular velocity in world axes); see :mod:`redik.core.conventions`.
        """
        q = self.check_q(q)
        resolved = self.frame(frame)
        if reference not in JACOBIAN_REFERENCES:
            raise InvalidInput(f"reference must be one of {JACOBIAN_REFERENCES}, got {reference!r}")
        self.update(q)
        J = np.empty((6, self.dof))
        self.world_jacobian_into(resolved, J)
        R, p = self._pose_views(resolved)
        return world_jacobian_to(reference, J, R, p, out=J)

    # ----------------------------------------------------------------------------------
    # Kinematics, unchecked hot path (the caller validates once, outside its loop)

    def update(self, q: np.ndarray) -> None:
        """Write ``q`` into the model state and run forward kinematics (no checks)."""
        self.data.qpos[self._qpos_index] = q
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_comPos(self.model, self.data)

    def _pose_views(self, frame: Frame) -> tuple[np.ndarray, np.ndarray]:
        """Views of ``frame``'s rotation and position inside ``data`` (valid after update)."""
        views = self._views.get(frame)
        if views is None:
            views = self._views[frame] = frame_pose_views(self.data, frame)
        return views

    def pose_into(self, frame: Frame, T: np.ndarray) -> np.ndarray:
        """Copy the current pose of ``frame`` (after :meth:`update`) into the 4 × 4 ``T``."""
        R, p = self._pose_views(frame)
        T[:3, :3] = R
        T[:3, 3] = p
        return T

    def world_jacobian_into(self, frame: Frame, J: np.ndarray) -> np.ndarray:
        """Write the ``"world"`` Jacobian of ``frame`` (after :meth:`update`) into 6 × n ``J``."""
        jac = FRAME_JACOBIANS[frame.kind]
        if self._jacobian_is_direct and J.flags.c_contiguous:
            jac(self.model, self.data, J[:3], J[3:], frame.id)
            return J
        jac(self.model, self.data, self._jacp, self._jacr, frame.id)
        J[:3] = self._jacp[:, self._dof_adr]
        J[3:] = self._jacr[:, self._dof_adr]
        return J

    def kinematics(
        self, q: np.ndarray, frame: Frame, T: np.ndarray, J: np.ndarray | None = None
    ) -> None:
        """One FK (+ world Jacobian when ``J`` is given) into caller-owned buffers, no checks."""
        self.update(q)
        self.pose_into(frame, T)
        if J is not None:
            self.world_jacobian_into(frame, J)

    @property
    def qpos_indices(self) -> np.ndarray:
        """Indices of ``q``'s entries in ``model.qpos`` (for embedding ``q`` into a full qpos)."""
        return self._qpos_adr

    @property
    def dof_indices(self) -> np.ndarray:
        """Indices of the tangent coordinates in the model's velocity space (Jacobian columns)."""
        return self._dof_adr

    @property
    def joint_ids(self) -> np.ndarray:
        """MuJoCo ids of the moved joints."""
        return self._joint_ids

    def q_of(self, qpos: np.ndarray | None = None) -> np.ndarray:
        """This robot's ``q`` read from a full ``qpos``; default its own ``data.qpos``: the
        last forward kinematics' configuration or, for a fresh chain of :meth:`chain`, the
        values it was cut at."""
        qpos = self.data.qpos if qpos is None else real_array(qpos, "qpos", InvalidConfiguration)
        if qpos.shape != (self.model.nq,):
            raise InvalidConfiguration(
                f"qpos must have shape ({self.model.nq},) (model.nq), got {qpos.shape}"
            )
        return qpos[self._qpos_adr].copy()

    def full_qpos(self, q: np.ndarray) -> np.ndarray:
        """The model's full ``qpos`` with the robot's joints set to ``q``, the rest as held."""
        qpos = self.data.qpos.copy()
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


def _as_slice(indices: np.ndarray) -> slice | np.ndarray:
    """``indices`` as a slice when they are consecutive, else unchanged."""
    if np.array_equal(indices, np.arange(indices[0], indices[0] + len(indices))):
        return slice(int(indices[0]), int(indices[0]) + len(indices))
    return indices
