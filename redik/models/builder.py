r"""Generate MuJoCo models (MJCF strings) from Denavit–Hartenberg tables or screw axes.

A redik robot is always a MuJoCo model; this module is how a kinematic description from a
textbook or a datasheet becomes one. Both builders produce the same kind of scene:

* one body per joint, nested from the world, each holding one hinge or slide joint;
* capsules between consecutive joint origins and a sphere at each joint (so zero-length
  links still have mass and render), contact disabled (``contype = conaffinity = 0``):
  the models are for kinematics first, and the arm must not collide with itself;
* a site ``ee`` at the end-effector, a floor, a light and a camera ``track`` that follows
  the arm;
* joint ranges from ``limits`` (a joint is limited only where its limits are finite);
* a keyframe ``home``, and with ``actuators=True`` one ``<position>`` servo per joint
  (critically damped, stiffness from the joint-space inertia at ``home`` for a ≈4 Hz
  response, ``ctrlrange`` = joint range); bodies are gravity-compensated so the servos
  track commands without sagging;
* the kinematic description itself, stored in ``<custom>`` so it can be recovered from the
  file (:func:`read_dh`, :func:`read_screws`) together with any user ``custom`` numerics.

Units and conventions: :mod:`redik.core.conventions` (metres, radians). Screw axes follow Modern
Robotics (``S = (ω, v)``), the one place redik uses that order.
"""

from __future__ import annotations

import itertools
import math
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import mujoco
import numpy as np

from redik.core.exceptions import InvalidInput, ModelError
from redik.lie import adjoint, as_pose, quat_from_matrix
from redik.models.dh import DHRow, RowLike, parse_convention, parse_rows, split_row, tool_transform

# Names of the <custom> entries that carry the kinematic description.
DH_NUMERICS = ("redik_dh_a", "redik_dh_d", "redik_dh_alpha", "redik_dh_theta")
DH_PRISMATIC = "redik_dh_prismatic"
DH_TOOL = "redik_dh_tool"
DH_CONVENTION = "redik_convention"
POE_SCREWS = "redik_poe_screws"
POE_HOME = "redik_poe_M"

SERVO_FREQUENCY = 4.0
"""Natural frequency (Hz) of the generated position servos at the ``home`` posture."""

_UNIT_TOL = 1e-6
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_.\-]*$")


@dataclass
class _Link:
    """One body of the chain, in its parent's coordinates."""

    pose: np.ndarray  # 4×4, parent body → this body at q = 0
    slide: bool
    axis: np.ndarray  # joint axis, body coordinates
    anchor: np.ndarray  # joint position, body coordinates
    next_anchor: np.ndarray = field(default_factory=lambda: np.zeros(3))


# ---------------------------------------------------------------------------------------
# Public builders
# ---------------------------------------------------------------------------------------


def dh_to_mjcf(
    rows: Iterable[RowLike],
    convention: str = "standard",
    limits: Any = None,
    tool: Any = None,
    *,
    name: str = "dh_robot",
    home: Any = None,
    radius: float | None = None,
    actuators: bool = True,
    custom: Mapping[str, float | Sequence[float]] | None = None,
    floor_height: float = 0.0,
    comment: str | None = None,
) -> str:
    r"""MJCF of the serial arm described by a Denavit–Hartenberg table.

    Each row becomes a body holding a joint about its local *z*, with ``qpos = 0`` ⇔
    ``θ = offset`` (revolute) or ``d = offset`` (prismatic), so that the ``ee`` site pose
    equals :func:`redik.models.dh.forward` ``(rows, q, convention, tool)`` for every ``q``. The row
    is split as ``T_i(q) = pre_i · J(q_i) · post_i`` (:func:`redik.models.dh.split_row`), body *i*
    sits at ``post_{i-1} · pre_i`` in body *i−1*, and the ``ee`` site at ``post_n · tool``.

    Args:
        rows: The DH table (forms of :func:`redik.models.dh.parse_rows`).
        convention: ``"standard"`` (Spong §3.2) or ``"modified"`` (Craig §3.4).
        limits: ``None`` or one ``(lower, upper)`` per joint (rad or m); ``None``/``±inf``
            for an unlimited joint.
        tool: ``None``, a 4×4 transform, or a DH row in the same convention with θ fixed.
        name: Model name.
        home: Joint vector of the ``home`` keyframe (default: 0, or mid-range for a limited
            joint whose range excludes 0).
        radius: Capsule radius (m); default ≈ 3 % of the reach.
        actuators: Add one ``<position>`` servo per joint.
        custom: Extra ``<numeric>`` entries, name → float or list of floats.
        floor_height: Height of the floor below the base frame (visual only).
        comment: Text of an XML comment written at the top of the file.

    Returns:
        The MJCF document. The table is stored in numerics ``redik_dh_a``, ``redik_dh_d``,
        ``redik_dh_alpha``, ``redik_dh_theta``, ``redik_dh_prismatic`` (1 for prismatic),
        ``redik_dh_tool`` (4×4 row-major) and the text ``redik_convention``.

    Raises:
        ModelError: A row is malformed.
        InvalidInput: Bad convention, limits, home, tool, radius or custom entry.
    """
    table = parse_rows(rows)
    conv = parse_convention(convention)
    T_tool = tool_transform(tool, conv)
    splits = [split_row(row, conv) for row in table]
    links = []
    previous_post = np.eye(4)
    for row, (pre, post) in zip(table, splits, strict=True):
        links.append(
            _Link(previous_post @ pre, row.is_prismatic, np.array([0.0, 0, 1]), np.zeros(3))
        )
        previous_post = post
    ee = splits[-1][1] @ T_tool
    for link, following in itertools.pairwise(links):
        link.next_anchor = following.pose[:3, 3].copy()
    links[-1].next_anchor = ee[:3, 3].copy()

    stored = {
        "redik_dh_a": [row.a for row in table],
        "redik_dh_d": [row.d for row in table],
        "redik_dh_alpha": [row.alpha for row in table],
        "redik_dh_theta": [row.theta for row in table],
        DH_PRISMATIC: [float(row.is_prismatic) for row in table],
        DH_TOOL: T_tool.ravel().tolist(),
    }
    return _chain_to_mjcf(
        links,
        ee,
        limits=limits,
        name=name,
        home=home,
        radius=radius,
        actuators=actuators,
        custom=custom,
        stored=stored,
        texts={DH_CONVENTION: conv},
        floor_height=floor_height,
        comment=comment,
    )


def screws_to_mjcf(
    screws: Any,
    M: Any,
    frame: str = "space",
    limits: Any = None,
    *,
    name: str = "poe_robot",
    home: Any = None,
    radius: float | None = None,
    actuators: bool = True,
    custom: Mapping[str, float | Sequence[float]] | None = None,
    floor_height: float = 0.0,
    comment: str | None = None,
) -> str:
    r"""MJCF of the serial arm given by the product of exponentials (Modern Robotics §4.1).

    .. math:: T(q) = e^{[S_1] q_1} \cdots e^{[S_n] q_n} M = M e^{[B_1] q_1} \cdots e^{[B_n] q_n}

    Body screws are first converted to space screws, :math:`S_i = [\mathrm{Ad}_M] B_i`. The
    bodies are nested and all sit at the world origin with identity orientation at
    ``q = 0``, so each joint is written with its world axis: a revolute joint
    (:math:`\|\omega\| = 1`, zero pitch) at the point :math:`q = \omega \times v` of its
    axis, a prismatic joint (:math:`\omega = 0`, :math:`\|v\| = 1`) along :math:`v`. The
    ``ee`` site is at ``M`` in the last body.

    Args:
        screws: Screw axes, shape ``(6, n)``, each column ``(ω, v)`` (MR order).
        M: End-effector pose at ``q = 0`` (4×4).
        frame: ``"space"`` (``screws`` are :math:`S_i`) or ``"body"`` (:math:`B_i`).
        limits, name, home, radius, actuators, custom, floor_height, comment: As in
            :func:`dh_to_mjcf`.

    Returns:
        The MJCF document. The space screws are stored in the numeric ``redik_poe_screws``
        (n × 6, row-major, each row ``(ω, v)``) and ``M`` in ``redik_poe_M`` (row-major).

    Raises:
        ModelError: A column is helical (non-zero pitch) or has a non-unit axis.
        InvalidInput: Bad shape, frame, limits, home, radius or custom entry.
        InvalidPose: ``M`` is not a rigid transform.
    """
    S = _space_screws(screws, M, frame)
    M = as_pose(M, "M")
    links = []
    previous_anchor = np.zeros(3)
    for i in range(S.shape[1]):
        omega, v = S[:3, i], S[3:, i]
        prismatic = not np.any(omega)
        anchor = previous_anchor if prismatic else np.cross(omega, v)
        links.append(_Link(np.eye(4), prismatic, v if prismatic else omega, anchor.copy()))
        previous_anchor = anchor
    for link, following in itertools.pairwise(links):
        link.next_anchor = following.anchor.copy()
    links[-1].next_anchor = M[:3, 3].copy()
    stored = {POE_SCREWS: S.T.ravel().tolist(), POE_HOME: M.ravel().tolist()}
    return _chain_to_mjcf(
        links,
        M,
        limits=limits,
        name=name,
        home=home,
        radius=radius,
        actuators=actuators,
        custom=custom,
        stored=stored,
        texts={},
        floor_height=floor_height,
        comment=comment,
    )


def read_dh(model: mujoco.MjModel) -> tuple[tuple[DHRow, ...], str, np.ndarray]:
    """Recover ``(rows, convention, tool)`` from a model made by :func:`dh_to_mjcf`.

    Raises:
        ModelError: The model does not carry a DH table.
    """
    try:
        a, d, alpha, theta = (_numeric(model, key) for key in DH_NUMERICS)
        prismatic = _numeric(model, DH_PRISMATIC)
        tool = _numeric(model, DH_TOOL).reshape(4, 4)
        convention = parse_convention(_text(model, DH_CONVENTION))
    except (KeyError, ValueError) as error:
        raise ModelError(
            f"the model carries no DH table (custom numerics "
            f"{', '.join(DH_NUMERICS)}, {DH_PRISMATIC}, {DH_TOOL} and text {DH_CONVENTION}): "
            f"{error}"
        ) from None
    rows = tuple(
        DHRow(*values, joint="prismatic" if flag else "revolute")
        for *values, flag in zip(a, d, alpha, theta, prismatic, strict=True)
    )
    return rows, convention, tool


def read_screws(model: mujoco.MjModel) -> tuple[np.ndarray, np.ndarray]:
    """Recover the space screws ``S`` (6 × n, MR order) and ``M`` from :func:`screws_to_mjcf`.

    Raises:
        ModelError: The model does not carry screw axes.
    """
    try:
        S = _numeric(model, POE_SCREWS).reshape(-1, 6).T
        M = _numeric(model, POE_HOME).reshape(4, 4)
    except (KeyError, ValueError) as error:
        raise ModelError(
            f"the model carries no screw axes (custom numerics {POE_SCREWS}, {POE_HOME}): {error}"
        ) from None
    return S, M


# ---------------------------------------------------------------------------------------
# Validation of the kinematic inputs
# ---------------------------------------------------------------------------------------


def _space_screws(screws: Any, M: Any, frame: str) -> np.ndarray:
    try:
        S = np.array(screws, dtype=float)
    except (TypeError, ValueError):
        raise InvalidInput(f"screws must be a 6×n array of numbers, got {screws!r}") from None
    if S.ndim == 1 and S.shape == (6,):
        S = S.reshape(6, 1)
    if S.ndim != 2 or S.shape[0] != 6 or S.shape[1] == 0:
        raise InvalidInput(
            f"screws must have shape (6, n) with columns (ω, v), got {S.shape}"
            + (" (transpose it?)" if S.ndim == 2 and S.shape[1] == 6 else "")
        )
    if not np.all(np.isfinite(S)):
        raise InvalidInput(f"screws must be finite, got\n{S}")
    if frame not in ("space", "body"):
        raise InvalidInput(f"frame must be 'space' or 'body', got {frame!r}")
    if frame == "body":
        # S = [Ad_M] B (MR §4.1.3); lie.adjoint acts on (v, ω), so swap the halves around it.
        swap = np.r_[3:6, 0:3]
        S = (adjoint(as_pose(M, "M")) @ S[swap])[swap]
    for i in range(S.shape[1]):
        omega, v = S[:3, i], S[3:, i]
        norm_omega = float(np.linalg.norm(omega))
        if norm_omega > _UNIT_TOL:
            if abs(norm_omega - 1.0) > _UNIT_TOL:
                raise ModelError(
                    f"screw column {i}: a revolute axis needs ‖ω‖ = 1, got ‖ω‖ = {norm_omega:.9g}"
                )
            pitch = float(omega @ v)
            if abs(pitch) > _UNIT_TOL:
                raise ModelError(
                    f"screw column {i} has pitch ω·v = {pitch:.9g}; only revolute (pitch 0) "
                    "and prismatic (ω = 0) joints are supported, not helical ones"
                )
        else:
            S[:3, i] = 0.0
            norm_v = float(np.linalg.norm(v))
            if abs(norm_v - 1.0) > _UNIT_TOL:
                raise ModelError(
                    f"screw column {i}: a prismatic axis (ω = 0) needs ‖v‖ = 1, "
                    f"got ‖v‖ = {norm_v:.9g}"
                )
    return S


def _limits(limits: Any, n: int) -> np.ndarray:
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


def _home(home: Any, ranges: np.ndarray) -> np.ndarray:
    n = len(ranges)
    if home is None:
        q = np.zeros(n)
        outside = (q < ranges[:, 0]) | (q > ranges[:, 1])
        q[outside] = ranges[outside].mean(axis=1)
        return q
    q = np.asarray(home, dtype=float)
    if q.shape != (n,) or not np.all(np.isfinite(q)):
        raise InvalidInput(f"home must be {n} finite joint values, got {home!r}")
    outside = np.flatnonzero((q < ranges[:, 0]) | (q > ranges[:, 1]))
    if outside.size:
        i = int(outside[0])
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


# ---------------------------------------------------------------------------------------
# MJCF writer
# ---------------------------------------------------------------------------------------


def _fmt(x: float) -> str:
    """Shortest exact text of a float; integers without '.0', tiny round-off as 0."""
    x = float(x)
    if abs(x) < 1e-14:
        return "0"
    if x == round(x) and abs(x) < 1e15:
        return str(int(x))
    return repr(x)


def _vec(values: Iterable[float]) -> str:
    return " ".join(_fmt(x) for x in values)


def _pose_attrs(T: np.ndarray) -> str:
    """``pos``/``quat`` attributes of a 4×4 (omitted when zero/identity)."""
    attrs = []
    if np.any(np.abs(T[:3, 3]) >= 1e-14):
        attrs.append(f'pos="{_vec(T[:3, 3])}"')
    R = np.where(np.abs(T[:3, :3]) < 1e-14, 0.0, T[:3, :3])
    if not np.array_equal(R, np.eye(3)):
        attrs.append(f'quat="{_vec(quat_from_matrix(R))}"')
    return (" " + " ".join(attrs)) if attrs else ""


def _reach(links: Sequence[_Link], ranges: np.ndarray) -> float:
    total = sum(float(np.linalg.norm(link.next_anchor - link.anchor)) for link in links)
    for link, (lower, upper) in zip(links, ranges, strict=True):
        if link.slide:
            total += upper - lower if math.isfinite(upper) else 0.0
    return max(total, 0.1)


def _servo_gains(xml: str, nq: int, home: np.ndarray) -> list[float]:
    """``kp_i = (2π f)² M_ii(home)``, rounded to two significant digits."""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    data.qpos[:] = home
    mujoco.mj_forward(model, data)
    gains = []
    unit, column = np.zeros(nq), np.zeros(nq)
    for i in range(nq):
        unit[:] = 0.0
        unit[i] = 1.0
        mujoco.mj_mulM(model, data, column, unit)
        kp = (2 * math.pi * SERVO_FREQUENCY) ** 2 * column[i]
        gains.append(round(kp, 1 - math.floor(math.log10(kp))))
    return gains


def _chain_to_mjcf(
    links: list[_Link],
    ee: np.ndarray,
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
            _document_lines(
                links, ee, ranges, q_home, radius, reach, gains, numerics, texts, name,
                floor_height, comment,
            )
        ) + "\n"  # fmt: skip

    if not actuators:
        xml = document(None)
        _compile(xml)
        return xml
    return document(_servo_gains(_compile(document(None)), n, q_home))


def _compile(xml: str) -> str:
    try:
        mujoco.MjModel.from_xml_string(xml)
    except ValueError as error:
        raise ModelError(f"the generated MJCF does not compile: {error}") from None
    return xml


def _document_lines(
    links: list[_Link],
    ee: np.ndarray,
    ranges: np.ndarray,
    q_home: np.ndarray,
    radius: float,
    reach: float,
    gains: list[float] | None,
    numerics: dict[str, list[float]],
    texts: dict[str, str],
    name: str,
    floor_height: float,
    comment: str | None,
) -> list[str]:
    r = radius
    lines = []
    if comment:
        lines += ["<!--", *("  " + line if line else "" for line in comment.splitlines()), "-->"]
    lines += [
        f'<mujoco model="{name}">',
        '  <compiler angle="radian" autolimits="true"/>',
        '  <option timestep="0.002" integrator="implicitfast"/>',
        f'  <statistic center="0 0 {_fmt(round(0.3 * reach, 3))}" extent="{_fmt(round(reach, 3))}"/>',  # noqa: E501
        "",
        "  <default>",
        '    <joint armature="0.01" damping="0.1"/>',
        '    <geom contype="0" conaffinity="0" material="link"/>',
        "  </default>",
        "",
        "  <asset>",
        '    <texture name="grid" type="2d" builtin="checker" width="512" height="512"'
        ' rgb1="0.2 0.3 0.4" rgb2="0.3 0.4 0.5"/>',
        '    <material name="grid" texture="grid" texrepeat="1 1" texuniform="true"'
        ' reflectance="0.1"/>',
        '    <material name="link" rgba="0.85 0.55 0.2 1"/>',
        '    <material name="link_alt" rgba="0.9 0.9 0.9 1"/>',
        '    <material name="joint" rgba="0.25 0.25 0.3 1"/>',
        '    <material name="ram" rgba="0.6 0.6 0.65 1"/>',
        "  </asset>",
        "",
        "  <worldbody>",
        f'    <light name="top" pos="0 0 {_fmt(round(3 * reach, 3))}" dir="0 0 -1"/>',
        f'    <geom name="floor" type="plane" pos="0 0 {_fmt(floor_height)}"'
        f' size="{_fmt(round(2 * reach, 3))} {_fmt(round(2 * reach, 3))} 0.05" material="grid"/>',
        f'    <geom name="base" type="cylinder" fromto="0 0 {_fmt(floor_height)} 0 0'
        f' {_fmt(max(floor_height + r, 0.0))}" size="{_fmt(2 * r)}" material="joint"/>',
        f'    <camera name="track" mode="targetbodycom" target="link1"'
        f' pos="{_vec(np.round([1.2 * reach, -1.2 * reach, 0.8 * reach], 3))}"/>',
    ]
    indent = "    "
    for i, link in enumerate(links, start=1):
        lower, upper = ranges[i - 1]
        joint_range = f' range="{_fmt(lower)} {_fmt(upper)}"' if math.isfinite(lower) else ""
        kind = "slide" if link.slide else "hinge"
        anchor = f' pos="{_vec(link.anchor)}"' if np.any(link.anchor) else ""
        lines += [
            f'{indent}<body name="link{i}"{_pose_attrs(link.pose)} gravcomp="1">',
            f'{indent}  <joint name="joint{i}" type="{kind}"{anchor}'
            f' axis="{_vec(link.axis)}"{joint_range}/>',
            f'{indent}  <geom name="joint{i}" type="sphere" size="{_fmt(1.25 * r)}"'
            f'{anchor} material="joint"/>',
        ]
        if link.slide:
            travel = upper - lower if math.isfinite(upper) else 0.5 * reach
            axis = link.axis / np.linalg.norm(link.axis)
            tail = link.anchor - travel * axis
            lines.append(
                f'{indent}  <geom name="ram{i}" type="capsule" size="{_fmt(0.6 * r)}"'
                f' fromto="{_vec(tail)} {_vec(link.anchor)}" material="ram"/>'
            )
        if np.linalg.norm(link.next_anchor - link.anchor) > 1e-9:
            material = "" if i % 2 else ' material="link_alt"'
            lines.append(
                f'{indent}  <geom name="link{i}" type="capsule" size="{_fmt(r)}"'
                f' fromto="{_vec(link.anchor)} {_vec(link.next_anchor)}"{material}/>'
            )
        indent += "  "
    lines.append(
        f'{indent}<site name="ee"{_pose_attrs(ee)} size="{_fmt(round(0.8 * r, 4))}"'
        ' rgba="0.9 0.1 0.1 1"/>'
    )
    for _ in links:
        indent = indent[:-2]
        lines.append(f"{indent}</body>")
    lines += ["  </worldbody>", ""]
    if gains is not None:
        lines.append("  <actuator>")
        for i, kp in enumerate(gains, start=1):
            lower, upper = ranges[i - 1]
            ctrl = f' ctrlrange="{_fmt(lower)} {_fmt(upper)}"' if math.isfinite(lower) else ""
            lines.append(
                f'    <position name="actuator{i}" joint="joint{i}" kp="{_fmt(kp)}"'
                f' dampratio="1"{ctrl}/>'
            )
        lines += ["  </actuator>", ""]
    lines.append("  <custom>")
    for key, data in numerics.items():
        lines.append(f'    <numeric name="{key}" data="{_vec(data)}"/>')
    for key, text in texts.items():
        lines.append(f'    <text name="{key}" data="{text}"/>')
    lines += ["  </custom>", "", "  <keyframe>"]
    ctrl = f' ctrl="{_vec(q_home)}"' if gains is not None else ""
    lines += [f'    <key name="home" qpos="{_vec(q_home)}"{ctrl}/>', "  </keyframe>", "</mujoco>"]
    return lines


def _numeric(model: mujoco.MjModel, key: str) -> np.ndarray:
    return np.array(model.numeric(key).data, dtype=float)


def _text(model: mujoco.MjModel, key: str) -> str:
    index = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_TEXT, key)
    if index < 0:
        raise KeyError(f"no text {key!r}")
    start = int(model.text_adr[index])
    raw = bytes(model.text_data[start : start + int(model.text_size[index])])
    return raw.split(b"\x00", 1)[0].decode()
