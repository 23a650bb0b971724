"""Checks of scalar options at the public boundary (rates, tolerances, counts, steps, switches).

Each returns the value as a plain Python type or raises :class:`~redik.core.exceptions.InvalidInput`
naming the option, so a string, ``None``, a bool or NaN where a number belongs never reaches
numpy or MuJoCo as a raw ``TypeError``.
"""

from __future__ import annotations

import math
import os
from numbers import Real
from pathlib import Path

import numpy as np

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


def fraction(value: object, name: str) -> float:
    """``value`` as a float strictly between 0 and 1 (a share such as the fraction by which
    ``‖e‖²`` must fall to count as progress: 0 asks nothing, 1 asks an exact zero)."""
    if isinstance(value, bool) or not isinstance(value, Real) or not 0.0 < value < 1.0:
        raise InvalidInput(f"{name} must be a number in (0, 1), got {value!r}")
    return float(value)


def integer(value: object, name: str, minimum: int = 0, *, allow_none: bool = False) -> int | None:
    """``value`` as a Python ``int ≥ minimum`` (an ``int`` or numpy integer), or None when
    ``allow_none``. A bool, a float (even ``3.0``) or a string is refused: a count of
    iterations, restarts, samples or workers, a chunk size or a seed is a whole number."""
    if value is None and allow_none:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        none = " (or None)" if allow_none else ""
        raise InvalidInput(f"{name} must be an integer ≥ {minimum}{none}, got {value!r}")
    return int(value)


def seed(value: object, name: str = "seed") -> int | None:
    """``value`` when it is a seed of random choices, ``int | None``: an integer ``≥ 0`` (an
    ``int`` or numpy integer, returned as ``int``) for reproducible choices, or None for
    fresh entropy. The callee makes its own ``np.random.default_rng(seed)`` or
    ``np.random.SeedSequence(seed)`` from it. A bool is refused like for :func:`integer`
    (``seed=True`` is no seed 1), and so are floats, strings, negative integers and numpy
    ``Generator``/``SeedSequence`` objects (the message says to pass an int)."""
    if value is None:
        return None
    if not isinstance(value, bool) and isinstance(value, (int, np.integer)) and value >= 0:
        return int(value)
    if isinstance(value, np.random.Generator | np.random.SeedSequence | np.random.BitGenerator):
        raise InvalidInput(
            f"{name} must be None or an integer ≥ 0, got a numpy {type(value).__name__}: pass "
            "an int (e.g. int(rng.integers(2**63)) to derive one from a generator)"
        )
    raise InvalidInput(f"{name} must be None or an integer ≥ 0, got {value!r}")


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
