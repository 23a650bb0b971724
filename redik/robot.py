"""The kinematic model: a MuJoCo model plus the chain from its root to an end-effector.

Every robot in redik is a :class:`mujoco.MjModel`, however it was described (MJCF, URDF,
a Denavit–Hartenberg table, screw axes), so every feature works on every robot. Frames,
twist order and Jacobian references are those of :mod:`redik.conventions`.

Forward kinematics runs ``mj_kinematics`` and ``mj_comPos`` (the latter fills the ``cdof``
that ``mj_jac*`` reads) on the robot's own ``MjData`` and reads the Jacobian with
``mj_jacSite``/``mj_jacBody`` into preallocated buffers. The public ``fk``/``jacobian`` check
their input and return fresh arrays; solvers use :meth:`Robot.kinematics`, which skips the
checks and writes into caller-owned buffers.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from pathlib import Path

import mujoco
import numpy as np

from . import loading
from .exceptions import InvalidConfiguration, InvalidInput, ModelError, UnknownFrame
from .lie import skew

JACOBIAN_REFERENCES = ("space", "body", "world")

_CHAIN_JOINT_TYPES = (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))


@dataclasses.dataclass(frozen=True)
class Frame:
    """A resolved frame: a site or a body of the model, by id."""

    name: str
    kind: str  # "site" or "body"
    id: int


class Robot:
    """A serial chain of hinge and slide joints inside a MuJoCo model.

    Args:
        model: The MuJoCo model.
        ee: Name of the end-effector site or body. Default: the site named ``ee``.
        name: A label for printing; default the model's name.

    Attributes:
        model: The :class:`mujoco.MjModel`.
        data: The robot's own :class:`mujoco.MjData` (scratch space of ``fk``/``jacobian``).
        ee: The end-effector :class:`Frame`.
        dof: Number of chain joints ``n``.
        joint_names: Chain joints from the root to the end-effector.
        lower, upper: Joint limits (``±inf`` where a joint has no range).
        revolute: Boolean mask, True for hinge joints.
        home: The ``home`` keyframe's chain values (else ``qpos0``), clipped into the limits.
        solver_cache: What solvers compile once per robot and frame (e.g. the chain of
            :func:`redik.solve_pose`'s ``"dls"`` kernel), kept here so it lives and dies
            with the robot. Like :attr:`data`, it makes a robot unsafe to share between
            threads.
    """

    def __init__(self, model: mujoco.MjModel, ee: str | None = None, *, name: str | None = None):
        self.model = model
        self.data = mujoco.MjData(model)
        self.name = name or _model_name(model)
        self._frames: dict[str, Frame] = {}
        self.ee = self.frame(ee if ee is not None else "ee")

        joint_ids = _chain_joints(model, self._body_of(self.ee))
        if not joint_ids:
            raise ModelError(
                f"no hinge or slide joint between the root and end-effector {self.ee.name!r} "
                f"in model {self.name!r}"
            )
        self._joint_ids = np.array(joint_ids, dtype=int)
        self.joint_names = tuple(
            mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j) or f"joint{j}" for j in joint_ids
        )
        self.dof = len(joint_ids)
        self._qpos_adr = model.jnt_qposadr[self._joint_ids].copy()
        self._dof_adr = model.jnt_dofadr[self._joint_ids].copy()
        self.revolute = model.jnt_type[self._joint_ids] == int(mujoco.mjtJoint.mjJNT_HINGE)
        limited = model.jnt_limited[self._joint_ids].astype(bool)
        ranges = model.jnt_range[self._joint_ids]
        self.lower = np.where(limited, ranges[:, 0], -np.inf)
        self.upper = np.where(limited, ranges[:, 1], np.inf)
        for array in (self.lower, self.upper, self.revolute):
            array.setflags(write=False)

        key = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_KEY, "home")
        if key >= 0:
            self.data.qpos[:] = model.key_qpos[key]
        else:
            self.data.qpos[:] = model.qpos0
        self.home = np.clip(self.data.qpos[self._qpos_adr], self.lower, self.upper)
        self.home.setflags(write=False)

        self._jacp = np.zeros((3, model.nv))
        self._jacr = np.zeros((3, model.nv))
        # Hot-path shortcuts: a slice instead of fancy indexing when the chain is contiguous
        # in qpos, and MuJoCo writing straight into the caller's J when the chain is every dof.
        self._qpos_index = _as_slice(self._qpos_adr)
        self._jacobian_is_direct = model.nv == self.dof and np.array_equal(
            self._dof_adr, np.arange(self.dof)
        )
        self._views: dict[Frame, tuple[np.ndarray, np.ndarray]] = {}
        self.solver_cache: dict[object, object] = {}

    # ----------------------------------------------------------------------------------
    # Construction

    @classmethod
    def from_file(
        cls, path: str | Path, ee: str | None = None, *, name: str | None = None, **options
    ) -> Robot:
        """Load an MJCF (``.xml``) or URDF (``.urdf``) file.

        ``options`` go to :func:`redik.loading.load_spec`: ``meshes=False`` for a
        kinematics-only model, ``visual``, ``package_paths`` for ``package://`` meshes,
        ``floating_base``, ``keep_fixed_links``. Fixed URDF links stay bodies, so ``tool0`` or
        ``panda_hand`` can be the end-effector.

        Raises:
            ModelError: the file or a mesh is missing, or MuJoCo cannot compile the model.
        """
        model = loading.compile_spec(loading.load_spec(path, **options), str(path))
        return cls(model, ee=ee, name=name or Path(path).stem)

    @classmethod
    def from_xml_string(
        cls, xml: str, ee: str | None = None, name: str | None = None, **options
    ) -> Robot:
        """Build from an MJCF or URDF string (``options`` as for :func:`load_spec_from_string`).

        Raises:
            ModelError: MuJoCo cannot compile the string.
        """
        spec = loading.load_spec_from_string(xml, **options)
        return cls(loading.compile_spec(spec, "the model string"), ee=ee, name=name)

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
        """Build from a Denavit–Hartenberg table (see :func:`redik.dh.parse_rows`).

        ``convention`` is ``"standard"`` (Spong/Paul: ``Rz(θ) Tz(d) Tx(a) Rx(α)``) or
        ``"modified"`` (Craig: ``Rx(α) Tx(a) Rz(θ) Tz(d)``); ``limits`` is n × 2; ``tool`` a
        4 × 4 flange transform or a row. The generated MJCF places the ``ee`` site at the
        last frame, so ``robot.fk(q)`` equals the table's ``T_0n(q) · tool``.
        ``builder_options`` (``radius``, ``actuators``, ``custom``, …) go to
        :func:`redik.model_builder.dh_to_mjcf`.
        """
        from .model_builder import dh_to_mjcf

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
        ``builder_options`` go to :func:`redik.model_builder.screws_to_mjcf`.
        """
        from .model_builder import screws_to_mjcf

        xml = screws_to_mjcf(screws, M, frame, limits, name=name, home=home, **builder_options)
        return cls.from_xml_string(xml, name=name)

    # ----------------------------------------------------------------------------------
    # Frames

    def frame(self, name: str | Frame | None = None) -> Frame:
        """Resolve a site or body name (sites first); ``None`` is the end-effector."""
        if name is None:
            return self.ee
        if isinstance(name, Frame):
            return name
        cached = self._frames.get(name)
        if cached is not None:
            return cached
        if not isinstance(name, str):
            raise UnknownFrame(f"a frame is named by a string, got {name!r}")
        site = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_SITE, name)
        body = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, name)
        if site >= 0:
            resolved = Frame(name, "site", site)
        elif body >= 0:
            resolved = Frame(name, "body", body)
        else:
            raise loading.unknown_frame(self.model, name, f"model {self.name!r}", ("site", "body"))
        self._frames[name] = resolved
        return resolved

    def frame_names(self, kind: str = "site") -> list[str]:
        """Names of the model's sites (``kind="site"``) or bodies (``kind="body"``)."""
        obj, count = (
            (mujoco.mjtObj.mjOBJ_SITE, self.model.nsite)
            if kind == "site"
            else (mujoco.mjtObj.mjOBJ_BODY, self.model.nbody)
        )
        names = (mujoco.mj_id2name(self.model, obj, i) for i in range(count))
        return [n for n in names if n]

    def _body_of(self, frame: Frame) -> int:
        return int(self.model.site_bodyid[frame.id]) if frame.kind == "site" else frame.id

    # ----------------------------------------------------------------------------------
    # Joint vectors

    def check_q(self, q: np.ndarray, name: str = "q") -> np.ndarray:
        """``q`` as a float vector of length ``dof``, or raise :class:`InvalidConfiguration`."""
        q = np.asarray(q, dtype=float)
        if q.shape != (self.dof,):
            raise InvalidConfiguration(
                f"{name} must have shape ({self.dof},) for {self.name} "
                f"(joints {list(self.joint_names)}), got shape {q.shape}"
            )
        if not np.all(np.isfinite(q)):
            raise InvalidConfiguration(f"{name} holds NaN or inf: {q.tolist()}")
        return q

    def within_limits(self, q: np.ndarray, tol: float = 0.0) -> bool:
        """True when ``lower − tol ≤ q ≤ upper + tol`` for every joint."""
        return bool(np.all(q >= self.lower - tol) and np.all(q <= self.upper + tol))

    def clip(self, q: np.ndarray) -> np.ndarray:
        """``q`` clipped into the joint limits."""
        return np.clip(q, self.lower, self.upper)

    @property
    def sampling_lower(self) -> np.ndarray:
        """Lower bound used for random sampling: the limit, or −π (or −1 m) where unlimited."""
        return np.where(np.isfinite(self.lower), self.lower, np.where(self.revolute, -np.pi, -1.0))

    @property
    def sampling_upper(self) -> np.ndarray:
        """Upper bound used for random sampling: the limit, or π (or 1 m) where unlimited."""
        return np.where(np.isfinite(self.upper), self.upper, np.where(self.revolute, np.pi, 1.0))

    def random_q(self, rng: np.random.Generator | int | None = None, size: int | None = None):
        """Configurations drawn uniformly within the sampling bounds (one, or ``size`` × n)."""
        rng = np.random.default_rng(rng)
        shape = (self.dof,) if size is None else (size, self.dof)
        return rng.uniform(self.sampling_lower, self.sampling_upper, size=shape)

    @property
    def midrange(self) -> np.ndarray:
        """The middle of each joint's sampling range."""
        return 0.5 * (self.sampling_lower + self.sampling_upper)

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
        (origin velocity and angular velocity in world axes); see :mod:`redik.conventions`.
        """
        q = self.check_q(q)
        resolved = self.frame(frame)
        if reference not in JACOBIAN_REFERENCES:
            raise InvalidInput(f"reference must be one of {JACOBIAN_REFERENCES}, got {reference!r}")
        self.update(q)
        J = np.empty((6, self.dof))
        self.world_jacobian_into(resolved, J)
        R, p = self._pose_views(resolved)
        if reference == "space":
            J[:3] += skew(p) @ J[3:]
        elif reference == "body":
            J[:3] = R.T @ J[:3]
            J[3:] = R.T @ J[3:]
        return J

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
            if frame.kind == "site":
                views = self.data.site_xmat[frame.id].reshape(3, 3), self.data.site_xpos[frame.id]
            else:
                views = self.data.xmat[frame.id].reshape(3, 3), self.data.xpos[frame.id]
            self._views[frame] = views
        return views

    def pose_into(self, frame: Frame, T: np.ndarray) -> np.ndarray:
        """Copy the current pose of ``frame`` (after :meth:`update`) into the 4 × 4 ``T``."""
        R, p = self._pose_views(frame)
        T[:3, :3] = R
        T[:3, 3] = p
        return T

    def world_jacobian_into(self, frame: Frame, J: np.ndarray) -> np.ndarray:
        """Write the ``"world"`` Jacobian of ``frame`` (after :meth:`update`) into 6 × n ``J``."""
        jac = mujoco.mj_jacSite if frame.kind == "site" else mujoco.mj_jacBody
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
        """Indices of the chain joints in ``model.qpos`` (for embedding ``q`` into a full qpos)."""
        return self._qpos_adr

    @property
    def dof_indices(self) -> np.ndarray:
        """Indices of the chain joints in the model's velocity space (Jacobian columns)."""
        return self._dof_adr

    def full_qpos(self, q: np.ndarray) -> np.ndarray:
        """The model's full ``qpos`` with the chain set to ``q`` and the rest at home."""
        qpos = self.data.qpos.copy()
        qpos[self._qpos_adr] = q
        return qpos

    def __repr__(self) -> str:
        return f"Robot({self.name!r}, dof={self.dof}, ee={self.ee.name!r})"


def _model_name(model: mujoco.MjModel) -> str:
    # MuJoCo stores the model's own name first in its names buffer.
    return bytes(model.names).split(b"\0", 1)[0].decode() or "robot"


def _as_slice(indices: np.ndarray) -> slice | np.ndarray:
    """``indices`` as a slice when they are consecutive, else unchanged."""
    if np.array_equal(indices, np.arange(indices[0], indices[0] + len(indices))):
        return slice(int(indices[0]), int(indices[0]) + len(indices))
    return indices


def _chain_joints(model: mujoco.MjModel, body: int) -> list[int]:
    """Hinge and slide joints on the path from the world to ``body``, root first."""
    joints: list[int] = []
    while body > 0:
        start, count = model.body_jntadr[body], model.body_jntnum[body]
        body_joints = [
            j for j in range(start, start + count) if int(model.jnt_type[j]) in _CHAIN_JOINT_TYPES
        ]
        joints[:0] = body_joints
        body = int(model.body_parentid[body])
    return joints
