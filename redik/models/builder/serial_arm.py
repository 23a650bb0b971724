"""A serial arm, one :class:`~redik.models.builder.link.Link` per joint → its checked MJCF.

Both builders (:mod:`~redik.models.builder.from_dh`, :mod:`~redik.models.builder.from_screws`)
describe the arm as links and hand it to :func:`serial_arm_to_mjcf`, which checks the options
they share (name, limits, home, radius, custom numerics), sizes the arm and writes the file.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import InvalidInput, ModelError
from redik.models.builder.link import Link
from redik.models.builder.mjcf_text import document_lines
from redik.models.builder.servos import servo_gains

_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_.\-]*$")


def serial_arm_to_mjcf(
    links: list[Link],
    ee: NDArray[np.float64],
    *,
    limits: Any,
    name: str,
    home: Any,
    radius: float | None,
    actuators: bool,
    custom: Mapping[str, float | Sequence[float]] | None,
    stored: dict[str, list[float]],
    texts: dict[str, str],
    floor_height: float,
    comment: str | None,
) -> str:
    """The checked MJCF document of an arm.

    The arm is ``links``, its end-effector site at ``ee`` (a pose in the last body). The
    options are those of :func:`~redik.models.builder.dh_to_mjcf`; ``stored`` and
    ``texts`` are the ``<custom>`` entries of the description the arm came from
    (:mod:`~redik.models.builder.description`). The document is compiled once to check it
    and, with ``actuators``, once more to size the servos at ``home``
    (:func:`~redik.models.builder.servos.servo_gains`).

    Raises:
        InvalidInput: a bad name, limits, home, radius, floor height, comment or custom entry.
        ModelError: MuJoCo does not compile the document.
    """
    n = len(links)
    if not isinstance(name, str) or not _NAME.match(name):
        raise InvalidInput(f"name must be an identifier (letters, digits, _ . -), got {name!r}")
    ranges = _limits(limits, n)
    q_home = _home(home, ranges)
    numerics = _custom(custom)
    numerics.update(stored)
    reach = _reach(links, ranges)
    if radius is None:
        radius = float(np.clip(round(0.03 * reach, 3), 0.005, 0.06))
    if not (isinstance(radius, (int, float)) and math.isfinite(radius) and radius > 0):
        raise InvalidInput(f"radius must be a positive number of metres, got {radius!r}")
    if not math.isfinite(floor_height):
        raise InvalidInput(f"floor_height must be finite, got {floor_height!r}")
    if comment is not None and "--" in comment:
        raise InvalidInput("comment must not contain '--' (not allowed in an XML comment)")

    def document(gains: list[float] | None) -> str:
        return "\n".join(
            document_lines(
                links, ee, ranges, q_home, radius, reach, gains, numerics, texts, name,
                floor_height, comment,
            )
        ) + "\n"  # fmt: skip

    if not actuators:
        xml = document(None)
        _compile(xml)
        return xml
    return document(servo_gains(_compile(document(None)), n, q_home))


def _compile(xml: str) -> str:
    try:
        mujoco.MjModel.from_xml_string(xml)
    except ValueError as error:
        raise ModelError(f"the generated MJCF does not compile: {error}") from None
    return xml


def _limits(limits: Any, n: int) -> NDArray[np.float64]:
    """(n, 2) array of ranges, ±inf where unlimited."""
    if limits is None:
        return np.tile([-np.inf, np.inf], (n, 1))
    rows = list(limits)
    if len(rows) != n:
        raise InvalidInput(f"limits must have one (lower, upper) pair per joint ({n}), got {rows}")
    result = np.empty((n, 2))
    for i, pair in enumerate(rows):
        if pair is None:
            result[i] = (-np.inf, np.inf)
            continue
        try:
            lower, upper = pair
            lower = -np.inf if lower is None else float(lower)
            upper = np.inf if upper is None else float(upper)
        except (TypeError, ValueError):
            raise InvalidInput(
                f"limits[{i}] must be a pair (lower, upper) or None, got {pair!r}"
            ) from None
        finite = (math.isfinite(lower), math.isfinite(upper))
        if finite == (False, False) and lower < upper:
            result[i] = (-np.inf, np.inf)
        elif finite != (True, True):
            raise InvalidInput(
                f"limits[{i}] = {pair!r}: a MuJoCo joint range is either two finite values "
                "or unlimited (None / ±inf on both sides)"
            )
        elif not lower < upper:
            raise InvalidInput(f"limits[{i}] = {pair!r}: expected lower < upper")
        else:
            result[i] = (lower, upper)
    return result


def _home(home: Any, ranges: NDArray[np.float64]) -> NDArray[np.float64]:
    n = len(ranges)
    if home is None:
        q = np.zeros(n)
        outside = (q < ranges[:, 0]) | (q > ranges[:, 1])
        q[outside] = ranges[outside].mean(axis=1)
        return q
    q = np.asarray(home, dtype=float)
    if q.shape != (n,) or not np.all(np.isfinite(q)):
        raise InvalidInput(f"home must be {n} finite joint values, got {home!r}")
    outside_ids = np.flatnonzero((q < ranges[:, 0]) | (q > ranges[:, 1]))
    if outside_ids.size:
        i = int(outside_ids[0])
        raise InvalidInput(
            f"home[{i}] = {float(q[i])!r} lies outside the joint range {tuple(ranges[i].tolist())}"
        )
    return q


def _custom(custom: Mapping[str, float | Sequence[float]] | None) -> dict[str, list[float]]:
    result: dict[str, list[float]] = {}
    for key, value in (custom or {}).items():
        if not isinstance(key, str) or not _NAME.match(key) or key.startswith("redik_"):
            raise InvalidInput(
                f"custom numeric name must be an identifier not starting with 'redik_', got {key!r}"
            )
        data = np.atleast_1d(np.asarray(value, dtype=float))
        if data.ndim != 1 or data.size == 0 or not np.all(np.isfinite(data)):
            raise InvalidInput(
                f"custom[{key!r}] must be a finite float or a non-empty list of them, got {value!r}"
            )
        result[key] = data.tolist()
    return result


def _reach(links: Sequence[Link], ranges: NDArray[np.float64]) -> float:
    total = sum(float(np.linalg.norm(link.next_anchor - link.anchor)) for link in links)
    for link, (lower, upper) in zip(links, ranges, strict=True):
        if link.slide:
            total += upper - lower if math.isfinite(upper) else 0.0
    return max(total, 0.1)
