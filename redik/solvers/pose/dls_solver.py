r"""The ``"dls"`` driver of :func:`~redik.solvers.pose.solve_pose`: one compiled call per solve.

Every attempt and restart of damped least squares on one pose target runs in one call of the
compiled kernel :func:`redik.solvers.dls.solve_one`, the code
:func:`redik.solvers.batch.solve_batch` runs.

.. math:: Δq = J^T (J J^T + λ I)^{-1} e, \qquad λ = μ\,‖e‖^2 + λ_{min}

(Wampler 1986; Nakamura & Hanafusa 1986; damping after Sugihara 2011; :mod:`redik.solvers.dls`
has the acceptance rule, the clamping loop and the restarts).

The Python around the kernel is kept thin, because its cost is of the order of the solve's:
a solve whose scalar arguments were seen before finds its settings by one dictionary look-up
(:meth:`DLSSolver.prepare` validated them once), hands the target and ``q0`` unchecked to the
kernel, which checks them itself (and refuses, so that
:func:`~redik.solvers.pose.solve.solve_pose`'s full validation names the fault), and builds
the result from the kernel's own summary: the FK of the returned ``q``, its errors, the body
error and the reach excess, with no second FK in Python (the compiled FK is tested equal to
MuJoCo's to 1e-12, ``tests/test_batch_kernel.py``). Only a ``q`` shifted by 2π into the limits
afterwards (``respect_limits=False``) is re-checked by MuJoCo's FK. The kernel is called with
arguments of exactly the types it was compiled for (:func:`exact_array`), so no call compiles
another specialisation.
"""

from __future__ import annotations

import secrets
import threading
from typing import TypeGuard

import numpy as np

from redik.core.result import IKResult
from redik.kinematics.chain import Chain
from redik.solvers import dls as kernel
from redik.solvers.dls import DLSOptions
from redik.solvers.iterative import world_error
from redik.solvers.pose.frame import PoseFrame
from redik.solvers.pose.options import DLS_OPTIONS
from redik.solvers.pose.result import (
    body_twist_norm,
    same_stationary_point,
    shift_into_limits,
    verdict,
)

_SETTINGS_KEPT = 64
"""Combinations of arguments whose settings a solver keeps (all are dropped past it)."""


class DLSSolver:
    """The compiled ``"dls"`` solve of one frame of a robot, with what its calls reuse.

    It holds the frame's compiled chain, the kernel's settings arrays per combination of
    arguments (validated once by :class:`~redik.solvers.dls.DLSOptions`) and the kernel's
    output buffers. One lives in the robot's :class:`~redik.solvers.pose.cache.PoseCache` per
    frame. Threads sharing the robot share the solver; each has its own output buffers, so
    their solves do not overwrite each other's results.

    Args:
        frame: The frame's joints and reach.
    """

    def __init__(self, frame: PoseFrame) -> None:
        self.frame = frame
        self.robot = frame.robot
        self.kernel_arrays = Chain.from_robot(self.robot, frame.frame).kernel_arrays()
        self.reach = np.array([*frame.origin, frame.reach])
        self._thread = threading.local()  # .buffers: this thread's kernel outputs
        self.settings: dict[tuple, tuple] = {}

    def prepare(
        self,
        arguments: tuple,
        pos_tol: float,
        rot_tol: float,
        max_iterations: int,
        restarts: int,
        respect_limits: bool,
        options: dict,
    ) -> tuple:
        """Keep the kernel's settings for these validated values under ``arguments``.

        ``arguments`` are the caller's values as given, and their types; the settings hold the
        history length ``max_iterations`` needs. They are returned too: another thread may
        evict them before a look-up finds them.

        Returns:
            The settings, for :meth:`solve`.

        Raises:
            InvalidInput: an option value :class:`~redik.solvers.dls.DLSOptions` refuses.
        """
        try:
            settings = self.settings.get(arguments)
            if settings is not None:
                return settings
        except TypeError:  # an unhashable option value: DLSOptions names it below
            pass
        dls_options = DLSOptions(
            pos_tol=pos_tol, rot_tol=rot_tol, max_iterations=max_iterations, restarts=restarts,
            **{**DLS_OPTIONS, **options},
        )  # fmt: skip
        floats, counts = dls_options.kernel_settings(respect_limits)
        if len(self.settings) >= _SETTINGS_KEPT:
            self.settings.clear()
        length = dls_options.history_length
        settings = (floats, counts, pos_tol, rot_tol, respect_limits, length)
        self.settings[arguments] = settings
        return settings

    def buffers(self, length: int) -> tuple[np.ndarray, ...]:
        """This thread's kernel output buffers ``(history, errors, q, e)``.

        The history holds at least ``length`` steps; the buffers are made on the thread's first
        solve and grown when short.
        """
        buffers = getattr(self._thread, "buffers", None)
        if buffers is None or buffers[1].shape[1] < length:
            n = self.frame.columns.size
            buffers = self._thread.buffers = (
                np.empty((2, length, n)), np.empty((2, length)), np.empty(n), np.empty(6),
            )  # fmt: skip
        return buffers

    def solve(
        self,
        T_target: object,
        q0: object,
        key: np.uint64,
        arguments: tuple,
        settings: tuple | None = None,
    ) -> IKResult | None:
        """Solve with the settings :meth:`prepare` kept under ``arguments`` (or ``settings``).

        The joints that do not move the frame stay at ``q0`` (default ``robot.home``).

        Returns:
            The result; or None, having solved nothing, when these arguments were not
            prepared, when ``T_target`` or ``q0`` is not a float64 array of its shape (a
            read-only or non-contiguous one, such as ``robot.home``, is copied into the
            C-contiguous writable type the kernel is compiled for: any other would compile
            another specialisation), or when the kernel refuses them (not a rigid transform
            within :data:`~redik.core.rotation_policy.ROTATION_TOLERANCE`; a non-finite or
            huge ``q0``). The caller's full validation then raises, or projects a
            near-rotation onto SO(3).
        """
        if settings is None:
            settings = self._kept(arguments)
        if settings is None:
            return None
        inputs = self._inputs(T_target, q0)
        if inputs is None:
            return None
        T_target, q0 = inputs
        floats, counts, length = settings[0], settings[1], settings[5]
        history, errors, q_chain, e = self.buffers(length)
        status, iterations, used, length, summary = kernel.solve_one(
            self.kernel_arrays, self.frame.columns, self.reach, T_target, q0, key, floats,
            counts, q_chain, history, errors, e,
        )  # fmt: skip
        if status == kernel.INVALID:
            return None
        q, path = self._embed(q0, q_chain, history[1, :length], settings[4])
        return self._result(
            T_target, settings, q, path, errors[1, :length].copy(), e, iterations, used, summary
        )

    def _kept(self, arguments: tuple) -> tuple | None:
        """The settings kept under ``arguments``, or None (also for an unhashable one)."""
        try:
            return self.settings.get(arguments)
        except TypeError:  # an unhashable argument: the full validation refuses it
            return None

    def _inputs(self, T_target: object, q0: object) -> tuple[np.ndarray, np.ndarray] | None:
        """``(T_target, q0)`` as the kernel's exact types, or None when they are not arrays."""
        robot = self.robot
        if q0 is None:
            q0 = robot.home.copy()  # home is read-only
        elif not exact_array(q0, (robot.nq,)):
            q0 = kernel_copy(q0, (robot.nq,))
        if not exact_array(T_target, (4, 4)):
            T_target = kernel_copy(T_target, (4, 4))
        return None if q0 is None or T_target is None else (T_target, q0)

    def _embed(
        self, q0: np.ndarray, q_chain: np.ndarray, history: np.ndarray, respect_limits: bool
    ) -> tuple[np.ndarray, np.ndarray]:
        """The robot's ``q`` and history from the chain's: the other joints stay at ``q0``."""
        if self.frame.every_joint:
            return q_chain.copy(), history.copy()
        robot, columns = self.robot, self.frame.columns
        q = np.clip(q0, robot.lower, robot.upper) if respect_limits else q0.copy()
        q[columns] = q_chain
        path = np.repeat(q[None], len(history), axis=0)
        path[:, columns] = history
        return q, path

    def _result(
        self,
        T_target: np.ndarray,
        settings: tuple,
        q: np.ndarray,
        history: np.ndarray,
        errors: np.ndarray,
        e: np.ndarray,
        iterations: int,
        used: int,
        summary: tuple,
    ) -> IKResult:
        """The result from the kernel's summary, success decided by the pose of ``q``."""
        pos_tol, rot_tol, respect_limits = settings[2], settings[3], settings[4]
        robot = self.robot
        (error_min, error_max, stationary, diverged, position_error, rotation_error, inside,
         error, reach) = summary  # fmt: skip
        if not respect_limits:
            shifted = shift_into_limits(robot, q)
            if shifted is not q:
                q, e, T = shifted, np.empty(6), np.eye(4)
                robot.state.kinematics(q, self.frame.frame, T)
                position_error, rotation_error = world_error(T_target, T, e)
                error = body_twist_norm(e)
            inside = robot.within_limits(q)
        success = (
            position_error <= pos_tol
            and rotation_error <= rot_tol
            and (inside or not respect_limits)
        )
        status, message = verdict(
            success, inside, position_error, rotation_error, reach,
            same_stationary_point(used + 1, error_min, error_max, stationary), diverged,
            used + 1, iterations,
        )  # fmt: skip
        return IKResult(
            q=q,
            success=success,
            status=status,
            iterations=iterations,
            error=error,
            position_error=position_error,
            rotation_error=rotation_error,
            history=history,
            error_history=errors,
            restarts=used,
            method="dls",
            message=message,
        )


_FLOAT = np.dtype(float)
_TWO_TO_64 = 2**64


def exact_array(value: object, shape: tuple[int, ...]) -> TypeGuard[np.ndarray]:
    """``value`` is a C-contiguous writable float64 array of ``shape``.

    That is the type the compiled kernel takes as it is.
    """
    if type(value) is not np.ndarray or value.dtype != _FLOAT or value.shape != shape:
        return False
    flags = value.flags
    return flags.c_contiguous and flags.writeable


def kernel_copy(value: object, shape: tuple[int, ...]) -> np.ndarray | None:
    """A C-contiguous writable copy of a float64 array of ``shape``, None for anything else.

    For a read-only or non-contiguous one (``robot.home``, a transposed view), which would
    otherwise take the full validation.
    """
    if type(value) is not np.ndarray or value.dtype != _FLOAT or value.shape != shape:
        return None
    return np.array(value, order="C")


def kernel_key(seed: int | None) -> np.uint64:
    """The kernel generator's 64-bit state from a validated ``seed``.

    Reproducible for an int; a fresh random one for None.
    """
    if seed is None:
        return np.uint64(secrets.randbits(64))
    return np.uint64(seed % _TWO_TO_64)


def fast_kernel_key(seed: object) -> np.uint64 | None:
    """:func:`kernel_key` of the seeds that need no validation (None, an ``int`` ≥ 0).

    None for the others, which take the full validation.
    """
    if seed is None:
        return np.uint64(secrets.randbits(64))
    if type(seed) is int and seed >= 0:
        return np.uint64(seed % _TWO_TO_64)
    return None
