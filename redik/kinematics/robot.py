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
Jacobian column, a limit bound, a weight live in the tangent space (``robot.dof`` values,
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

import dataclasses
import fnmatch
import os
from collections.abc import Sequence
from pathlib import Path

import mujoco
import numpy as np

from redik.core.exceptions import InvalidConfiguration, InvalidInput, ModelError, UnknownFrame
from redik.lie import MAX_COORDINATE, periodic_coordinates, real_array, world_jacobian_to
from redik.models import loading, scenes

JACOBIAN_REFERENCES = ("space", "body", "world")
FRAME_KINDS = ("site", "body", "geom")

_FREE, _BALL, _SLIDE, _HINGE = (
    int(mujoco.mjtJoint.mjJNT_FREE),
    int(mujoco.mjtJoint.mjJNT_BALL),
    int(mujoco.mjtJoint.mjJNT_SLIDE),
    int(mujoco.mjtJoint.mjJNT_HINGE),
)
_CHAIN_JOINT_TYPES = (_HINGE, _SLIDE)
_JOINT_NQ = {_FREE: 7, _BALL: 4, _SLIDE: 1, _HINGE: 1}
_JOINT_NV = {_FREE: 6, _BALL: 3, _SLIDE: 1, _HINGE: 1}
_JOINT_TYPE_NAMES = {_FREE: "free", _BALL: "ball", _SLIDE: "slide", _HINGE: "hinge"}


@dataclasses.dataclass(frozen=True)
class Frame:
    """A resolved frame: a site, a body or a geom of the model, by id."""

    name: str
    kind: str  # "site", "body" or "geom"
    id: int


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
            with the robot. Like :attr:`data`, it makes a robot unsafe to share between
            threads.
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
        fixed_ids = set(_match_joints(model, fixed or (), "fixed", self.name))
        self.is_chain = joints is None
        if self.is_chain:
            self.ee = self.frame(ee if ee is not None else "ee")
            joint_ids = _chain_joints(model, self._body_of(self.ee), fixed_ids, self.name)
            if not joint_ids:
                raise ModelError(
                    f"no hinge or slide joint between the root and end-effector "
                    f"{self.ee.name!r} in model {self.name!r}"
                )
        else:
            self.ee = None
            if ee is not None:
                self.ee = self.frame(ee)
            elif _has_name(model, mujoco.mjtObj.mjOBJ_SITE, "ee"):
                self.ee = self.frame("ee")
            selected = (
                range(model.njnt)
                if isinstance(joints, str) and joints == "all"
                else _match_joints(model, [joints] if isinstance(joints, str) else joints,
                                   "joints", self.name)
            )  # fmt: skip
            named_both = sorted(_exact_names(joints) & _exact_names(fixed))
            if named_both:
                raise InvalidInput(
                    f"joints {named_both} are named both in joints= (to move) and in fixed= "
                    "(to hold); name each in one of them"
                )
            joint_ids = sorted(set(selected) - fixed_ids)
            if not joint_ids:
                raise ModelError(
                    f"no joint left to move in model {self.name!r} (joints={joints!r}, "
                    f"fixed={fixed!r})"
                )
        self._joint_ids = np.array(joint_ids, dtype=int)
        self.joint_names = tuple(_joint_name(model, j) for j in joint_ids)
        types = [int(model.jnt_type[j]) for j in joint_ids]
        self.joint_types = tuple(_JOINT_TYPE_NAMES[t] for t in types)
        self._qpos_adr = np.concatenate(
            [
                model.jnt_qposadr[j] + np.arange(_JOINT_NQ[t])
                for j, t in zip(joint_ids, types, strict=True)
            ]
        ).astype(int)
        self._dof_adr = np.concatenate(
            [
                model.jnt_dofadr[j] + np.arange(_JOINT_NV[t])
                for j, t in zip(joint_ids, types, strict=True)
            ]
        ).astype(int)
        self.dof = len(self._dof_adr)
        self.nq = len(self._qpos_adr)
        self.flat = self.nq == self.dof
        dof_names, dof_joints, revolute, lower, upper = [], [], [], [], []
        scalar_dofs, scalar_q, quaternion_q, free_q = [], [], [], []
        q_offset = 0
        for j, t, joint_name in zip(joint_ids, types, self.joint_names, strict=True):
            if t == _FREE:
                free_q.append(q_offset)
            if t in (_FREE, _BALL):
                quaternion_q.append(q_offset + (3 if t == _FREE else 0))
            if t in _CHAIN_JOINT_TYPES:
                scalar_dofs.append(len(dof_names))
                scalar_q.append(q_offset)
                dof_names.append(joint_name)
                dof_joints.append(joint_name)
                revolute.append(t == _HINGE)
                limited = bool(model.jnt_limited[j])
                lower.append(model.jnt_range[j, 0] if limited else -np.inf)
                upper.append(model.jnt_range[j, 1] if limited else np.inf)
            else:
                axes = ("wx", "wy", "wz") if t == _BALL else ("x", "y", "z", "wx", "wy", "wz")
                dof_names.extend(f"{joint_name}:{axis}" for axis in axes)
                dof_joints.extend([joint_name] * len(axes))
                revolute.extend(axis.startswith("w") for axis in axes)
                lower.extend([-np.inf] * len(axes))
                upper.extend([np.inf] * len(axes))
            q_offset += _JOINT_NQ[t]
        self.dof_names = tuple(dof_names)
        self.dof_joints = tuple(dof_joints)
        self.revolute = np.array(revolute, dtype=bool)
        self.lower = np.array(lower, dtype=float)
        self.upper = np.array(upper, dtype=float)
        # Hinge and slide entries: their tangent coordinate and their index in q.
        self._scalar_dofs = np.array(scalar_dofs, dtype=int)
        self._scalar_q = np.array(scalar_q, dtype=int)
        # Where a ball or free joint's quaternion, and a free joint's position, start in q.
        self._quaternion_q = tuple(quaternion_q)
        self._free_q = tuple(free_q)
        for array in (self.lower, self.upper, self.revolute):
            array.setflags(write=False)

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
        self.solver_cache: dict[object, object] = {}

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
        if cached is not None:
            return cached
        prefix, _, rest = name.partition(":")
        kinds, bare = ((prefix,), rest) if rest and prefix in FRAME_KINDS else (FRAME_KINDS, name)
        for candidate in kinds:
            index = mujoco.mj_name2id(self.model, _FRAME_OBJECTS[candidate], bare)
            if index >= 0:
                resolved = Frame(name, candidate, index)
                break
        else:
            raise loading.unknown_frame(self.model, name, f"model {self.name!r}", kinds)
        self._frames[name] = resolved
        return resolved

    def frame_names(self, kind: str = "site") -> list[str]:
        """Names of the model's sites, bodies or geoms (``kind`` = "site", "body", "geom")."""
        if kind not in FRAME_KINDS:
            raise InvalidInput(f"kind must be one of {FRAME_KINDS}, got {kind!r}")
        count = {"site": self.model.nsite, "body": self.model.nbody, "geom": self.model.ngeom}
        names = (mujoco.mj_id2name(self.model, _FRAME_OBJECTS[kind], i) for i in range(count[kind]))
        return [n for n in names if n]

    def body_of(self, frame: str | Frame) -> int:
        """Id of the body ``frame`` is attached to (itself for a body)."""
        return self._body_of(self.frame(frame))

    def _body_of(self, frame: Frame) -> int:
        if frame.kind == "site":
            return int(self.model.site_bodyid[frame.id])
        if frame.kind == "geom":
            return int(self.model.geom_bodyid[frame.id])
        return frame.id

    def moves(self, frame: str | Frame) -> bool:
        """True when some joint of the robot moves ``frame``."""
        body = self._body_of(self.frame(frame))
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
            _literal(_joint_name(self.model, j))
            for j in range(self.model.njnt)
            if j not in moved or int(self.model.jnt_type[j]) == _BALL
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
        :data:`redik.lie.MAX_COORDINATE`, or raise :class:`InvalidConfiguration` naming the
        value (complex, string and object arrays are refused, not cast)."""
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
        jac = _JACOBIANS[frame.kind]
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


_FRAME_OBJECTS = {
    "site": mujoco.mjtObj.mjOBJ_SITE,
    "body": mujoco.mjtObj.mjOBJ_BODY,
    "geom": mujoco.mjtObj.mjOBJ_GEOM,
}
_JACOBIANS = {"site": mujoco.mj_jacSite, "body": mujoco.mj_jacBody, "geom": mujoco.mj_jacGeom}


def frame_pose_views(data: mujoco.MjData, frame: Frame) -> tuple[np.ndarray, np.ndarray]:
    """Views ``(R, p)`` of ``frame``'s world rotation and position inside ``data``."""
    if frame.kind == "site":
        return data.site_xmat[frame.id].reshape(3, 3), data.site_xpos[frame.id]
    if frame.kind == "geom":
        return data.geom_xmat[frame.id].reshape(3, 3), data.geom_xpos[frame.id]
    return data.xmat[frame.id].reshape(3, 3), data.xpos[frame.id]


def frame_jacobian(
    model: mujoco.MjModel, data: mujoco.MjData, frame: Frame, jacp: np.ndarray, jacr: np.ndarray
) -> None:
    """MuJoCo's world Jacobian of ``frame`` (``mj_jacSite``/``mj_jacBody``/``mj_jacGeom``)."""
    _JACOBIANS[frame.kind](model, data, jacp, jacr, frame.id)


def _has_name(model: mujoco.MjModel, obj: mujoco.mjtObj, name: str) -> bool:
    return mujoco.mj_name2id(model, obj, name) >= 0


def _joint_name(model: mujoco.MjModel, joint: int) -> str:
    return mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, joint) or f"joint{joint}"


def _literal(name: str) -> str:
    """An ``fnmatch`` pattern matching exactly ``name`` (``*``, ``?``, ``[`` escaped)."""
    return "".join(f"[{char}]" if char in "*?[" else char for char in name)


def _match_joints(
    model: mujoco.MjModel, patterns: Sequence[str], argument: str, robot_name: str
) -> list[int]:
    """Ids of the joints whose name equals or ``fnmatch``-es one of ``patterns``.

    Raises:
        ModelError: a pattern matches no joint (a typo would otherwise move, or fix,
            nothing).
    """
    if isinstance(patterns, str):
        patterns = [patterns]
    if not isinstance(patterns, (list, tuple, set, frozenset)):
        raise InvalidInput(
            f"{argument} must be 'all', a joint name or pattern, or a list of them; got "
            f"{patterns!r}"
        )
    names = [_joint_name(model, j) for j in range(model.njnt)]
    selected: list[int] = []
    for pattern in patterns:
        if not isinstance(pattern, str):
            raise InvalidInput(f"{argument} holds joint names or patterns, got {pattern!r}")
        hits = [j for j, name in enumerate(names) if fnmatch.fnmatchcase(name, pattern)]
        if not hits:
            raise ModelError(
                f"{argument}: no joint of model {robot_name!r} matches {pattern!r}; joints: {names}"
            )
        selected.extend(hits)
    return sorted(set(selected))


def _exact_names(patterns: str | Sequence[str] | None) -> set[str]:
    """The entries of a joints= or fixed= argument that are names, not patterns."""
    if patterns is None or patterns == "all":
        return set()
    if isinstance(patterns, str):
        patterns = [patterns]
    return {p for p in patterns if isinstance(p, str) and not any(c in p for c in "*?[")}


def _model_name(model: mujoco.MjModel) -> str:
    # MuJoCo stores the model's own name first in its names buffer.
    return bytes(model.names).split(b"\0", 1)[0].decode() or "robot"


def _as_slice(indices: np.ndarray) -> slice | np.ndarray:
    """``indices`` as a slice when they are consecutive, else unchanged."""
    if np.array_equal(indices, np.arange(indices[0], indices[0] + len(indices))):
        return slice(int(indices[0]), int(indices[0]) + len(indices))
    return indices


def _chain_joints(model: mujoco.MjModel, body: int, fixed: set[int], robot_name: str) -> list[int]:
    """Hinge and slide joints on the path from the world to ``body``, root first.

    A free joint on the path is the floating base: it stays where ``qpos`` puts it. A ball
    joint cannot be part of a serial chain of hinges and slides; it must be fixed
    explicitly (or the robot built with ``joints=``), never silently frozen.

    Raises:
        ModelError: an unfixed ball joint lies on the path.
    """
    joints: list[int] = []
    while body > 0:
        start, count = model.body_jntadr[body], model.body_jntnum[body]
        body_joints = []
        for j in range(start, start + count):
            if j in fixed:
                continue
            joint_type = int(model.jnt_type[j])
            if joint_type == _BALL:
                raise ModelError(
                    f"ball joint {_joint_name(model, j)!r} lies on the chain to body "
                    f"{mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, body)!r} of model "
                    f"{robot_name!r}: a serial chain moves hinges and slides only. Build a "
                    f"whole-model robot (joints='all') to move it, or pass "
                    f"fixed=[{_joint_name(model, j)!r}] to hold it"
                )
            if joint_type in _CHAIN_JOINT_TYPES:
                body_joints.append(j)
        joints[:0] = body_joints
        body = int(model.body_parentid[body])
    return joints


def load(name: str | os.PathLike[str], ee: str | None = None, **options) -> Robot:
    """Load a bundled scene by name (``redik.load("panda")``) or any MJCF/URDF file by path.

    ``name`` is anything :func:`redik.models.scenes.scene_path` accepts; ``options`` go to
    :func:`redik.models.loading.load_spec` (``meshes=False`` for kinematics only, ``visual``,
    ``package_paths``, ``floating_base``, ``keep_fixed_links``)::

        redik.load("example-robot-data:ur5", ee="tool0", meshes=False)

    Raises:
        InvalidInput: ``name`` is neither a string nor a path.
        ModelError: no such scene or file, or MuJoCo cannot compile it.
        UnknownFrame: ``ee`` names no site or body of the model.
    """
    return Robot.from_file(scenes.scene_path(name), ee=ee, **options)
