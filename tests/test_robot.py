"""Robot: chain extraction, FK, Jacobians (all references) against finite differences, errors."""

from __future__ import annotations

import time
from concurrent.futures import ThreadPoolExecutor

import mujoco
import numpy as np
import pytest

import redik
from redik import lie
from redik.core.exceptions import InvalidConfiguration, InvalidInput, ModelError, UnknownFrame
from redik.solvers import dls
from redik.solvers.cache import solver_cache

from .conftest import ARM_XML


def numeric_jacobian(robot: redik.Robot, q: np.ndarray, frame, reference: str) -> np.ndarray:
    """Central differences of FK on SE(3), step 1e-6 (error O(h²) ≈ 1e-12)."""
    h = 1e-6
    J = np.empty((6, robot.dof))
    for i in range(robot.dof):
        dq = np.zeros(robot.dof)
        dq[i] = h
        T_plus, T_minus = robot.fk(q + dq, frame), robot.fk(q - dq, frame)
        if reference == "space":
            J[:, i] = lie.se3_log(T_plus @ lie.inverse(T_minus)) / (2 * h)
        elif reference == "body":
            J[:, i] = lie.se3_log(lie.inverse(T_minus) @ T_plus) / (2 * h)
        else:
            J[:3, i] = (T_plus[:3, 3] - T_minus[:3, 3]) / (2 * h)
            J[3:, i] = lie.so3_log(T_plus[:3, :3] @ T_minus[:3, :3].T) / (2 * h)
    return J


def test_chain_joints_limits_and_home(arm):
    assert arm.joint_names == ("j1", "j2", "j3", "j4", "j5", "j6", "j7")
    assert arm.dof == 7
    assert arm.ee.kind == "site" and arm.ee.name == "ee"
    assert arm.lower[3] == -np.inf and arm.upper[3] == np.inf
    np.testing.assert_allclose(arm.lower[[0, 2]], [-2.8, 0.0])
    np.testing.assert_array_equal(arm.revolute, [1, 1, 0, 1, 1, 1, 1])
    np.testing.assert_allclose(arm.home, [0.1, 0.2, 0.05, -0.3, 0.4, 0.5, 0.6])
    # Off-chain joints stay at their home values.
    assert arm.state.data.qpos[7] == pytest.approx(0.02)
    fingertip = redik.Robot(arm.model, ee="fingertip")
    assert fingertip.joint_names[-1] == "grip"


def test_fk_matches_an_independent_product_of_transforms(arm, rng):
    """Rebuild the chain by hand from the MJCF numbers: body offsets, joint motions, site."""

    def T(pos=(0, 0, 0), R=None):
        return lie.make_pose(np.eye(3) if R is None else R, np.array(pos, dtype=float))

    def euler(a, b, c):  # MuJoCo's default eulerseq 'xyz' is intrinsic
        return lie.so3_exp([a, 0, 0]) @ lie.so3_exp([0, b, 0]) @ lie.so3_exp([0, 0, c])

    def rot(axis, angle):
        axis = np.asarray(axis, float)
        return T(R=lie.so3_exp(angle * axis / np.linalg.norm(axis)))

    base_R = lie.matrix_from_quat([0.9238795, 0, 0, 0.3826834])
    for _ in range(50):
        q = arm.random_q(rng)
        expected = (
            T((0.1, -0.2, 0.3), base_R)
            @ rot([0, 0, 1], q[0])
            @ T((0, 0, 0.3))
            @ rot([0, 1, 0], q[1])
            @ T((0.3, 0, 0), euler(0.3, 0, 0))
            @ T((q[2], 0, 0))
            @ T((0.2, 0, 0))
            @ rot([0, 1, 0], q[3])
            @ T((0.25, 0, 0))
            @ rot([1, 0, 0], q[4])
            @ rot([0, 1, 0], q[5])
            @ T((0.05, 0, 0.02))
            @ rot([0.6, 0, 0.8], q[6])
            @ T((0.1, 0.01, 0.02), euler(0.1, 0.2, 0.3))
        )
        np.testing.assert_allclose(arm.fk(q), expected, atol=1e-7)  # MJCF quat has 7 digits


@pytest.mark.parametrize("reference", ["space", "body", "world"])
@pytest.mark.parametrize("frame", [None, "fingertip", "l5", "l2"])
def test_jacobian_matches_finite_differences(arm, rng, reference, frame):
    for _ in range(10):
        q = arm.random_q(rng)
        np.testing.assert_allclose(
            arm.jacobian(q, frame, reference),
            numeric_jacobian(arm, q, frame, reference),
            atol=1e-8,
        )


def test_jacobian_references_are_related_by_the_adjoint(arm, rng):
    q = arm.random_q(rng)
    T = arm.fk(q)
    np.testing.assert_allclose(
        arm.jacobian(q, reference="space"),
        lie.adjoint(T) @ arm.jacobian(q, reference="body"),
        atol=1e-12,
    )


def test_random_q_within_limits_and_reproducible(arm):
    samples = arm.random_q(7, size=500)
    assert samples.shape == (500, 7)
    assert all(arm.within_limits(q) for q in samples)
    np.testing.assert_array_equal(samples, arm.random_q(7, size=500))
    assert np.all(np.abs(samples[:, 3]) <= np.pi)  # unlimited hinge sampled in [−π, π]


def test_urdf_loads(tmp_path):
    urdf = """<robot name="two_link">
      <link name="base"/><link name="l1"/><link name="l2"/>
      <joint name="a" type="revolute"><parent link="base"/><child link="l1"/>
        <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-1" upper="1"/></joint>
      <joint name="b" type="revolute"><parent link="l1"/><child link="l2"/>
        <origin xyz="0.5 0 0"/><axis xyz="0 0 1"/><limit lower="-2" upper="2"/></joint>
    </robot>"""
    path = tmp_path / "two_link.urdf"
    path.write_text(urdf)
    robot = redik.Robot.from_file(path, ee="l2")
    assert robot.joint_names == ("a", "b")
    np.testing.assert_allclose(robot.upper, [1, 2])
    T = robot.fk([np.pi / 2, 0.0])
    np.testing.assert_allclose(T[:3, 3], [0.0, 0.5, 0.1], atol=1e-12)


def test_bad_inputs_raise_redik_errors(arm, tmp_path):
    with pytest.raises(InvalidConfiguration, match=r"shape \(7,\)"):
        arm.fk(np.zeros(6))
    with pytest.raises(InvalidConfiguration, match="NaN"):
        arm.fk(np.full(7, np.nan))
    with pytest.raises(InvalidConfiguration, match="NaN"):
        arm.jacobian([0, 0, 0, np.inf, 0, 0, 0])
    with pytest.raises(UnknownFrame, match="no site or body or geom named 'nowhere'"):
        arm.fk(np.zeros(7), frame="nowhere")
    with pytest.raises(InvalidInput, match="reference"):
        arm.jacobian(np.zeros(7), reference="hybrid")
    with pytest.raises(ModelError, match="not found"):
        redik.Robot.from_file(tmp_path / "missing.xml")
    with pytest.raises(ModelError, match="could not"):
        redik.Robot.from_xml_string("<mujoco><worldbody><body></mujoco>")
    with pytest.raises(UnknownFrame):
        redik.Robot.from_xml_string(ARM_XML, ee="wrist_camera")
    with pytest.raises(ModelError, match="no hinge or slide joint"):
        redik.Robot(mujoco.MjModel.from_xml_string(ARM_XML), ee="floating")
    # every redik error is catchable at the root
    with pytest.raises(redik.RedikError):
        arm.fk(np.zeros(3))


@pytest.mark.parametrize("scene", redik.list_scenes())
def test_every_scene_jacobian_matches_finite_differences(scene, rng):
    robot = redik.load(scene)
    for reference in ("space", "body", "world"):
        for _ in range(3):
            q = robot.random_q(rng)
            np.testing.assert_allclose(
                robot.jacobian(q, reference=reference),
                numeric_jacobian(robot, q, None, reference),
                atol=1e-8,
            )


def test_builders_pass_their_options_on():
    rows = [(1.0, 0.0, 0.0), (1.0, 0.0, 0.0)]
    thin = redik.Robot.from_dh(rows, radius=0.01)
    thick = redik.Robot.from_dh(rows, radius=0.2)
    capsule = int(mujoco.mjtGeom.mjGEOM_CAPSULE)
    for robot, radius in ((thin, 0.01), (thick, 0.2)):
        sizes = robot.model.geom_size[robot.model.geom_type == capsule, 0]
        np.testing.assert_allclose(sizes, radius)
    assert redik.Robot.from_dh(rows, custom={"l1": 1.0}).model.numeric("l1").data[0] == 1.0
    with pytest.raises(TypeError):
        redik.Robot.from_dh(rows, bogus_option=1)
    screws = np.array([[0, 0, 1, 0, 0, 0], [0, 0, 1, 0, -1, 0]], dtype=float).T
    M = np.eye(4)
    M[0, 3] = 2.0
    assert redik.Robot.from_screws(screws, M, actuators=False).model.nu == 0
    with pytest.raises(TypeError):
        redik.Robot.from_screws(screws, M, bogus_option=1)


@pytest.mark.parametrize(
    ("q", "named"),
    [
        (np.array(["0"] * 7), "dtype <U1"),  # was parsed as numbers
        (np.zeros(7) + 1j, "dtype complex128"),  # was cast, dropping the imaginary part
        (np.zeros(7, dtype=object), "dtype object"),  # was accepted
        ([0, 0, [1], 0, 0, 0, 0], "real numbers"),  # was a raw numpy ValueError
        ([None] * 7, "dtype object"),
        ([[0.0] * 7], r"got shape \(1, 7\)"),
        (np.zeros(0), r"got shape \(0,\)"),
        ([0, 0, 0, np.inf, 0, 0, 0], "NaN or inf"),
    ],
)
def test_fk_and_jacobian_refuse_non_real_q_naming_it(arm, q, named):
    for call in (arm.fk, arm.jacobian):
        with pytest.raises(InvalidConfiguration, match=named):
            call(q)


def test_periodic_joints_have_one_definition_every_solver_uses():
    from redik.kinematics.chain import Chain
    from redik.solvers.redundancy import PostureDistance
    from redik.solvers.redundancy.corrector import Corrector

    spec = mujoco.MjSpec.from_file(str(redik.models.scene_path("panda")))
    spec.joints[0].limited = mujoco.mjtLimited.mjLIMITED_FALSE  # unlimited
    spec.joints[2].range = [-np.pi, np.pi]  # exactly one turn
    spec.joints[4].range = [-3.0, 3.0]  # less than a turn
    robot = redik.Robot(spec.compile())
    expected = np.array([True, False, True, False, False, False, False])
    np.testing.assert_array_equal(robot.periodic, expected)
    np.testing.assert_array_equal(redik.load("ur5e").periodic, True)  # ±2π
    # The kernel wraps the limited ones (an unlimited hinge never leaves its range).
    np.testing.assert_array_equal(Chain.from_robot(robot).kernel_arrays()[-1], expected)
    corrector = Corrector(robot, robot.fk(robot.home), robot.ee)
    np.testing.assert_array_equal(corrector.periodic, expected)
    # A turn of a periodic joint is no posture change; of any other joint it is.
    posture = PostureDistance(robot.home)
    for joint, periodic in enumerate(expected):
        q = robot.home.copy()
        q[joint] += 2.0 * np.pi
        assert (posture.value(robot, q, None) < 1e-12) == periodic


@pytest.fixture
def switch_after_each_kernel(monkeypatch):
    """Hand the GIL to another thread right after every compiled dls solve returns (the
    moment a shared output buffer would be overwritten before it is copied), so a race
    between threads shows up on every run rather than once in a while. Yields the number of
    kernel calls so far (a list of one), to check that the patch point is the one used."""
    calls = [0]
    solve_one = dls.solve_one

    def solve_then_switch(*args):
        result = solve_one(*args)
        calls[0] += 1
        time.sleep(1e-4)
        return result

    monkeypatch.setattr(dls, "solve_one", solve_then_switch)
    yield calls


@pytest.mark.parametrize("whole", [False, True], ids=["chain", "whole-model"])
def test_one_robot_solves_from_several_threads_as_in_series(whole, switch_after_each_kernel):
    robot = redik.load("panda")
    if whole:  # a whole-model robot solves on a chain it keeps in its solver cache
        robot = redik.Robot(robot.model, joints="all")
    targets = [robot.fk(q) for q in robot.random_q(3, size=48)]

    def solve(i: int) -> redik.IKResult:
        return redik.solve_pose(robot, targets[i], seed=i, frame="ee")

    with ThreadPoolExecutor(4) as pool:
        threaded = list(pool.map(solve, range(len(targets))))
    assert switch_after_each_kernel[0] >= len(targets)
    serial = [solve(i) for i in range(len(targets))]
    assert len(solver_cache(robot)) == 1
    for a, b in zip(threaded, serial, strict=True):
        assert a.status == b.status and a.iterations == b.iterations
        np.testing.assert_array_equal(a.q, b.q)
        np.testing.assert_array_equal(a.history, b.history)
        np.testing.assert_array_equal(a.error_history, b.error_history)


TWO_FINGERS = """<mujoco><worldbody>
  <body name="palm"><joint name="wrist" axis="0 0 1"/><geom size="0.05"/>
    <body name="finger_a" pos="0.1 0 0"><joint name="a" axis="0 1 0"/><geom size="0.02"/>
      <site name="tip_a" pos="0.05 0 0"/></body>
    <body name="finger_b" pos="-0.1 0 0"><joint name="b" axis="0 1 0"/><geom size="0.02"/></body>
  </body>
  <body name="table" pos="1 0 0"><geom type="box" size="0.2 0.2 0.02"/></body>
</worldbody></mujoco>"""


def test_a_model_without_an_ee_site_loads_whole_and_names_frames_where_used():
    robot = redik.Robot.from_xml_string(TWO_FINGERS)
    assert robot.ee is None and not robot.is_chain
    assert robot.joint_names == ("wrist", "a", "b")
    # Sites, then leaf bodies; the table is a leaf no joint moves.
    assert robot.suggested_frames() == ["tip_a", "finger_a", "finger_b"]
    with pytest.raises(UnknownFrame, match=r"sites \['tip_a'\]; leaf bodies \['finger_a', 'finger"):
        robot.chain()
    chain = robot.chain("finger_b")
    assert chain.is_chain and chain.joint_names == ("wrist", "b") and chain.ee.name == "finger_b"
    assert chain.chain().joint_names == chain.joint_names  # a chain's default frame is its own
    named = redik.Robot.from_xml_string(TWO_FINGERS, ee="tip_a")
    assert named.is_chain and named.joint_names == ("wrist", "a")


def test_a_site_named_ee_is_the_natural_frame():
    robot = redik.Robot.from_xml_string(TWO_FINGERS.replace("tip_a", "ee"))
    assert robot.is_chain and robot.ee.name == "ee" and robot.joint_names == ("wrist", "a")
    whole = redik.Robot.from_xml_string(TWO_FINGERS.replace("tip_a", "ee"), joints="all")
    assert not whole.is_chain and whole.ee.name == "ee"
