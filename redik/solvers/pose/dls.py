r"""The ``"dls"`` driver: damped least squares (Levenberg–Marquardt) on one pose target, every
attempt and restart in one call of the compiled kernel :func:`redik.kinematics.dls.solve_one`
— the same code as :func:`redik.solvers.batch.solve_batch`.

.. math:: Δq = J^T (J J^T + λ I)^{-1} e, \qquad λ = μ\,‖e‖^2 + λ_{min}

(Wampler 1986; Nakamura & Hanafusa 1986; damping after Sugihara 2011; the kernel's docstring
has the acceptance rule, the clamping loop and the restarts).

**Why the Python around the kernel is so thin.** A solve of panda takes ~20 µs in the
kernel. Measured on the 2-core machine (``redik bench pose``, interleaved with Robotics
Toolbox, TRAC-IK and mink), the Python that used to surround it — ``as_pose``,
``check_q``, a numpy ``Generator`` built only to check the seed, the settings and the
result, ~115 Python calls in all — cost 40 µs when run back to back and 110 µs right after
another library had run (or after a 1 ms sleep): that code and its data are then cold in
the caches, and the solve was 1.1–1.6× slower than rtb's C++ ``ik_LM`` in the interleaved
run while at parity alone. Hence: a solve whose scalar arguments were seen before finds its
settings by one dictionary look-up (:meth:`DLSSolver.prepare` validated them once), hands
the target and ``q0`` unchecked to the kernel, which checks them itself (and refuses, so
that :func:`~redik.solvers.pose.solve.solve_pose`'s full validation names the fault), and
builds the result from the kernel's own summary: the FK of the returned ``q``, its errors,
the body error and the reach excess, with no second FK in Python (the compiled FK is tested
equal to MuJoCo's to 1e-12, ``tests/test_batch_kernel.py``). Only a ``q`` shifted by 2π into
the limits afterwards (``respect_limits=False``) is re-checked by MuJoCo's FK. The kernel is
called through numba's dispatcher with arguments of exactly the types it was compiled for
(:func:`exact_array`), so no call compiles another specialisation; calling the compiled
entry point directly (numba's internal ``overloads[signature].entry_point``) saved 0.2 µs
warm and 1.8 µs cold of a 23–31 µs call, not worth depending on numba's internals.
"""

from __future__ import annotations

import secrets
import threading

import numpy as np

from redik.core.result import IKResult
from redik.kinematics import dls as kernel
from redik.kinematics.chain import Chain
from redik.kinematics.dls import BatchOptions
from redik.solvers.pose.attempt import PoseProblem
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
    """The compiled chain of one frame (compiled on first use), the kernel's settings arrays
    per combination of arguments (validated once by :class:`BatchOptions`) and the kernel's
    output buffers, reused by every solve: one lives in the robot's
    :class:`~redik.solvers.pose.cache.PoseCache` per frame. Threads sharing the robot share
    the solver; each has its own output buffers, so their solves do not overwrite each
    other's results."""

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
        """Keep the kernel's settings for these validated values, and the history length
        ``max_iterations`` needs, under the caller's ``arguments`` (the values as given, and their
        types), and return them: another thread may evict them before a look-up finds them.

        Raises:
            InvalidInput: an option value :class:`BatchOptions` refuses.
        """
        try:
            settings = self.settings.get(arguments)
            if settings is not None:
                return settings
        except TypeError:  # an unhashable option value: BatchOptions names it below
            pass
        floats, counts = BatchOptions(
            pos_tol=pos_tol, rot_tol=rot_tol, max_iterations=max_iterations, restarts=restarts,
            **{**DLS_OPTIONS, **options},
        ).kernel_settings(respect_limits)  # fmt: skip
        if len(self.settings) >= _SETTINGS_KEPT:
            self.settings.clear()
        settings = (floats, counts, pos_tol, rot_tol, respect_limits, max_iterations + 1)
        self.settings[arguments] = settings
        return settings

    def buffers(self, length: int) -> tuple[np.ndarray, ...]:
        """This thread's kernel output buffers ``(history, errors, q, e)``, the history at
        least ``length`` steps long (made on the thread's first solve, grown when short)."""
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
        """Solve with the settings :meth:`prepare` kept under ``arguments`` (or returned:
        ``settings``); the joints that do not move the frame stay at ``q0`` (default
        ``robot.home``).

        Returns None — having solved nothing — when these arguments were not prepared, when
        ``T_target`` or ``q0`` is not a float64 array of its shape (a read-only or
        non-contiguous one, such as ``robot.home``, is copied into the C-contiguous writable
        type the kernel is compiled for: any other would compile another specialisation),
        or when the kernel refuses them (not a rigid transform within
        :data:`~redik.core.rotation_policy.ROTATION_TOLERANCE`; a non-finite or huge ``q0``).
        The caller's full validation then raises, or projects a near-rotation onto SO(3).
        """
        if settings is None:
            try:
                settings = self.settings.get(arguments)
            except TypeError:  # an unhashable argument: the full validation refuses it
                return None
            if settings is None:
                return None
        floats, counts, pos_tol, rot_tol, respect_limits, length = settings
        robot = self.robot
        if q0 is None:
            q0 = robot.home.copy()  # home is read-only
        elif not exact_array(q0, (robot.nq,)):
            q0 = kernel_copy(q0, (robot.nq,))
            if q0 is None:
                return None
        if not exact_array(T_target, (4, 4)):
            T_target = kernel_copy(T_target, (4, 4))
            if T_target is None:
                return None
        history, errors, q_chain, e = self.buffers(length)
        columns = self.frame.columns
        status, iterations, used, length, summary = kernel.solve_one(
            self.kernel_arrays, columns, self.reach, T_target, q0, key, floats, counts,
            q_chain, history, errors, e,
        )  # fmt: skip
        if status == kernel.INVALID:
            return None
        (error_min, error_max, stationary, diverged, position_error, rotation_error, inside,
         error, reach) = summary  # fmt: skip
        if self.frame.every_joint:
            q = q_chain.copy()
            path = history[1, :length].copy()
        else:
            q = np.clip(q0, robot.lower, robot.upper) if respect_limits else q0.copy()
            q[columns] = q_chain
            path = np.repeat(q[None], length, axis=0)
            path[:, columns] = history[1, :length]
        if not respect_limits:
            shifted = shift_into_limits(robot, q)
            if shifted is not q:
                q, e, T = shifted, np.empty(6), np.eye(4)
                robot.state.kinematics(q, self.frame.frame, T)
                problem = PoseProblem(robot, self.frame.frame, T_target, pos_tol, rot_tol, False)
                position_error, rotation_error = problem.world_error(T, e)
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
            history=path,
            error_history=errors[1, :length].copy(),
            restarts=used,
            method="dls",
            message=message,
        )


_FLOAT = np.dtype(float)
_TWO_TO_64 = 2**64


def exact_array(value: object, shape: tuple[int, ...]) -> bool:
    """``value`` is a C-contiguous writable float64 array of ``shape``: the type the compiled
    kernel takes as it is."""
    if type(value) is not np.ndarray or value.dtype != _FLOAT or value.shape != shape:
        return False
    flags = value.flags
    return flags.c_contiguous and flags.writeable


def kernel_copy(value: object, shape: tuple[int, ...]) -> np.ndarray | None:
    """A C-contiguous writable copy of a float64 array of ``shape`` that is read-only or
    not contiguous (``robot.home``, a transposed view: taken through the full validation,
    the solve was 2.4× slower); None for anything else."""
    if type(value) is not np.ndarray or value.dtype != _FLOAT or value.shape != shape:
        return None
    return np.array(value, order="C")


def kernel_key(seed: int | None) -> np.uint64:
    """The kernel generator's 64-bit state from a validated ``seed`` (reproducible for an
    int; a fresh random one for None)."""
    if seed is None:
        return np.uint64(secrets.randbits(64))
    return np.uint64(seed % _TWO_TO_64)


def fast_kernel_key(seed: object) -> np.uint64 | None:
    """:func:`kernel_key` of the seeds that need no validation (None, an ``int`` ≥ 0); None
    for the others, which take the full validation."""
    if seed is None:
        return np.uint64(secrets.randbits(64))
    if type(seed) is int and seed >= 0:
        return np.uint64(seed % _TWO_TO_64)
    return None
