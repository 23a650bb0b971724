"""The MJCF text of a generated arm: numbers, poses and the document's elements.

Numbers are written in their shortest exact form (:func:`fmt`), so a generated file reads like
a hand-written one and regenerating it gives the same bytes.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np
from numpy.typing import NDArray

from redik.lie import quat_from_matrix
from redik.models.builder.link import Link


def fmt(x: float) -> str:
    """Shortest exact text of a float; integers without '.0', tiny round-off as 0."""
    x = float(x)
    if abs(x) < 1e-14:
        return "0"
    if x == round(x) and abs(x) < 1e15:
        return str(int(x))
    return repr(x)


def vec(values: Iterable[float]) -> str:
    """Numbers as an MJCF attribute value: each by :func:`fmt`, separated by spaces."""
    return " ".join(fmt(x) for x in values)


def pose_attrs(T: NDArray[np.float64]) -> str:
    """``pos``/``quat`` attributes of a 4×4 (omitted when zero/identity)."""
    attrs = []
    if np.any(np.abs(T[:3, 3]) >= 1e-14):
        attrs.append(f'pos="{vec(T[:3, 3])}"')
    R = np.where(np.abs(T[:3, :3]) < 1e-14, 0.0, T[:3, :3])
    if not np.array_equal(R, np.eye(3)):
        attrs.append(f'quat="{vec(quat_from_matrix(R))}"')
    return (" " + " ".join(attrs)) if attrs else ""


def document_lines(
    links: list[Link],
    ee: NDArray[np.float64],
    ranges: NDArray[np.float64],
    q_home: NDArray[np.float64],
    radius: float,
    reach: float,
    gains: list[float] | None,
    numerics: dict[str, list[float]],
    texts: dict[str, str],
    name: str,
    floor_height: float,
    comment: str | None,
) -> list[str]:
    """The lines of the MJCF document of ``links``.

    See :mod:`redik.models.builder` for what the scene holds; ``gains`` is ``None`` for a
    model without actuators.
    """
    r = radius
    lines = []
    if comment:
        lines += ["<!--", *("  " + line if line else "" for line in comment.splitlines()), "-->"]
    lines += [
        f'<mujoco model="{name}">',
        '  <compiler angle="radian" autolimits="true"/>',
        '  <option timestep="0.002" integrator="implicitfast"/>',
        f'  <statistic center="0 0 {fmt(round(0.3 * reach, 3))}" extent="{fmt(round(reach, 3))}"/>',
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
        f'    <light name="top" pos="0 0 {fmt(round(3 * reach, 3))}" dir="0 0 -1"/>',
        f'    <geom name="floor" type="plane" pos="0 0 {fmt(floor_height)}"'
        f' size="{fmt(round(2 * reach, 3))} {fmt(round(2 * reach, 3))} 0.05" material="grid"/>',
        f'    <geom name="base" type="cylinder" fromto="0 0 {fmt(floor_height)} 0 0'
        f' {fmt(max(floor_height + r, 0.0))}" size="{fmt(2 * r)}" material="joint"/>',
        f'    <camera name="track" mode="targetbodycom" target="link1"'
        f' pos="{vec(np.round([1.2 * reach, -1.2 * reach, 0.8 * reach], 3))}"/>',
    ]
    indent = "    "
    for i, link in enumerate(links, start=1):
        lower, upper = ranges[i - 1]
        joint_range = f' range="{fmt(lower)} {fmt(upper)}"' if math.isfinite(lower) else ""
        kind = "slide" if link.slide else "hinge"
        anchor = f' pos="{vec(link.anchor)}"' if np.any(link.anchor) else ""
        lines += [
            f'{indent}<body name="link{i}"{pose_attrs(link.pose)} gravcomp="1">',
            f'{indent}  <joint name="joint{i}" type="{kind}"{anchor}'
            f' axis="{vec(link.axis)}"{joint_range}/>',
            f'{indent}  <geom name="joint{i}" type="sphere" size="{fmt(1.25 * r)}"'
            f'{anchor} material="joint"/>',
        ]
        if link.slide:
            travel = upper - lower if math.isfinite(upper) else 0.5 * reach
            axis = link.axis / np.linalg.norm(link.axis)
            tail = link.anchor - travel * axis
            lines.append(
                f'{indent}  <geom name="ram{i}" type="capsule" size="{fmt(0.6 * r)}"'
                f' fromto="{vec(tail)} {vec(link.anchor)}" material="ram"/>'
            )
        if np.linalg.norm(link.next_anchor - link.anchor) > 1e-9:
            material = "" if i % 2 else ' material="link_alt"'
            lines.append(
                f'{indent}  <geom name="link{i}" type="capsule" size="{fmt(r)}"'
                f' fromto="{vec(link.anchor)} {vec(link.next_anchor)}"{material}/>'
            )
        indent += "  "
    lines.append(
        f'{indent}<site name="ee"{pose_attrs(ee)} size="{fmt(round(0.8 * r, 4))}"'
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
            ctrl = f' ctrlrange="{fmt(lower)} {fmt(upper)}"' if math.isfinite(lower) else ""
            lines.append(
                f'    <position name="actuator{i}" joint="joint{i}" kp="{fmt(kp)}"'
                f' dampratio="1"{ctrl}/>'
            )
        lines += ["  </actuator>", ""]
    lines.append("  <custom>")
    for key, data in numerics.items():
        lines.append(f'    <numeric name="{key}" data="{vec(data)}"/>')
    for key, text in texts.items():
        lines.append(f'    <text name="{key}" data="{text}"/>')
    lines += ["  </custom>", "", "  <keyframe>"]
    ctrl = f' ctrl="{vec(q_home)}"' if gains is not None else ""
    lines += [f'    <key name="home" qpos="{vec(q_home)}"{ctrl}/>', "  </keyframe>", "</mujoco>"]
    return lines
