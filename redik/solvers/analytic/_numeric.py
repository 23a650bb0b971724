"""The arithmetic the closed-form kernels are written against, for one target or many.

A kernel is written once, as formulas on values that are either Python floats (one target:
:data:`SCALAR`, :mod:`math`, no array is allocated) or numpy arrays of shape (B,) (a batch:
:data:`ARRAY`). Branch choices (shoulder, elbow, wrist) are Python loops over the signs, so
every value stays per-target and the same code serves both. Kernels leave angles unwrapped:
the solvers wrap each result once. Operators (``+``, ``*``, ``<=``,
``&``, ``|``, ``abs``) are used directly; never ``~`` or ``not`` on a condition, which differ
between a bool and a bool array.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

#: A float (one target) or a (B,) array (a batch).
Value = Any


@dataclass(frozen=True)
class Numeric:
    """Elementwise functions for one kind of value (see the module docstring)."""

    cos: Callable[[Value], Value]
    sin: Callable[[Value], Value]
    sqrt: Callable[[Value], Value]
    hypot: Callable[[Value, Value], Value]
    atan2: Callable[[Value, Value], Value]
    #: ``where(condition, a, b)``: ``a`` where the condition holds, else ``b``.
    where: Callable[[Value, Value, Value], Value]
    #: ``maximum(a, b)`` elementwise.
    maximum: Callable[[Value, Value], Value]
    #: ``clip(a, lower, upper)`` with scalar bounds.
    clip: Callable[[Value, float, float], Value]
    #: Whether a condition holds for any target.
    any: Callable[[Value], bool]


SCALAR = Numeric(
    cos=math.cos,
    sin=math.sin,
    sqrt=math.sqrt,
    hypot=math.hypot,
    atan2=math.atan2,
    where=lambda condition, a, b: a if condition else b,
    maximum=max,
    clip=lambda a, lower, upper: min(max(a, lower), upper),
    any=bool,
)

ARRAY = Numeric(
    cos=np.cos,
    sin=np.sin,
    sqrt=np.sqrt,
    hypot=np.hypot,
    atan2=np.arctan2,
    where=np.where,
    maximum=np.maximum,
    clip=np.clip,
    any=lambda condition: bool(np.any(condition)),
)


def pose_entries(T: np.ndarray) -> tuple[Any, Numeric]:
    """The entries of one pose or a stack, with their arithmetic.

    The entries ``M[i][j]`` of a validated 4×4 pose (floats) or (B, 4, 4) stack ((B,)
    arrays), with the :class:`Numeric` that goes with them.
    """
    if T.ndim == 2:
        return T.tolist(), SCALAR
    return T.transpose(1, 2, 0), ARRAY
