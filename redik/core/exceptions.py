"""Exceptions raised by redik.

Every error redik raises on misuse derives from :class:`RedikError`. Ordinary failures of a
solver (a target out of reach, an iteration limit) are *not* exceptions: they come back as
a result with ``success=False`` and a ``status``. Input that redik can repair without changing
its meaning beyond a stated tolerance (a rotation typed with three decimals) is repaired with a
:class:`RedikWarning`, never silently; a run that misses a bound the caller set (a simulated
arm leaving its path) warns the same way.
"""

from __future__ import annotations

import os
import sys
import warnings
from pathlib import Path
from types import FrameType

_PACKAGE = str(Path(__file__).resolve().parents[1]) + os.sep  # redik/, not redik/core/


class RedikError(Exception):
    """Root of every redik exception."""


class InvalidInput(RedikError, ValueError):
    """An argument has the wrong shape, holds NaN/inf, or is outside its domain."""


class InvalidConfiguration(InvalidInput):
    """A joint vector ``q`` has the wrong length or non-finite entries."""


class InvalidRotation(InvalidInput):
    """A matrix that should be a rotation (orthonormal, det = +1) is not."""


class InvalidPose(InvalidInput):
    """A 4×4 matrix that should be a rigid transform is not."""


class CheckpointMismatch(InvalidInput):
    """A checkpoint directory belongs to another batch, or is no checkpoint at all.

    See :mod:`redik.solvers.batch.checkpoint`; the message names what differs.
    """


class TargetNotSet(RedikError):
    """A task was used before its target was set (mink's ``TargetNotSet``)."""


class ModelError(RedikError):
    """A robot model cannot be loaded or built (missing file, bad MJCF/URDF, bad table)."""


class UnknownFrame(RedikError, KeyError):
    """A frame name names no site or body of the model."""

    def __str__(self) -> str:  # KeyError would otherwise quote the message
        return str(self.args[0]) if self.args else ""


class BackendError(RedikError):
    """A QP back-end is unknown, not installed, or failed on a problem."""


class InfeasibleProblem(RedikError):
    """The hard constraints of a problem admit no solution."""


class TaskError(RedikError):
    """A foreign (mink) task or limit raised; the message names it, the cause is chained."""


class RedikWarning(UserWarning):
    """Root of every warning redik issues.

    The input was used after a documented repair, or a result missed a bound the caller set.
    """


class ModelWarning(RedikWarning):
    """A model loaded after a stated repair.

    A part was left out (a mesh in a format MuJoCo cannot read) or replaced (an indefinite
    inertia tensor); see :mod:`redik.models.loading`.
    """


class NearRotationWarning(RedikWarning):
    """A matrix close to a rotation was replaced by the closest rotation.

    See :mod:`redik.core.rotation_policy` for the tolerance and
    :func:`~redik.core.rotation_policy.closest_rotation` for the projection.
    """


class TrackingWarning(RedikWarning):
    """A closed-loop run left the reference by more than the bound it was given.

    See :func:`redik.apps.sim.simulate`.
    """


class InstabilityWarning(RedikWarning):
    """A closed-loop run stopped because MuJoCo reported the physics unsound.

    A NaN or huge state it reset, or a full constraint arena; see
    :func:`redik.apps.sim.simulate`.
    """


def warn(message: str, category: type[RedikWarning] = RedikWarning) -> None:
    """Issue a warning attributed to the first caller outside redik.

    So that the warning names the user's line (and filters by module work) however deep the
    check sits.

    Args:
        message: The warning's text.
        category: Its class.
    """
    frame: FrameType | None = sys._getframe(1)
    level = 2  # stacklevel 2 is the caller of warn()
    while frame is not None and frame.f_code.co_filename.startswith(_PACKAGE):
        frame, level = frame.f_back, level + 1
    warnings.warn(message, category, stacklevel=level)
