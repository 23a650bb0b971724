"""The methods of :func:`~redik.solvers.pose.solve_pose`, their defaults and their options.

With the checks of the scalar arguments that are not checked elsewhere (seed, counts,
options).

Tolerances go through :func:`redik.core.validate.positive`, targets through
:func:`redik.core.rotation_policy.as_pose` and joint vectors through
:meth:`redik.Robot.check_q`; what is here is only what belongs to pose IK.
"""

from __future__ import annotations

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.solvers.dls import DLSOptions

METHODS = ("newton", "transpose", "hybrid", "dls", "qp")
"""The methods of :func:`~redik.solvers.pose.solve_pose`."""

MAX_ITERATIONS = {
    "newton": 100, "transpose": 2000, "hybrid": 200, "dls": DLSOptions.max_iterations, "qp": 200,
}  # fmt: skip
"""Default iteration budget per attempt, by method."""

RESTARTS = {"newton": 20, "transpose": 5, "hybrid": 20, "dls": DLSOptions.restarts, "qp": 20}
"""Default number of random restarts after the first attempt, by method."""

DLS_OPTIONS = {
    name: getattr(DLSOptions, name)
    for name in (
        "damping",
        "min_damping",
        "max_damping",
        "patience",
        "progress",
        "candidates",
        "polish_iterations",
        "polish_error",
        "polish_damping",
    )
}
"""The options of ``"dls"`` and their defaults: those of the compiled kernel's
:class:`~redik.solvers.dls.DLSOptions`, which validates them."""

OPTIONS = {
    "dls": DLS_OPTIONS,
    "newton": {"form": "body", "step": 1.0, "stop": "pose"},
    "transpose": {"step": "armijo"},
    "hybrid": {"switch_error": 0.1},
}
"""The options of each method but ``"qp"`` (whose are those of
:func:`redik.solvers.pose.qp.solve_pose_qp`) and their defaults."""


def check_method(method: object) -> str:
    """``method`` if it is one of :data:`METHODS`, else :class:`InvalidInput`."""
    if not isinstance(method, str) or method not in METHODS:
        raise InvalidInput(f"method must be one of {METHODS}, got {method!r}")
    return method


def check_options(method: str, options: dict) -> None:
    """Refuse an option that ``method`` does not take (its values are checked where used)."""
    unknown = sorted(set(options) - set(OPTIONS[method]))
    if unknown:
        raise InvalidInput(
            f"unknown option(s) {unknown} for method {method!r}; it takes {sorted(OPTIONS[method])}"
        )


def check_flag(value: object, name: str) -> bool:
    """``value`` if it is True or False (numpy's too), else :class:`InvalidInput`."""
    if not isinstance(value, bool | np.bool_):
        raise InvalidInput(f"{name} must be True or False, got {value!r}")
    return bool(value)
