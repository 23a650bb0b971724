"""What pose solves keep between calls, owned by the robot they solve for.

One :class:`PoseCache` per robot, in its :attr:`redik.Robot.solver_cache` (so it lives and
dies with the robot, and two robots never share one): per frame its
:class:`~redik.solvers.pose.frame.PoseFrame` and, once ``"dls"`` has run, its compiled
:class:`~redik.solvers.pose.dls.DLSSolver`; on a whole-model robot, the chain to each frame;
the :class:`~redik.solvers.problem.Problem` of ``"qp"`` per frame and settings
(:func:`redik.solvers.pose.qp.solve_pose_qp`). Threads solving on one robot share the cache:
each entry is built once, under the cache's lock, and read without one (what ``"dls"``
needs; ``"qp"`` writes the robot's ``MjData`` and its problems are not shared safely).
"""

from __future__ import annotations

import threading

import numpy as np

from redik.kinematics.robot import Frame, Robot
from redik.solvers.pose.dls import DLSSolver
from redik.solvers.pose.frame import PoseFrame

_KEY = "pose"
"""The cache's key in :attr:`redik.Robot.solver_cache`."""


class PoseCache:
    """A robot's pose-solve state (see the module docstring); :meth:`of` gets or makes it."""

    def __init__(self, robot: Robot) -> None:
        self.robot = robot
        self.frames: dict[Frame, PoseFrame] = {}
        self.dls_solvers: dict[object, DLSSolver] = {}
        """By resolved :class:`Frame`, and by each frame argument (None, a name) a solve
        has resolved before."""
        self.chains: dict[Frame, tuple[Robot, np.ndarray]] = {}
        self.qp_problems: dict[tuple, object] = {}
        """``"qp"``'s problems, by (frame argument, respect_limits, damping, gain)."""
        self.qp_chains: dict[Frame, tuple | None] = {}
        """``"qp"``'s compiled chains for restart seeds, by frame (None: whole model)."""
        self._lock = threading.RLock()  # around every build-and-insert

    @classmethod
    def of(cls, robot: Robot) -> PoseCache:
        """The robot's cache, made on first use."""
        return robot.solver_cache.get_or_build(_KEY, lambda: cls(robot))

    @staticmethod
    def known_dls(robot: Robot, frame: object) -> DLSSolver | None:
        """The ``"dls"`` solver of the frame argument ``frame`` (None, a name or a
        :class:`Frame`) if a solve has made it, else None — a look-up, nothing validated."""
        cache = robot.solver_cache.get(_KEY)
        if cache is None:
            return None
        try:
            return cache.dls_solvers.get(frame)  # type: ignore[attr-defined]
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
                    pose_frame = self.frames[frame] = PoseFrame(self.robot, frame)
        return pose_frame

    def dls(self, frame: Frame, argument: object) -> DLSSolver:
        """The ``"dls"`` solver of a resolved frame, compiled on first use; :meth:`known_dls`
        finds it by the frame argument ``argument`` from now on (when None or a name)."""
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
        """``robot.chain(frame, q_whole)`` of a whole-model robot and its ``q`` there, the
        chain kept while the joints it holds keep their values: its compiled solver bakes
        them in, and rebuilding both per call made a ``dls`` solve 17× slower than on the
        chain itself (2.2 ms vs 0.13 ms, left arm of ``tests/test_whole_model.py``'s torso;
        0.40 ms kept). The chain's ``q`` comes from ``q_whole``, not from ``chain.data``,
        which the threads sharing the chain all write."""
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
        chain.data.qpos[:] = qpos
        return chain, qpos[chain.qpos_indices]


def _holds(cached: tuple[Robot, np.ndarray] | None, qpos: np.ndarray) -> bool:
    """A cached ``(chain, held values)`` holds its other joints at their values in ``qpos``."""
    return cached is not None and np.array_equal(np.delete(qpos, cached[0].qpos_indices), cached[1])
