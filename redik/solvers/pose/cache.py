"""What pose solves keep between calls, owned by the robot they solve for.

One :class:`PoseCache` per robot, in its :func:`~redik.solvers.cache.solver_cache` (so it lives and
dies with the robot, and two robots never share one): per frame its
:class:`~redik.solvers.pose.frame.PoseFrame` and, once ``"dls"`` has run, its compiled
:class:`~redik.solvers.pose.dls_solver.DLSSolver`; on a whole-model robot, the chain to each frame;
the :class:`~redik.qp.problem.Problem` of ``"qp"`` per frame and settings
(:func:`redik.solvers.pose.qp.solve_pose_qp`). Threads solving on one robot share the cache:
each entry is built once, under the cache's lock, and read without one (what ``"dls"``
needs; ``"qp"`` writes the robot's ``MjData`` and its problems are not shared safely).

What it keeps is derived from the model (the compiled chain folds in ``body_pos``,
``site_pos``, the joint axes and anchors; the reach bound), from the values
``robot.state.data.qpos`` holds for the joints the robot does not move, and from the robot's
``lower``, ``upper`` and ``home``. MuJoCo reads the model afresh at each forward kinematics,
so a user may move a tool site or a link between solves; :meth:`PoseCache.of` and
:meth:`PoseCache.known_dls` then find the cache out of date (a byte comparison of those
arrays) and start a new one, instead of solving — and reporting success — on the
old geometry.
"""

from __future__ import annotations

import threading
from typing import TYPE_CHECKING, TypeGuard

import numpy as np

from redik.kinematics.robot import Frame, Robot
from redik.solvers.cache import solver_cache
from redik.solvers.pose.dls_solver import DLSSolver
from redik.solvers.pose.frame import PoseFrame

if TYPE_CHECKING:
    from redik.qp.problem import Problem

_KEY = "pose"
"""The cache's key in :func:`~redik.solvers.cache.solver_cache`."""

_GEOMETRY = ("body_pos", "body_quat", "jnt_pos", "jnt_axis", "qpos0")
"""The model arrays the cached chains and reach bounds are built from (with the rows of
``site_pos``/``site_quat`` or ``geom_pos``/``geom_quat`` of each frame solved for)."""


class PoseCache:
    """A robot's pose-solve state (see the module docstring); :meth:`of` gets or makes it."""

    def __init__(self, robot: Robot) -> None:
        self.robot = robot
        self.frames: dict[Frame, PoseFrame] = {}
        self.dls_solvers: dict[object, DLSSolver] = {}
        """By resolved :class:`Frame`, and by each frame argument (None, a name) a solve
        has resolved before."""
        self.chains: dict[Frame, tuple[Robot, np.ndarray]] = {}
        self.qp_problems: dict[tuple[object, ...], Problem] = {}
        """``"qp"``'s problems, by (frame argument, respect_limits, damping, gain)."""
        self._lock = threading.RLock()  # around every build-and-insert
        # Views of what the kept state is built from (module docstring): the model's
        # geometry and, in contiguous runs, the held entries of robot.state.data.qpos.
        model, qpos = robot.model, robot.state.data.qpos
        held = np.setdiff1d(np.arange(model.nq), robot.qpos_indices)
        runs = np.split(held, np.flatnonzero(np.diff(held) != 1) + 1) if held.size else []
        sources = (
            *(getattr(model, name) for name in _GEOMETRY),
            *(qpos[run[0] : run[-1] + 1] for run in runs),
        )
        self._limits = (robot.lower, robot.upper, robot.home)
        self._sources: tuple[tuple[np.ndarray, ...], bytes] = (sources, b"".join(sources))
        """The views and their bytes when kept, one attribute so that threads read a pair."""

    def is_current(self) -> bool:
        """Whether the cache still describes the robot (module docstring).

        False once the model geometry, the held joints' values or the robot's limits differ
        from those this cache was built on: one ``bytes.join`` of views, cheaper than a
        comparison per array.
        """
        robot = self.robot
        lower, upper, home = self._limits
        sources, stamp = self._sources
        return (
            robot.lower is lower
            and robot.upper is upper
            and robot.home is home
            # ndarray exposes the buffer protocol, which numpy's stubs do not declare.
            and b"".join(sources) == stamp  # type: ignore[arg-type]
        )

    @classmethod
    def of(cls, robot: Robot) -> PoseCache:
        """The robot's cache, made on first use."""
        return solver_cache(robot).get_or_build(_KEY, lambda: cls(robot), PoseCache.is_current)

    @staticmethod
    def known_dls(robot: Robot, frame: object) -> DLSSolver | None:
        """The ``"dls"`` solver of the frame argument ``frame``, if a solve has made it.

        ``frame`` is None, a name or a :class:`Frame`. None when no solve made the solver or
        the cache is out of date: a look-up, the arguments unvalidated.
        """
        cache = solver_cache(robot).get(_KEY)
        if cache is None or not cache.is_current():
            return None  # the full path starts a new cache
        try:
            return cache.dls_solvers.get(frame)
        except TypeError:  # an unhashable frame argument: the full validation refuses it
            return None

    def frame(self, frame: Frame) -> PoseFrame:
        """The :class:`PoseFrame` of a resolved frame, built on first use.

        Raises:
            InvalidInput: no joint of the robot moves ``frame``.
        """
        pose_frame = self.frames.get(frame)
        if pose_frame is None:
            with self._lock:
                pose_frame = self.frames.get(frame)
                if pose_frame is None:
                    pose_frame = PoseFrame(self.robot, frame)
                    if frame.kind != "body":  # its offset on its body is geometry too
                        model, rows = self.robot.model, slice(frame.id, frame.id + 1)
                        sources = self._sources[0] + tuple(
                            getattr(model, f"{frame.kind}_{name}")[rows] for name in ("pos", "quat")
                        )
                        self._sources = (sources, b"".join(sources))
                    self.frames[frame] = pose_frame
        return pose_frame

    def dls(self, frame: Frame, argument: object) -> DLSSolver:
        """The ``"dls"`` solver of a resolved frame, compiled on first use.

        :meth:`known_dls` finds it by the frame argument ``argument`` from now on (when None
        or a name).
        """
        solver = self.dls_solvers.get(frame)
        if solver is None:
            with self._lock:
                solver = self.dls_solvers.get(frame)
                if solver is None:
                    solver = self.dls_solvers[frame] = DLSSolver(self.frame(frame))
        if argument is None or isinstance(argument, str):
            self.dls_solvers[argument] = solver
        return solver

    def chain(self, frame: Frame, q_whole: np.ndarray) -> tuple[Robot, np.ndarray]:
        """``robot.chain(frame, q_whole)`` of a whole-model robot, and its ``q`` there.

        The chain is kept while the joints it holds keep their values: its compiled solver
        bakes them in, and rebuilding both per call would cost more than the solve. The
        chain's ``q`` comes from ``q_whole``, not from ``chain.data``, which the threads sharing
        the chain all write.
        """
        robot = self.robot
        qpos = robot.full_qpos(q_whole)
        cached = self.chains.get(frame)
        if not _holds(cached, qpos):
            with self._lock:
                cached = self.chains.get(frame)
                if not _holds(cached, qpos):
                    chain = robot.chain(frame, q_whole)
                    cached = self.chains[frame] = (chain, np.delete(qpos, chain.qpos_indices))
        chain = cached[0]
        chain.state.data.qpos[:] = qpos
        return chain, qpos[chain.qpos_indices]


def _holds(
    cached: tuple[Robot, np.ndarray] | None, qpos: np.ndarray
) -> TypeGuard[tuple[Robot, np.ndarray]]:
    """A cached ``(chain, held values)`` holds its other joints at their values in ``qpos``."""
    return cached is not None and np.array_equal(np.delete(qpos, cached[0].qpos_indices), cached[1])
