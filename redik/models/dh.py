r"""Denavit–Hartenberg tables as data, and a pure-numpy forward kinematics.

This module is deliberately independent of MuJoCo: it is the reference the generated
scenes are tested against, and the kinematics the closed-form solvers are written in.
Units and frames follow :mod:`redik.core.conventions` (metres, radians, ``T_ab`` maps frame *b*
coordinates to frame *a*).

Two conventions are supported, differing in where frame *i* is attached to link *i*.

``"standard"`` (Denavit–Hartenberg 1955; Spong, Hutchinson & Vidyasagar, *Robot Modeling
and Control*, §3.2). Joint *i* moves about/along :math:`z_{i-1}`; row *i* holds
:math:`(a_i, d_i, \alpha_i, \theta_i)` and

.. math:: {}^{i-1}T_i = R_z(\theta_i)\, T_z(d_i)\, T_x(a_i)\, R_x(\alpha_i).

``"modified"`` (Craig, *Introduction to Robotics*, 3rd ed., §3.4). Joint *i* moves
about/along :math:`z_i`; row *i* holds :math:`(a_{i-1}, d_i, \alpha_{i-1}, \theta_i)` and

.. math:: {}^{i-1}T_i = R_x(\alpha_{i-1})\, T_x(a_{i-1})\, R_z(\theta_i)\, T_z(d_i).

In both, a revolute row has :math:`\theta_i = q_i + \theta^{\text{offset}}_i` and a
prismatic row :math:`d_i = q_i + d_i^{\text{offset}}`, so ``q = 0`` is the pose the table
is written at. The end pose is :math:`T_{0n}(q) = \prod_i {}^{i-1}T_i(q_i)\; T_{\text{tool}}`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import InvalidConfiguration, InvalidInput, ModelError
from redik.core.rotation_policy import as_pose
from redik.core.validate import as_vector

Convention = Literal["standard", "modified"]
JointType = Literal["revolute", "prismatic"]

_CONVENTION_ALIASES: dict[str, Convention] = {
    "standard": "standard",
    "sdh": "standard",
    "modified": "modified",
    "mdh": "modified",
    "craig": "modified",
}
_JOINT_TYPES: tuple[JointType, ...] = ("revolute", "prismatic")
_ROW_KEYS = ("a", "d", "alpha", "theta", "joint")


@dataclass(frozen=True)
class DHRow:
    r"""One row of a Denavit–Hartenberg table.

    Attributes:
        a: Link length (m). In the modified convention this is :math:`a_{i-1}`.
        d: Link offset (m); for a prismatic row, the offset added to ``q_i``.
        alpha: Link twist (rad). In the modified convention this is :math:`\alpha_{i-1}`.
        theta: Joint angle (rad); for a revolute row, the offset added to ``q_i``.
        joint: ``"revolute"`` or ``"prismatic"``.
    """

    a: float
    d: float
    alpha: float
    theta: float = 0.0
    joint: JointType = "revolute"

    def __post_init__(self) -> None:
        for field in ("a", "d", "alpha", "theta"):
            value = getattr(self, field)
            real = isinstance(value, (int, float, np.integer, np.floating))
            if isinstance(value, bool) or not real:
                raise InvalidInput(f"DHRow.{field} must be a real number, got {value!r}")
            if not math.isfinite(value):
                raise InvalidInput(f"DHRow.{field} must be finite, got {value!r}")
            object.__setattr__(self, field, float(value))
        if self.joint not in _JOINT_TYPES:
            raise InvalidInput(f"DHRow.joint must be 'revolute' or 'prismatic', got {self.joint!r}")

    @property
    def is_prismatic(self) -> bool:
        """Whether the row's joint variable is ``d`` (else it is ``theta``)."""
        return self.joint == "prismatic"


RowLike = DHRow | Mapping[str, Any] | Sequence[Any]


def parse_row(row: RowLike, index: int | None = None) -> DHRow:
    """Convert one row to a :class:`DHRow`.

    Accepted forms: a :class:`DHRow`; a mapping with keys ``a``, ``d``, ``alpha`` and
    optionally ``theta`` and ``joint``; a tuple/list ``(a, d, alpha[, theta[, joint]])``.

    Raises:
        ModelError: The row has the wrong form, an unknown key, or a bad value; the message
            names the row (``index``) and what was expected.
    """
    where = "DH row" if index is None else f"DH row {index}"
    if isinstance(row, DHRow):
        return row
    try:
        if isinstance(row, Mapping):
            unknown = sorted(set(row) - set(_ROW_KEYS))
            missing = [key for key in ("a", "d", "alpha") if key not in row]
            if unknown or missing:
                raise ModelError(
                    f"{where}: expected keys a, d, alpha[, theta][, joint], "
                    f"got {sorted(row)} (missing {missing}, unknown {unknown})"
                )
            return DHRow(**dict(row))
        if isinstance(row, (str, bytes)) or not isinstance(row, Sequence | np.ndarray):
            raise ModelError(
                f"{where}: expected a DHRow, a mapping or a tuple (a, d, alpha[, theta[, joint]]),"
                f" got {row!r}"
            )
        if not 3 <= len(row) <= 5:
            raise ModelError(
                f"{where}: expected a tuple (a, d, alpha[, theta[, joint]]) of 3 to 5 entries, "
                f"got {len(row)}: {row!r}"
            )
        return DHRow(*row)
    except InvalidInput as error:
        raise ModelError(f"{where}: {error}") from None


def parse_rows(rows: DHRow | Iterable[RowLike]) -> tuple[DHRow, ...]:
    """Convert a DH table to a tuple of :class:`DHRow` (see :func:`parse_row` for the forms).

    Raises:
        ModelError: The table is empty or a row is malformed (the message names the row).
    """
    if isinstance(rows, (DHRow, Mapping, str, bytes)):
        raise ModelError(f"expected a sequence of DH rows, got a single {type(rows).__name__}")
    parsed = tuple(parse_row(row, index) for index, row in enumerate(rows))
    if not parsed:
        raise ModelError("a DH table needs at least one row, got none")
    return parsed


def parse_convention(convention: str) -> Convention:
    """Normalise a convention name (``"standard"``/``"sdh"``, ``"modified"``/``"mdh"``)."""
    try:
        return _CONVENTION_ALIASES[str(convention).lower()]
    except KeyError:
        raise InvalidInput(
            f"convention must be 'standard' or 'modified' (aliases 'sdh', 'mdh'), "
            f"got {convention!r}"
        ) from None


def rot_x(angle: float) -> NDArray[np.float64]:
    r"""The 4×4 rotation :math:`R_x(\text{angle})`."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def rot_z(angle: float) -> NDArray[np.float64]:
    r"""The 4×4 rotation :math:`R_z(\text{angle})`."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1.0, 0], [0, 0, 0, 1.0]])


def trans(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> NDArray[np.float64]:
    """The 4×4 translation by ``(x, y, z)``."""
    T = np.eye(4)
    T[:3, 3] = (x, y, z)
    return T


def split_row(
    row: DHRow, convention: Convention
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    r"""Split a row's transform around its joint motion: ``T_i(q) = pre · J(q) · post``.

    ``J(q)`` is :math:`R_z(q)` (revolute) or :math:`T_z(q)` (prismatic), and ``pre``/``post``
    are fixed. This is how the row becomes a MuJoCo body (at ``pre``) holding a joint about
    its local *z*, with the next body (or the tool) attached at ``post``::

        standard  revolute    pre = Rz(θ)                 post = Tz(d) Tx(a) Rx(α)
        standard  prismatic   pre = Rz(θ) Tz(d)           post = Tx(a) Rx(α)
        modified  revolute    pre = Rx(α) Tx(a) Rz(θ)     post = Tz(d)
        modified  prismatic   pre = Rx(α) Tx(a) Rz(θ) Tz(d)   post = I
    """
    twist_x = trans(x=row.a) @ rot_x(row.alpha)  # T_x and R_x commute
    if convention == "standard":
        if row.is_prismatic:
            return rot_z(row.theta) @ trans(z=row.d), twist_x
        return rot_z(row.theta), trans(z=row.d) @ twist_x
    if row.is_prismatic:
        return twist_x @ rot_z(row.theta) @ trans(z=row.d), np.eye(4)
    return twist_x @ rot_z(row.theta), trans(z=row.d)


def row_transform(row: DHRow, q: float, convention: Convention) -> NDArray[np.float64]:
    r"""The link transform :math:`{}^{i-1}T_i(q_i)` of one row (equations in the module doc)."""
    theta = row.theta if row.is_prismatic else row.theta + q
    d = row.d + q if row.is_prismatic else row.d
    if convention == "standard":
        return rot_z(theta) @ trans(z=d) @ trans(x=row.a) @ rot_x(row.alpha)
    return rot_x(row.alpha) @ trans(x=row.a) @ rot_z(theta) @ trans(z=d)


def tool_transform(tool: Any, convention: Convention) -> NDArray[np.float64]:
    """The tool transform: identity for ``None``, a validated 4×4, or a θ-fixed DH row.

    A tool row is read in the table's convention with its ``theta`` as written and no
    joint variable (its ``joint`` entry is ignored: the tool is rigid).
    """
    if tool is None:
        return np.eye(4)
    if not isinstance(tool, (DHRow, Mapping)):
        try:
            matrix = np.asarray(tool, dtype=float)
        except (TypeError, ValueError):
            matrix = None
        if matrix is not None and matrix.ndim == 2:
            return as_pose(matrix, "tool")
    try:
        row = parse_row(tool)
    except ModelError as error:
        raise InvalidInput(f"tool must be a 4×4 transform or a DH row: {error}") from None
    return row_transform(row, 0.0, convention)


def forward_all(
    rows: Iterable[RowLike],
    q: Any,
    convention: str = "standard",
    tool: Any = None,
) -> NDArray[np.float64]:
    r"""Every frame of the chain: :math:`T_{00} = I, T_{01}, \dots, T_{0n}` (and the tool).

    Args:
        rows: The DH table (forms accepted by :func:`parse_rows`).
        q: Joint vector, shape ``(n,)`` (rad for revolute rows, m for prismatic rows).
        convention: ``"standard"`` (Spong §3.2) or ``"modified"`` (Craig §3.4).
        tool: ``None``, a 4×4 transform, or a DH row in the same convention with θ fixed.

    Returns:
        Array of shape ``(n + 1, 4, 4)`` — frames 0…n in the base frame — or
        ``(n + 2, 4, 4)`` when a tool is given, the last entry being :math:`T_{0n} T_{tool}`.
    """
    table = parse_rows(rows)
    conv = parse_convention(convention)
    q = as_vector(q, len(table), "q", InvalidConfiguration)
    frames = [np.eye(4)]
    for row, q_i in zip(table, q, strict=True):
        frames.append(frames[-1] @ row_transform(row, float(q_i), conv))
    if tool is not None:
        frames.append(frames[-1] @ tool_transform(tool, conv))
    return np.stack(frames)


def forward(
    rows: Iterable[RowLike],
    q: Any,
    convention: str = "standard",
    tool: Any = None,
) -> NDArray[np.float64]:
    r"""End pose :math:`T_{0n}(q)\,T_{tool}` of a DH chain (4×4, base frame).

    Standard: :math:`\prod_i R_z(\theta_i) T_z(d_i) T_x(a_i) R_x(\alpha_i)` (Spong §3.2);
    modified: :math:`\prod_i R_x(\alpha_{i-1}) T_x(a_{i-1}) R_z(\theta_i) T_z(d_i)`
    (Craig §3.4). See :func:`forward_all` for the arguments.
    """
    return forward_all(rows, q, convention, tool)[-1]
