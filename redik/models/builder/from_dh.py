r"""A Denavit–Hartenberg table → the MJCF of its serial arm (:func:`dh_to_mjcf`)."""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np

from redik.models.builder.description import dh_numerics, dh_texts
from redik.models.builder.link import Link
from redik.models.builder.serial_arm import serial_arm_to_mjcf
from redik.models.dh import RowLike, parse_convention, parse_rows, split_row, tool_transform


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
            Link(previous_post @ pre, row.is_prismatic, np.array([0.0, 0, 1]), np.zeros(3))
        )
        previous_post = post
    ee = splits[-1][1] @ T_tool
    for link, following in itertools.pairwise(links):
        link.next_anchor = following.pose[:3, 3].copy()
    links[-1].next_anchor = ee[:3, 3].copy()

    return serial_arm_to_mjcf(
        links,
        ee,
        limits=limits,
        name=name,
        home=home,
        radius=radius,
        actuators=actuators,
        custom=custom,
        stored=dh_numerics(table, T_tool),
        texts=dh_texts(conv),
        floor_height=floor_height,
        comment=comment,
    )
