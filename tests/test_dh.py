"""redik.models.dh: forward kinematics against hand-computed poses, and table validation."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from redik.core.exceptions import InvalidConfiguration, InvalidInput, InvalidPose, ModelError
from redik.models import dh


def test_planar_2r_matches_trigonometry(rng):
    l1, l2 = 0.7, 0.4
    rows = [(l1, 0.0, 0.0), (l2, 0.0, 0.0)]
    for q1, q2 in rng.uniform(-math.pi, math.pi, (20, 2)):
        T = dh.forward(rows, [q1, q2])
        x = l1 * math.cos(q1) + l2 * math.cos(q1 + q2)
        y = l1 * math.sin(q1) + l2 * math.sin(q1 + q2)
        c, s = math.cos(q1 + q2), math.sin(q1 + q2)
        np.testing.assert_allclose(T[:3, 3], [x, y, 0.0], atol=1e-12)
        np.testing.assert_allclose(T[:3, :3], [[c, -s, 0], [s, c, 0], [0, 0, 1]], atol=1e-12)


def test_forward_all_returns_every_frame():
    rows = [(1.0, 0.0, 0.0), (1.0, 0.0, 0.0)]
    frames = dh.forward_all(rows, [math.pi / 2, -math.pi / 2])
    assert frames.shape == (3, 4, 4)
    np.testing.assert_allclose(frames[0], np.eye(4))
    np.testing.assert_allclose(frames[1][:3, 3], [0, 1, 0], atol=1e-15)
    np.testing.assert_allclose(frames[2][:3, 3], [1, 1, 0], atol=1e-15)
    with_tool = dh.forward_all(rows, [0.0, 0.0], tool=(0.5, 0.0, 0.0))
    assert with_tool.shape == (4, 4, 4)
    np.testing.assert_allclose(with_tool[-1][:3, 3], [2.5, 0, 0])


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_single_prismatic_row(convention):
    # One prismatic row: d = q + offset along z, then (standard) a along x and the twist α.
    row = dh.DHRow(a=0.2, d=0.1, alpha=math.pi / 2, theta=math.pi / 2, joint="prismatic")
    T = dh.forward([row], [0.3], convention)
    if convention == "standard":
        # Rz(π/2) Tz(0.4) Tx(0.2) Rx(π/2): x → y, so p = (0, 0.2, 0.4).
        np.testing.assert_allclose(T[:3, 3], [0.0, 0.2, 0.4], atol=1e-15)
        np.testing.assert_allclose(T[:3, :3], [[0, 0, 1], [1, 0, 0], [0, 1, 0]], atol=1e-15)
    else:
        # Rx(π/2) Tx(0.2) Rz(π/2) Tz(0.4): z → −y, so p = (0.2, −0.4, 0).
        np.testing.assert_allclose(T[:3, 3], [0.2, -0.4, 0.0], atol=1e-15)
        np.testing.assert_allclose(T[:3, :3], [[0, -1, 0], [0, 0, -1], [1, 0, 0]], atol=1e-15)


def test_revolute_offset_adds_to_q():
    rows = [dh.DHRow(1.0, 0.0, 0.0, theta=0.3)]
    np.testing.assert_allclose(dh.forward(rows, [0.2]), dh.forward([(1.0, 0.0, 0.0)], [0.5]))


def _standard_as_modified(rows: list[dh.DHRow]) -> tuple[list[dh.DHRow], dh.DHRow]:
    """Craig's table of the same arm: row i takes (a_{i-1}, α_{i-1}); the last (a_n, α_n) is
    the tool (T_x and R_x commute, so the products agree term by term)."""
    shifted = [dh.DHRow(0.0, rows[0].d, 0.0, rows[0].theta, rows[0].joint)]
    for previous, row in itertools.pairwise(rows):
        shifted.append(dh.DHRow(previous.a, row.d, previous.alpha, row.theta, row.joint))
    return shifted, dh.DHRow(rows[-1].a, 0.0, rows[-1].alpha)


def test_modified_and_standard_agree_for_an_equivalent_arm(rng):
    joints = ["revolute", "prismatic", "revolute", "revolute", "prismatic", "revolute"]
    rows = [dh.DHRow(*rng.normal(size=4), joint=joint) for joint in joints]
    modified, tool = _standard_as_modified(rows)
    for q in rng.uniform(-2, 2, (20, len(rows))):
        np.testing.assert_allclose(
            dh.forward(modified, q, "modified", tool), dh.forward(rows, q, "standard"), atol=1e-12
        )


def test_planar_2r_in_both_conventions():
    q = [0.3, 0.4]
    standard = dh.forward([(1, 0, 0), (1, 0, 0)], q)
    modified = dh.forward([(0, 0, 0), (1, 0, 0)], q, "modified", tool=(1, 0, 0))
    np.testing.assert_allclose(standard, modified, atol=1e-15)
    expected = [math.cos(0.3) + math.cos(0.7), math.sin(0.3) + math.sin(0.7), 0.0]
    np.testing.assert_allclose(standard[:3, 3], expected, atol=1e-15)


def test_tool_as_matrix_equals_tool_as_row():
    rows = [(0.1, 0.2, 0.3), (0.4, 0.5, 0.6)]
    tool_row = (0.05, 0.1, -0.4, 0.2)
    for convention in ("standard", "modified"):
        as_matrix = dh.row_transform(dh.parse_row(tool_row), 0.0, convention)
        np.testing.assert_allclose(
            dh.forward(rows, [0.7, -0.2], convention, tool=tool_row),
            dh.forward(rows, [0.7, -0.2], convention, tool=as_matrix),
        )


def test_row_forms_are_equivalent():
    as_tuple = dh.parse_rows([(0.1, 0.2, 0.3, 0.4, "prismatic")])
    mapping = {"a": 0.1, "d": 0.2, "alpha": 0.3, "theta": 0.4, "joint": "prismatic"}
    as_mapping = dh.parse_rows([mapping])
    assert as_tuple == as_mapping == (dh.DHRow(0.1, 0.2, 0.3, 0.4, "prismatic"),)
    assert dh.parse_rows([{"a": 1, "d": 0, "alpha": 0}])[0] == dh.DHRow(1.0, 0.0, 0.0)


def test_split_row_recomposes_the_link_transform(rng):
    for convention in ("standard", "modified"):
        for joint in ("revolute", "prismatic"):
            row = dh.DHRow(*rng.normal(size=4), joint=joint)
            pre, post = dh.split_row(row, convention)
            q = 0.37
            motion = dh.rot_z(q) if joint == "revolute" else dh.trans(z=q)
            np.testing.assert_allclose(pre @ motion @ post, dh.row_transform(row, q, convention))


@pytest.mark.parametrize(
    ("rows", "message"),
    [
        ([(1.0, 2.0)], "DH row 0: expected a tuple"),
        ([(0, 0, 0), {"a": 1.0, "d": 0.0}], "DH row 1: expected keys"),
        ([{"a": 1.0, "d": 0.0, "alpha": 0.0, "length": 2}], "unknown \\['length'\\]"),
        ([(0, 0, 0), (0, 0, 0), (1.0, "x", 0.0)], r"DH row 2: DHRow\.d must be a real number"),
        ([(1.0, 0.0, float("nan"))], r"DH row 0: DHRow\.alpha must be finite"),
        ([(1.0, 0.0, 0.0, 0.0, "helical")], r"DH row 0: DHRow\.joint must be 'revolute'"),
        ([3.0], "DH row 0: expected a DHRow, a mapping or a tuple"),
        ([], "at least one row"),
        ({"a": 1, "d": 0, "alpha": 0}, "sequence of DH rows"),
    ],
)
def test_bad_rows_are_rejected(rows, message):
    with pytest.raises(ModelError, match=message):
        dh.parse_rows(rows)


def test_bad_arguments_are_rejected():
    rows = [(1.0, 0.0, 0.0), (1.0, 0.0, 0.0)]
    with pytest.raises(InvalidConfiguration, match=r"shape \(2,\)"):
        dh.forward(rows, [0.0])
    with pytest.raises(InvalidConfiguration, match="finite"):
        dh.forward(rows, [0.0, np.inf])
    with pytest.raises(InvalidInput, match="convention must be 'standard' or 'modified'"):
        dh.forward(rows, [0.0, 0.0], "craig-ish")
    with pytest.raises(InvalidPose):
        dh.forward(rows, [0.0, 0.0], tool=np.ones((4, 4)))
    with pytest.raises(InvalidInput, match="tool must be a 4×4 transform or a DH row"):
        dh.forward(rows, [0.0, 0.0], tool=(1.0, 2.0))
    with pytest.raises(InvalidInput, match=r"DHRow\.joint"):
        dh.DHRow(1.0, 0.0, 0.0, joint="spherical")
    assert dh.parse_convention("MDH") == "modified"


def test_complex_or_string_joint_values_are_refused_not_truncated():
    rows = [(1.0, 0.0, 0.0), (1.0, 0.0, 0.0)]
    for q in ([0.5 + 1j, 0.0], ["0.5", "0"]):
        with pytest.raises(InvalidConfiguration, match="q must hold real numbers"):
            dh.forward(rows, q)
