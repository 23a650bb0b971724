"""Exceptions raised by redik.

Every error redik raises on misuse derives from :class:`RedikError`. Ordinary failures of a
solver (a target out of reach, an iteration limit) are *not* exceptions: they come back as
a result with ``success=False`` and a ``status``.
"""

from __future__ import annotations


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


class ModelError(RedikError):
    """A robot model cannot be loaded or built (missing file, bad MJCF/URDF, bad table)."""


class ModelWarning(UserWarning):
    """A model loaded, but with a part left out (e.g. a mesh in a format MuJoCo cannot read)."""


class UnknownFrame(RedikError, KeyError):
    """A frame name names no site or body of the model."""

    def __str__(self) -> str:  # KeyError would otherwise quote the message
        return str(self.args[0]) if self.args else ""


class BackendError(RedikError):
    """A QP back-end is unknown, not installed, or failed on a problem."""


class InfeasibleProblem(RedikError):
    """The hard constraints of a problem admit no solution."""
