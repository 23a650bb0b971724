"""redik.models.builder: the generated MJCF reproduces the DH / product-of-exponentials FK."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest
from scipy.linalg import expm

from redik.core.exceptions import InvalidInput, InvalidPose, ModelError
from redik.models import dh
from redik.models.builder import dh_to_mjcf, read_dh, read_screws, screws_to_mjcf

SAMPLES = 60


def site_pose(model: mujoco.MjModel, data: mujoco.MjData, q: np.ndarray) -> np.ndarray:
    data.qpos[:] = q
    mujoco.mj_kinematics(model, data)
    site = model.site("ee").id
    T = np.eye(4)
    T[:3, :3] = data.site_xmat[site].reshape(3, 3)
    T[:3, 3] = data.site_xpos[site]
    return T


def max_fk_error(xml: str, reference, qs: np.ndarray) -> float:
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    assert model.nq == qs.shape[1]
    return max(float(np.max(np.abs(site_pose(model, data, q) - reference(q)))) for q in qs)


def random_table(rng: np.random.Generator, joints: list[str]) -> list[dh.DHRow]:
    return [
        dh.DHRow(*rng.uniform(-0.5, 0.5, 2), *rng.uniform(-math.pi, math.pi, 2), joint=joint)
        for joint in joints
    ]


# ---------------------------------------------------------------------------------------
# DH


@pytest.mark.parametrize("convention", ["standard", "modified"])
@pytest.mark.parametrize(
    "joints",
    [
        ["revolute"] * 6,
        ["prismatic", "revolute", "prismatic", "revolute", "revolute"],
        ["prismatic"],
    ],
    ids=["revolute", "mixed", "single_prismatic"],
)
@pytest.mark.parametrize("with_tool", [False, True], ids=["no_tool", "tool"])
def test_dh_model_matches_dh_forward(rng, convention, joints, with_tool):
    rows = random_table(rng, joints)
    tool = dh.DHRow(*rng.uniform(-0.3, 0.3, 4)) if with_tool else None
    xml = dh_to_mjcf(rows, convention, tool=tool)
    qs = rng.uniform(-math.pi, math.pi, (SAMPLES, len(rows)))
    error = max_fk_error(xml, lambda q: dh.forward(rows, q, convention, tool), qs)
    assert error <= 1e-9


def test_tool_as_matrix(rng):
    rows = random_table(rng, ["revolute"] * 3)
    R, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    tool = np.eye(4)
    tool[:3, :3] = R * np.sign(np.linalg.det(R))
    tool[:3, 3] = [0.1, -0.2, 0.3]
    qs = rng.uniform(-3, 3, (SAMPLES, 3))
    xml = dh_to_mjcf(rows, "modified", tool=tool)
    assert max_fk_error(xml, lambda q: dh.forward(rows, q, "modified", tool), qs) <= 1e-9


def test_dh_model_structure():
    rows = [(0.0, 0.3, math.pi / 2), (0.5, 0.0, 0.0, 0.0, "prismatic"), (0.4, 0.0, 0.0)]
    limits = [(-1.0, 1.0), (0.0, 0.2), None]
    xml = dh_to_mjcf(rows, limits=limits, home=[0.5, 0.1, 0.0], name="arm", custom={"l": 0.4})
    model = mujoco.MjModel.from_xml_string(xml)
    assert model.nq == model.nu == 3
    assert [model.joint(i).name for i in range(3)] == ["joint1", "joint2", "joint3"]
    assert list(model.jnt_type) == [
        mujoco.mjtJoint.mjJNT_HINGE,
        mujoco.mjtJoint.mjJNT_SLIDE,
        mujoco.mjtJoint.mjJNT_HINGE,
    ]
    assert list(model.jnt_limited) == [1, 1, 0]
    np.testing.assert_array_equal(model.jnt_range[:2], [[-1.0, 1.0], [0.0, 0.2]])
    np.testing.assert_array_equal(model.actuator_ctrlrange[:2], [[-1.0, 1.0], [0.0, 0.2]])
    assert list(model.actuator_ctrllimited) == [1, 1, 0]
    np.testing.assert_array_equal(model.key("home").qpos, [0.5, 0.1, 0.0])
    assert model.actuator_gainprm[:, 0].min() > 0
    # No contacts: links must not collide with each other (nor with the floor).
    assert not np.any(model.geom_contype) and not np.any(model.geom_conaffinity)
    assert model.numeric("l").data.tolist() == [0.4]
    assert model.ncam == 1 and model.nlight == 1


def test_read_dh_round_trips(rng):
    rows = tuple(random_table(rng, ["revolute", "prismatic", "revolute"]))
    tool = dh.DHRow(0.1, 0.2, 0.3, 0.4)
    for convention in ("standard", "modified"):
        model = mujoco.MjModel.from_xml_string(dh_to_mjcf(rows, convention, tool=tool))
        read_rows, read_convention, read_tool = read_dh(model)
        assert read_rows == rows
        assert read_convention == convention
        np.testing.assert_array_equal(read_tool, dh.row_transform(tool, 0.0, convention))


def test_servos_track_a_command():
    """Issue #7's use: position servos drive the arm to a commanded posture headlessly."""
    rows = [(0.0, 0.3, math.pi / 2), (0.4, 0.0, 0.0), (0.3, 0.0, 0.0)]
    model = mujoco.MjModel.from_xml_string(dh_to_mjcf(rows, limits=[(-2, 2)] * 3))
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("home").id)
    target = np.array([0.5, -0.4, 0.8])
    data.ctrl[:] = target
    for _ in range(int(3.0 / model.opt.timestep)):
        mujoco.mj_step(model, data)
    np.testing.assert_allclose(data.qpos, target, atol=1e-3)


def test_actuators_can_be_left_out():
    model = mujoco.MjModel.from_xml_string(dh_to_mjcf([(1, 0, 0)], actuators=False))
    assert model.nu == 0 and model.key("home").qpos.tolist() == [0.0]


@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        ({"limits": [(-1, 1)]}, InvalidInput, "one \\(lower, upper\\) pair per joint"),
        ({"limits": [(1, -1), None]}, InvalidInput, "expected lower < upper"),
        ({"limits": [(0, np.inf), None]}, InvalidInput, "two finite values or unlimited"),
        ({"limits": [(0, "x"), None]}, InvalidInput, "must be a pair"),
        ({"limits": [(0.1, 1), None]}, None, None),
        ({"limits": [(-1, 1), None], "home": [2.0, 0.0]}, InvalidInput, "home\\[0\\] = 2.0"),
        ({"home": [0.0]}, InvalidInput, "home must be 2 finite joint values"),
        ({"radius": -0.1}, InvalidInput, "radius must be a positive"),
        ({"custom": {"redik_dh_a": 1.0}}, InvalidInput, "not starting with 'redik_'"),
        ({"custom": {"l1": []}}, InvalidInput, "non-empty list"),
        ({"custom": {"two words": 1.0}}, InvalidInput, "custom numeric name"),
        ({"name": "my robot"}, InvalidInput, "name must be an identifier"),
        ({"comment": "a -- b"}, InvalidInput, "must not contain '--'"),
        ({"convention": "euler"}, InvalidInput, "convention must be"),
        ({"tool": np.diag([1.0, 1.0, 2.0, 1.0])}, InvalidPose, "not a rotation"),
    ],
)
def test_dh_bad_input(kwargs, error, message):
    rows = [(1.0, 0.0, 0.0), (1.0, 0.0, 0.0)]
    if error is None:  # a valid limit excluding 0 moves the default home to mid-range
        model = mujoco.MjModel.from_xml_string(dh_to_mjcf(rows, **kwargs))
        assert model.key("home").qpos.tolist() == [0.55, 0.0]
        return
    with pytest.raises(error, match=message):
        dh_to_mjcf(rows, **kwargs)


def test_dh_bad_rows_name_the_row():
    with pytest.raises(ModelError, match="DH row 1"):
        dh_to_mjcf([(1.0, 0.0, 0.0), (1.0, 0.0)])


# ---------------------------------------------------------------------------------------
# Product of exponentials


def screw_matrix(S: np.ndarray) -> np.ndarray:
    """[S] ∈ se(3) of a screw (ω, v)."""
    w, v = S[:3], S[3:]
    X = np.zeros((4, 4))
    X[:3, :3] = [[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]]
    X[:3, 3] = v
    return X


def poe_space(S: np.ndarray, M: np.ndarray, q: np.ndarray) -> np.ndarray:
    """T = e^[S1]q1 ⋯ e^[Sn]qn M (MR Eq. 4.14), with scipy's matrix exponential."""
    T = np.eye(4)
    for i, q_i in enumerate(q):
        T = T @ expm(screw_matrix(S[:, i]) * q_i)
    return T @ M


def poe_body(B: np.ndarray, M: np.ndarray, q: np.ndarray) -> np.ndarray:
    """T = M e^[B1]q1 ⋯ e^[Bn]qn (MR Eq. 4.16)."""
    T = M.copy()
    for i, q_i in enumerate(q):
        T = T @ expm(screw_matrix(B[:, i]) * q_i)
    return T


def ur5_example() -> tuple[np.ndarray, np.ndarray]:
    """Modern Robotics Example 4.5 (UR5): space screws and home pose, metres."""
    W1, W2, L1, L2, H1, H2 = 0.109, 0.082, 0.425, 0.392, 0.089, 0.095
    S = np.array(
        [
            [0, 0, 1, 0, 0, 0],
            [0, 1, 0, -H1, 0, 0],
            [0, 1, 0, -H1, 0, L1],
            [0, 1, 0, -H1, 0, L1 + L2],
            [0, 0, -1, -W1, L1 + L2, 0],
            [0, 1, 0, H2 - H1, 0, L1 + L2],
        ],
        dtype=float,
    ).T
    M = np.array(
        [[-1, 0, 0, L1 + L2], [0, 0, 1, W1 + W2], [0, 1, 0, H1 - H2], [0, 0, 0, 1]], dtype=float
    )
    return S, M


def test_ur5_example_pose():
    """The book's worked answer: q = (0, −π/2, 0, 0, π/2, 0)."""
    S, M = ur5_example()
    model = mujoco.MjModel.from_xml_string(screws_to_mjcf(S, M))
    T = site_pose(model, mujoco.MjData(model), np.array([0, -np.pi / 2, 0, 0, np.pi / 2, 0]))
    expected = [[0, -1, 0, 0.095], [1, 0, 0, 0.109], [0, 0, 1, 0.988], [0, 0, 0, 1]]
    np.testing.assert_allclose(T, expected, atol=1e-12)


def test_ur5_space_screws(rng):
    S, M = ur5_example()
    qs = rng.uniform(-math.pi, math.pi, (SAMPLES, 6))
    assert max_fk_error(screws_to_mjcf(S, M), lambda q: poe_space(S, M, q), qs) <= 1e-9


def test_ur5_body_screws(rng):
    S, M = ur5_example()
    B = np.linalg.inv(adjoint_mr(M)) @ S  # B = [Ad_{M⁻¹}] S
    qs = rng.uniform(-math.pi, math.pi, (SAMPLES, 6))
    xml = screws_to_mjcf(B, M, frame="body")
    assert max_fk_error(xml, lambda q: poe_body(B, M, q), qs) <= 1e-9
    np.testing.assert_allclose(read_screws(mujoco.MjModel.from_xml_string(xml))[0], S, atol=1e-12)


def adjoint_mr(T: np.ndarray) -> np.ndarray:
    """[Ad_T] in MR's (ω, v) order."""
    R, p = T[:3, :3], T[:3, 3]
    hat_p = screw_matrix(np.r_[p, 0, 0, 0])[:3, :3]
    return np.block([[R, np.zeros((3, 3))], [hat_p @ R, R]])


def random_screws(rng: np.random.Generator, kinds: str) -> np.ndarray:
    columns = []
    for kind in kinds:
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        if kind == "R":
            columns.append(np.r_[direction, -np.cross(direction, rng.uniform(-0.5, 0.5, 3))])
        else:
            columns.append(np.r_[0.0, 0.0, 0.0, direction])
    return np.array(columns).T


def random_pose(rng: np.random.Generator) -> np.ndarray:
    R, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    T = np.eye(4)
    T[:3, :3] = R * np.sign(np.linalg.det(R))
    T[:3, 3] = rng.uniform(-0.5, 0.5, 3)
    return T


@pytest.mark.parametrize("frame", ["space", "body"])
def test_random_screws_with_prismatic_joints(rng, frame):
    screws = random_screws(rng, "RPRRPR")
    M = random_pose(rng)
    reference = poe_space if frame == "space" else poe_body
    qs = rng.uniform(-2, 2, (SAMPLES, screws.shape[1]))
    xml = screws_to_mjcf(screws, M, frame, limits=[(-2, 2)] * 6)
    assert max_fk_error(xml, lambda q: reference(screws, M, q), qs) <= 1e-9
    model = mujoco.MjModel.from_xml_string(xml)
    hinge, slide = mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE
    assert list(model.jnt_type) == [hinge, slide, hinge, hinge, slide, hinge]


def test_read_screws_requires_screws_and_read_dh_requires_a_table():
    S, M = ur5_example()
    poe_model = mujoco.MjModel.from_xml_string(screws_to_mjcf(S, M))
    dh_model = mujoco.MjModel.from_xml_string(dh_to_mjcf([(1.0, 0.0, 0.0)]))
    np.testing.assert_array_equal(read_screws(poe_model)[1], M)
    with pytest.raises(ModelError, match="carries no DH table"):
        read_dh(poe_model)
    with pytest.raises(ModelError, match="carries no screw axes"):
        read_screws(dh_model)


@pytest.mark.parametrize(
    ("column", "message"),
    [
        ([0, 0, 1, 0, 0, 0.3], "screw column 1 has pitch"),
        ([0, 0, 2, 0, 0, 0], "screw column 1: a revolute axis needs ‖ω‖ = 1"),
        ([0, 0, 0, 0, 0, 2], "screw column 1: a prismatic axis"),
        ([0, 0, 0, 0, 0, 0], "screw column 1: a prismatic axis"),
    ],
)
def test_bad_screws_name_the_column(column, message):
    S = np.array([[0, 0, 1, 0, 0, 0], column], dtype=float).T
    with pytest.raises(ModelError, match=message):
        screws_to_mjcf(S, np.eye(4))


def test_bad_screw_arguments():
    S, M = ur5_example()
    with pytest.raises(InvalidInput, match=r"shape \(6, n\).*transpose"):
        screws_to_mjcf(S[:, :3].T, M)
    with pytest.raises(InvalidInput, match="frame must be 'space' or 'body'"):
        screws_to_mjcf(S, M, frame="world")
    with pytest.raises(InvalidInput, match="finite"):
        screws_to_mjcf(np.full((6, 1), np.nan), M)
    with pytest.raises(InvalidPose):
        screws_to_mjcf(S, M[:3])
