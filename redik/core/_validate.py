"""Checks of scalar options at the public boundary (rates, tolerances, steps, switches).

Each returns the value as a plain Python type or raises :class:`~redik.core.exceptions.InvalidInput`
naming the option, so a string, ``None``, a bool or NaN where a number belongs never reaches
numpy or MuJoCo as a raw ``TypeError``.
"""

from __future__ import annotations

import math
import os
from numbers import Real
from pathlib import Path

from redik.core.exceptions import InvalidInput


def positive(value: object, name: str, *, allow_inf: bool = False, unit: str = "") -> float:
    """``value`` as a float ``> 0``, finite unless ``allow_inf``."""
    if (
        isinstance(value, bool)
        or not isinstance(value, Real)
        or not value > 0
        or not (allow_inf or math.isfinite(value))
    ):
        finite = "" if allow_inf else "finite "
        units = f" ({unit})" if unit else ""
        raise InvalidInput(f"{name} must be a {finite}positive number{units}, got {value!r}")
    return float(value)


def non_negative(value: object, name: str) -> float:
    """``value`` as a finite float ``≥ 0``."""
    if (
        isinstance(value, bool)
        or not isinstance(value, Real)
        or not value >= 0
        or not math.isfinite(value)
    ):
        raise InvalidInput(f"{name} must be a finite number ≥ 0, got {value!r}")
    return float(value)


def flag(value: object, name: str) -> bool:
    """``value`` when it is a bool (a truthy string such as ``"no"`` is refused, not obeyed)."""
    if not isinstance(value, bool):
        raise InvalidInput(f"{name} must be True or False, got {value!r}")
    return value


def path(value: object, name: str) -> Path:
    """``value`` as a :class:`~pathlib.Path` when it is a ``str`` or path-like object."""
    if not isinstance(value, (str, os.PathLike)):
        raise InvalidInput(f"{name} must be a path (str or os.PathLike), got {value!r}")
    return Path(value)
