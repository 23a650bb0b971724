"""Whole-model robots: several frames, floating bases, ball joints, chains cut out of a model."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import redik
from redik.core.exceptions import InvalidInput, ModelError, UnknownFrame
from redik.lie import pose_errors

# A floating torso (free joint) with a ball-jointed head, two 6-joint arms with a finger each
# (slide joints) and a table as an obstacle.
_ARM = """
      <body name="{side}_upper" pos="0 {y} 0.2">
        <joint name="{side}_shoulder_yaw" axis="0 0 1" range="-2 2"/>
        <joint name="{side}_shoulder_pitch" axis="0 1 0" range="-2 2"/>
        <joint name="{side}_shoulder_roll" axis="1 0 0" range="-2 2"/>
        <geom name="{side}_upper_geom" type="capsule" fromto="0 0 0 0.3 0 0" size="0.04"/>
        <body name="{side}_fore" pos="0.3 0 0">
          <joint name="{side}_elbow" axis="0 1 0" range="-2.5 0.5"/>
          <joint name="{side}_wrist_roll" axis="1 0 0" range="-2.5 2.5"/>
          <geom name="{side}_fore_geom" type="capsule" fromto="0 0 0 0.25 0 0" size="0.035"/>
          <body name="{side}_hand" pos="0.25 0 0">
            <joint name="{side}_wrist_yaw" axis="0 0 1" range="-2 2"/>
            <geom name="{side}_hand_geom" type="sphere" size="0.03"/>
            <site name="{side}_ee" pos="0.06 0 0"/>
            <body name="{side}_finger" pos="0.06 0 0">
              <joint name="{side}_finger" type="slide" axis="0 1 0" range="0 0.04"/>
              <geom type="box" size="0.01 0.01 0.01" contype="0" conaffinity="0"/>
            </body>
          </body>
        </body>
      </body>"""

TORSO_XML = f"""
<mujoco model="two_arm_torso">
  <compiler angle="radian"/>
  <worldbody>
    <geom name="table" type="box" pos="0.4 0.25 0.95" size="0.15 0.15 0.02"/>
    <body name="torso" pos="0 0 1">
      <freejoint name="base"/>
      <geom name="torso_geom" type="box" size="0.1 0.15 0.25"/>
      <body name="head" pos="0 0 0.35">
        <joint name="neck" type="ball" range="0 1.2"/>
        <geom name="head_geom" type="sphere" size="0.08"/>
        <site name="gaze" pos="0.1 0 0"/>
      </body>
      {_ARM.format(side="left", y=0.22)}
      {_ARM.format(side="right", y=-0.22)}
    </body>
  </worldbody>
  <keyframe>
    <key name="home" qpos="0 0 1 1 0 0 0  1 0 0 0  0 0.3 0 -1 0 0 0.01  0 0.3 0 -1 0 0 0.01"/>
  </keyframe>
</mujoco>
"""


@pytest.fixture(scope="module")
def model():
    return mujoco.MjModel.from_xml_string(TORSO_XML)


@pytest.fixture()
def whole(model):
    return redik.Robot(model, joints="all")


def _reachable_poses(robot, frames, rng):
    """Poses of ``frames`` at one random configuration near home (reachable together)."""
    q_target = robot.clip(robot.integrate(robot.home, 0.4 * rng.standard_normal(robot.dof)))
    return [robot.fk(q_target, frame) for frame in frames]


def test_whole_model_sizes_and_names(whole):
    assert whole.joint_types[:2] == ("free", "ball")
    assert (whole.nq, whole.dof) == (7 + 4 + 14, 6 + 3 + 14)
    assert not whole.flat and not whole.is_chain
    assert whole.dof_names[:4] == ("base:x", "base:y", "base:z", "base:wx")
    assert whole.dof_joints[6:9] == ("neck",) * 3
    assert np.all(np.isinf(whole.lower[:9])) and np.all(np.isfinite(whole.lower[9:]))
    assert whole.revolute[:9].tolist() == [False] * 3 + [True] * 6
    np.testing.assert_allclose(np.linalg.norm(whole.home[3:7]), 1.0)
    assert whole.ee is None
    with pytest.raises(UnknownFrame, match="names no end-effector") as error:
        whole.fk(whole.home)
    listed = (
        "sites ['gaze', 'left_ee', 'right_ee']; leaf bodies ['head', 'left_finger', 'right_finger']"
    )
    assert listed in str(error.value)
    assert whole.suggested_frames() == [
        "gaze", "left_ee", "right_ee", "head", "left_finger", "right_finger"
    ]  # fmt: skip


def test_joint_subsets_by_pattern(model):
    arms = redik.Robot(model, joints=["left_*", "right_*"], fixed=["*finger*"])
    assert arms.dof == arms.nq == 12 and arms.flat
    assert arms.joint_names[0] == "left_shoulder_yaw"
    with pytest.raises(ModelError, match=r"no joint .* matches 'elbow'"):
        redik.Robot(model, joints=["elbow"])
    with pytest.raises(ModelError, match="no joint left to move"):
        redik.Robot(model, joints=["left_*"], fixed=["left_*"])
    with pytest.raises(InvalidInput, match="joints must be 'all'"):
        redik.Robot(model, joints=5)
    with pytest.raises(InvalidInput, match=r"joints \['left_elbow'\] are named both"):
        redik.Robot(model, joints=["left_elbow", "right_elbow"], fixed=["left_elbow"])
    # A pattern that also covers a fixed joint is how a subset is carved out: no error.
    assert "left_elbow" not in redik.Robot(model, joints="left_*", fixed="left_elbow").joint_names
    with pytest.raises(ModelError, match=r"fixed: no joint .* matches 'nek'"):
        redik.Robot(model, joints="all", fixed=["nek"])
    with pytest.raises(UnknownFrame):
        redik.Robot(model, joints="all").chain("nowhere")


def test_a_ball_joint_on_a_chain_is_an_error_not_frozen(model):
    with pytest.raises(ModelError, match="ball joint 'neck'"):
        redik.Robot(model, ee="gaze")
    with pytest.raises(ModelError, match="no hinge or slide joint"):
        redik.Robot(model, ee="gaze", fixed=["neck"])
    chain = redik.Robot(model, ee="left_ee")  # the free joint is the (held) base
    assert chain.joint_names == (
        "left_shoulder_yaw",
        "left_shoulder_pitch",
        "left_shoulder_roll",
        "left_elbow",
        "left_wrist_roll",
        "left_wrist_yaw",
    )


def test_integrate_and_difference_are_inverse(whole):
    rng = np.random.default_rng(0)
    for _ in range(20):
        q = whole.random_q(rng)
        dq = 0.5 * rng.standard_normal(whole.dof)
        q2 = whole.integrate(q, dq)
        np.testing.assert_allclose(np.linalg.norm(q2[3:7]), 1.0, atol=1e-12)
        np.testing.assert_allclose(np.linalg.norm(q2[7:11]), 1.0, atol=1e-12)
        np.testing.assert_allclose(whole.difference(q, q2), dq, atol=1e-9)
    # Flat robots keep plain vector arithmetic.
    arms = redik.Robot(whole.model, joints=["left_*"])
    q = arms.random_q(rng)
    np.testing.assert_array_equal(arms.integrate(q, np.ones(arms.dof)), q + 1.0)


@pytest.mark.parametrize("frame", ["left_ee", "gaze", "geom:right_fore_geom", "torso"])
def test_jacobian_matches_finite_differences_on_the_manifold(whole, frame):
    """Column i of the world Jacobian is d/dh of the frame's pose at q ⊕ h eᵢ."""
    rng = np.random.default_rng(1)
    q = whole.random_q(rng)
    J = whole.jacobian(q, frame, reference="world")
    T = whole.fk(q, frame)
    h = 1e-6
    for i in range(whole.dof):
        step = np.zeros(whole.dof)
        step[i] = h
        T_h = whole.fk(whole.integrate(q, step), frame)
        dp = (T_h[:3, 3] - T[:3, 3]) / h
        dR = T_h[:3, :3] @ T[:3, :3].T
        omega = np.array([dR[2, 1] - dR[1, 2], dR[0, 2] - dR[2, 0], dR[1, 0] - dR[0, 1]]) / (2 * h)
        np.testing.assert_allclose(dp, J[:3, i], atol=1e-5)
        np.testing.assert_allclose(omega, J[3:, i], atol=1e-5)


def test_geom_frames(whole):
    q = whole.random_q(2)
    T = whole.fk(q, "left_hand_geom")
    data = whole.state.data
    geom = mujoco.mj_name2id(whole.model, mujoco.mjtObj.mjOBJ_GEOM, "left_hand_geom")
    np.testing.assert_allclose(T[:3, 3], data.geom_xpos[geom])
    np.testing.assert_allclose(T[:3, :3], data.geom_xmat[geom].reshape(3, 3))
    with pytest.raises(UnknownFrame, match=r"no geom named 'geom:nothing'.*geoms: \['table'"):
        whole.frame("geom:nothing")
    with pytest.raises(UnknownFrame, match="named by a string"):
        whole.frame(["left_ee"])


def test_two_hands_at_priority_0_posture_at_priority_1(whole):
    rng = np.random.default_rng(3)
    T_left, T_right = _reachable_poses(whole, ["left_ee", "right_ee"], rng)
    tasks = [
        redik.FrameTask("left_ee", target=T_left, priority=0),
        redik.FrameTask("right_ee", target=T_right, priority=0),
        redik.PostureTask(priority=1),
    ]
    result = redik.solve_problem(redik.Problem(whole, tasks), whole.home)
    assert result.success, result.message
    assert result.q.shape == (whole.nq,)
    for frame, T in (("left_ee", T_left), ("right_ee", T_right)):
        p_err, r_err = pose_errors(whole.fk(result.q, frame), T)
        assert p_err < 1e-6 and r_err < 1e-5
    assert whole.within_limits(result.q)
    np.testing.assert_allclose(np.linalg.norm(result.q[3:7]), 1.0, atol=1e-12)


def test_posture_reaches_a_floating_configuration(whole):
    """The posture error across the free and ball joints is mj_differentiatePos's."""
    q_nominal = whole.clip(whole.integrate(whole.home, 0.3 * np.ones(whole.dof)))
    problem = redik.Problem(whole, [redik.PostureTask(q_nominal, priority=0)])
    result = redik.solve_problem(problem, whole.home)
    assert result.success
    np.testing.assert_allclose(whole.difference(q_nominal, result.q), 0.0, atol=1e-8)


def test_posture_refuses_a_zero_quaternion(whole):
    q = whole.home.copy()
    q[7:11] = 0.0  # the neck's ball joint
    with pytest.raises(redik.InvalidConfiguration, match=r"q_nominal\[7:11\] is a zero quaternion"):
        redik.PostureTask(q).bind(whole)
    task = redik.PostureTask().bind(whole)
    with pytest.raises(redik.InvalidConfiguration, match="zero quaternion"):
        task.set_target(q)
    np.testing.assert_array_equal(task.q_nominal, whole.home)


def test_posture_jacobian_is_exact_along_the_error_only(whole):
    """q ⊖ r across the free and ball joints: d/dh of e(q ⊕ h δ) is J_r⁻¹(e) δ, not δ, but
    equals δ along δ = −e (the posture task's identity Jacobian gives exact descent)."""
    rng = np.random.default_rng(11)
    reference, q = whole.random_q(rng), whole.random_q(rng)
    e = whole.difference(reference, q)
    h = 1e-6

    def derivative(direction):
        return (whole.difference(reference, whole.integrate(q, h * direction)) - e) / h

    np.testing.assert_allclose(derivative(-e), -e, atol=1e-5)
    jacobian = np.array([derivative(column) for column in np.eye(whole.dof)]).T
    assert np.abs(jacobian - np.eye(whole.dof)).max() > 0.1  # not the identity far from r
    np.testing.assert_allclose(jacobian[:3, :3], np.eye(3), atol=1e-5)  # base position: exact


def test_step_is_a_tangent_vector(whole):
    problem = redik.Problem(whole, [redik.PositionTask("left_ee", target=[0.3, 0.4, 1.3])])
    dq = problem.step(whole.home)
    assert dq.shape == (whole.dof,)
    with pytest.raises(redik.InvalidConfiguration, match=r"shape \(25,\)"):
        problem.step(np.zeros(whole.dof))
    q = whole.home.copy()
    q[3:7] = 0.0
    with pytest.raises(redik.InvalidConfiguration, match="zero quaternion"):
        redik.solve_problem(problem, q)
    for bad in ("home", [*whole.home[:-1], "x"], whole.home + 0j):
        with pytest.raises(redik.InvalidConfiguration, match=r"q must .*real numbers"):
            whole.fk(bad, "left_ee")
    with pytest.raises(redik.InvalidConfiguration, match=r"qpos must .*real numbers"):
        whole.q_of("qpos")


def test_ball_joint_limit_keeps_every_iterate_inside_the_cone(whole):
    """The neck's range is a 1.2 rad cone; the posture asks for 1.5 rad from the identity."""
    import mink

    target = whole.home.copy()
    target[7:11] = [np.cos(0.75), np.sin(0.75), 0.0, 0.0]
    posture = [redik.PostureTask(target, priority=0)]
    limit = redik.BallJointLimit(margin=0.05)
    with pytest.raises(InvalidInput, match="not bound"):
        limit.angles_at(target)
    limit.bind(whole)

    def _neck_angle(q):
        return float(limit.angles_at(q)[0])

    free = redik.solve_problem(
        redik.Problem(whole, posture, [redik.ConfigurationLimit()]), whole.home
    )
    assert _neck_angle(free.q) == pytest.approx(1.5)
    # The default limits hold the cone (no margin): a box alone would not.
    default = redik.Problem(whole, posture)
    assert [type(limit).__name__ for limit in default.limits] == [
        "ConfigurationLimit",
        "BallJointLimit",
    ]
    held = redik.solve_problem(default, whole.home)
    assert _neck_angle(held.q) == pytest.approx(1.2, abs=1e-6)
    assert max(_neck_angle(q) for q in held.history) <= 1.2
    assert [type(limit).__name__ for limit in redik.Problem(whole, posture, []).limits] == []
    # mink's ConfigurationLimit has the same row but none at the identity: its first step
    # leaves the cone.
    theirs = redik.Problem(
        whole, posture, [redik.ConfigurationLimit(), mink.ConfigurationLimit(whole.model, gain=1.0)]
    )
    assert max(_neck_angle(q) for q in redik.solve_problem(theirs, whole.home).history) > 1.4
    result = redik.solve_problem(
        redik.Problem(whole, posture, [redik.ConfigurationLimit(), limit]), whole.home
    )
    assert limit.joint_names == ("neck",)
    assert _neck_angle(result.q) == pytest.approx(1.15, abs=1e-6)
    assert max(_neck_angle(q) for q in result.history) <= 1.15 + 1e-9
    # Online steps from outside the cone pull the joint back.
    q = target.copy()
    problem = redik.Problem(whole, [redik.PostureTask(target, priority=0)], [limit])
    for _ in range(5):
        q = whole.integrate(q, problem.step(q))
    assert _neck_angle(q) == pytest.approx(1.15, abs=1e-6)
    with pytest.raises(InvalidInput, match="leaves no cone"):
        redik.BallJointLimit(margin=1.3).bind(whole)
    with pytest.raises(InvalidInput, match="margin must be a number"):
        redik.BallJointLimit(margin="wide")


def test_velocity_limit_by_joint_bounds_every_dof_of_a_ball_joint(whole):
    limit = redik.VelocityLimit({"neck": 0.5, "left_elbow": 1.0}).bind(whole)
    assert limit.max_velocity[6:9].tolist() == [0.5] * 3
    assert limit.max_velocity[whole.dof_names.index("left_elbow")] == 1.0
    assert np.isinf(limit.max_velocity[:6]).all()
    for bad in ("fast", {"neck": "fast"}, [1.0, "fast"]):
        with pytest.raises(InvalidInput, match="max_velocity must be a number"):
            redik.VelocityLimit(bad).bind(whole)


def test_manipulability_needs_a_chain(whole):
    with pytest.raises(InvalidInput, match=r"robot.chain\(frame\)"):
        redik.Problem(whole, [redik.ManipulabilityTask("left_ee")])


def test_solve_pose_on_a_whole_model_moves_only_the_chain(whole):
    rng = np.random.default_rng(4)
    q0 = whole.random_q(rng)
    q0 = whole.clip(q0)
    chain = whole.chain("left_ee", q0)
    T = chain.fk(chain.clip(chain.random_q(rng)))
    result = redik.solve_pose(whole, T, q0, frame="left_ee", seed=0)
    assert result.success, result.message
    assert result.q.shape == (whole.nq,) and result.history.shape[1] == whole.nq
    moved = np.isin(whole.qpos_indices, chain.qpos_indices)
    np.testing.assert_array_equal(result.q[~moved], q0[~moved])
    p_err, r_err = pose_errors(whole.fk(result.q, "left_ee"), T)
    assert p_err < 1e-6 and r_err < 1e-5


def test_solve_pose_on_a_whole_model_follows_the_held_joints_between_calls(whole):
    # The chain and its compiled solver are kept between calls; moving a held joint (the
    # floating base) must not reuse the old base pose.
    rng = np.random.default_rng(6)
    q0 = whole.clip(whole.random_q(rng))
    for shift in (0.0, 0.1, 0.1, 0.0):
        q = q0.copy()
        q[0] += shift  # the base's x
        chain = whole.chain("left_ee", q)
        T = chain.fk(chain.clip(chain.random_q(rng)))
        for solved in (
            redik.solve_pose(whole, T, q, frame="left_ee", seed=0),
            redik.solve_all(whole, T, 20, seed=0, frame="left_ee", q0=q)[0],
        ):
            assert solved.success, solved.message
            assert solved.q[0] == q[0]
            p_err, r_err = pose_errors(whole.fk(solved.q, "left_ee"), T)
            assert p_err < 1e-6 and r_err < 1e-5


def test_chain_of_a_whole_model_runs_the_fast_paths(whole):
    rng = np.random.default_rng(5)
    q = whole.clip(whole.random_q(rng))
    chain = whole.chain("right_ee", q)
    assert chain.is_chain and chain.dof == 6
    # The held joints (base, neck, left arm) stay at q's values in the chain's model state.
    np.testing.assert_allclose(whole.fk(q, "right_ee"), chain.fk(chain.q_of()))
    targets = np.array([chain.fk(chain.clip(chain.random_q(rng))) for _ in range(4)])
    batch = redik.solve_batch(chain, targets, seed=0, engine="local", workers=1)
    assert batch.success_rate == 1.0
    with pytest.raises(redik.UnknownFrame, match=r"names no end-effector.*'left_ee'"):
        redik.solve_batch(whole, targets)  # no frame: the chain is not named
    whole_with_ee = redik.Robot(whole.model, "right_ee", joints="all")
    with pytest.raises(InvalidInput, match=r"whole-model.*robot\.chain\('right_ee'\)"):
        redik.solve_batch(whole_with_ee, targets)
    np.testing.assert_allclose(whole.embed(chain, batch.q[0], q)[:7], q[:7])
    qpos = whole.full_qpos(q)
    np.testing.assert_array_equal(chain.q_of(qpos), qpos[chain.qpos_indices])
    with pytest.raises(redik.InvalidConfiguration, match=r"model\.nq"):
        chain.q_of(q[:5])
    # A chain with joints this robot holds cannot be embedded into it.
    arms = redik.Robot(whole.model, joints=["left_*"], fixed=["left_elbow"])
    with pytest.raises(InvalidInput, match=r"moves joints \['left_elbow'\]"):
        arms.embed(whole.chain("left_ee", q), np.zeros(6))
    held = arms.chain("left_ee")  # the held elbow stays out of the chain
    assert "left_elbow" not in held.joint_names and held.dof == 5
    np.testing.assert_array_equal(arms.embed(held, np.zeros(5))[:5], np.zeros(5))


def _collision_problem(model, with_limit: bool, minimum_distance: float = 0.01):
    arm = redik.Robot(model, joints=["left_*"], fixed=["*finger*"])
    # The hand is asked to a point inside the table: only the limit stops it.
    target = redik.PositionTask("left_ee", target=[0.4, 0.25, 0.95], priority=0)
    limits = [redik.ConfigurationLimit()]
    if with_limit:
        limits.append(
            redik.CollisionAvoidanceLimit(
                [(["left_hand", "left_fore", "left_upper"], ["table"])],
                minimum_distance=minimum_distance,
                detection_distance=0.1,
            )
        )
    problem = redik.Problem(arm, [target, redik.PostureTask(priority=1)], limits)
    return arm, problem


def test_collision_limit_keeps_the_margin_the_unconstrained_solution_violates(model):
    arm, free = _collision_problem(model, with_limit=False)
    _, guarded = _collision_problem(model, with_limit=True)
    checker = redik.CollisionAvoidanceLimit([(["left_hand", "left_fore", "left_upper"], ["table"])])
    checker.bind(arm)
    unconstrained = redik.solve_problem(free, arm.home)
    assert checker.minimum_distance_at(unconstrained.q)[0] < 0.0  # it collides
    constrained = redik.solve_problem(guarded, arm.home)
    distance, pair = checker.minimum_distance_at(constrained.q)
    assert distance >= 0.01 - 1e-3, pair
    assert not constrained.success  # the target is inside the table
    # Every iterate kept the margin, not only the last.
    assert min(checker.minimum_distance_at(q)[0] for q in constrained.history) >= 0.01 - 1e-3


def test_collision_limit_default_pairs_and_bad_input(model):
    whole = redik.Robot(model, joints="all")
    limit = redik.CollisionAvoidanceLimit().bind(whole)
    names = {
        tuple(mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) for g in pair)
        for pair in limit.pairs
    }
    assert ("table", "torso_geom") in names  # an obstacle
    assert ("left_hand_geom", "right_hand_geom") in names  # self-collision
    assert ("torso_geom", "left_upper_geom") not in names  # parent and child
    assert all(None not in pair for pair in names)  # the contype-0 finger boxes are out
    with pytest.raises(ModelError, match="no geom or body named 'nothing'"):
        redik.CollisionAvoidanceLimit([(["nothing"], ["table"])]).bind(whole)
    with pytest.raises(InvalidInput, match="detection_distance"):
        redik.CollisionAvoidanceLimit(minimum_distance=0.1, detection_distance=0.05)
    with pytest.raises(InvalidInput, match="gain"):
        redik.CollisionAvoidanceLimit(gain=0.0)
    with pytest.raises(InvalidInput, match="minimum_distance must be a number, got 'a'"):
        redik.CollisionAvoidanceLimit(minimum_distance="a")
    with pytest.raises(InvalidInput, match="minimum_distance must be finite and >= 0"):
        redik.CollisionAvoidanceLimit(minimum_distance=-0.01)
    with pytest.raises(InvalidInput, match="geom_pairs must be a list of pairs"):
        redik.CollisionAvoidanceLimit("table")
    with pytest.raises(InvalidInput, match=r"geom_pairs\[0\] must be a pair"):
        redik.CollisionAvoidanceLimit([5])
    with pytest.raises(InvalidInput, match=r"geom_pairs\[0\]\[0\]: a geom group is a non-empty"):
        redik.CollisionAvoidanceLimit([([], ["table"])]).bind(whole)
    with pytest.raises(ModelError, match="no geom or body matches 'x\\*'"):
        redik.CollisionAvoidanceLimit([(["x*"], ["table"])]).bind(whole)
    # Pairs that all drop out (parent and child; nothing moves them apart) are a mistake.
    for pairs in ([(["torso"], ["left_upper"])], [(["table"], ["table"])]):
        with pytest.raises(ModelError, match="leave no pair to check"):
            redik.CollisionAvoidanceLimit(pairs).bind(whole)


def _geom_pair_names(limit):
    model = limit.robot.model
    return {
        tuple(mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) for g in pair)
        for pair in limit.pairs
    }


def test_collision_pairs_follow_mujocos_exclude_and_filterparent():
    hands = ("left_hand_geom", "right_hand_geom")
    parent_child = ("torso_geom", "left_upper_geom")
    excluded = TORSO_XML.replace(
        "</worldbody>",
        '</worldbody><contact><exclude body1="right_hand" body2="left_hand"/></contact>',
    )
    robot = redik.Robot(mujoco.MjModel.from_xml_string(excluded), joints="all")
    names = _geom_pair_names(redik.CollisionAvoidanceLimit().bind(robot))
    assert hands not in names and ("left_hand_geom", "right_fore_geom") in names
    with pytest.raises(ModelError, match="leave no pair"):
        redik.CollisionAvoidanceLimit([(["left_hand"], ["right_hand"])]).bind(robot)
    unfiltered = TORSO_XML.replace(
        "<worldbody>", '<option><flag filterparent="disable"/></option><worldbody>'
    )
    robot = redik.Robot(mujoco.MjModel.from_xml_string(unfiltered), joints="all")
    names = _geom_pair_names(redik.CollisionAvoidanceLimit().bind(robot))
    assert parent_child in names and hands in names


def test_mink_tasks_and_mink_interop_on_a_floating_base(whole):
    import mink

    rng = np.random.default_rng(6)
    T_left, T_right = _reachable_poses(whole, ["left_ee", "right_ee"], rng)
    left = mink.FrameTask("left_ee", "site", position_cost=1.0, orientation_cost=1.0)
    left.set_target(mink.SE3.from_matrix(T_left))
    tasks = [left, redik.FrameTask("right_ee", target=T_right), redik.PostureTask(priority=1)]
    result = redik.solve_problem(redik.Problem(whole, tasks), whole.home)
    assert result.success, result.message
    assert pose_errors(whole.fk(result.q, "left_ee"), T_left)[0] < 1e-6

    # A redik posture inside mink: the same error as mink's own PostureTask (tangent space),
    # which leaves the free joint out (redik's keeps it; cost 0 there does as mink).
    configuration = mink.Configuration(whole.model)
    configuration.update(whole.full_qpos(whole.random_q(rng)))
    ours = redik.PostureTask(whole.home).bind(whole)
    theirs = mink.PostureTask(whole.model, cost=1.0)
    theirs.set_target(whole.full_qpos(whole.home))
    e_ours, e_theirs = ours.compute_error(configuration), theirs.compute_error(configuration)
    np.testing.assert_allclose(e_ours[6:], e_theirs[6:], atol=1e-12)
    assert np.abs(e_ours[:6]).max() > 0.1 and not e_theirs[:6].any()
    J_ours, J_theirs = ours.compute_jacobian(configuration), theirs.compute_jacobian(configuration)
    np.testing.assert_allclose(J_ours[6:], J_theirs[6:], atol=1e-12)


@pytest.mark.parametrize(
    ("frame", "kind", "mink_name"),
    [("left_ee", "site", "left_ee"), ("geom:right_fore_geom", "geom", "right_fore_geom")],
)
def test_frame_task_on_sites_and_geoms_is_minks(whole, frame, kind, mink_name):
    import mink

    rng = np.random.default_rng(10)
    configuration = mink.Configuration(whole.model)
    T = whole.fk(whole.random_q(rng), frame)
    ours = redik.FrameTask(frame, target=T).bind(whole)
    theirs = mink.FrameTask(mink_name, kind, position_cost=1.0, orientation_cost=1.0)
    theirs.set_target(mink.SE3.from_matrix(T))
    for _ in range(3):
        configuration.update(whole.full_qpos(whole.random_q(rng)))
        e = theirs.compute_error(configuration)
        assert np.abs(e).max() > 0.1
        np.testing.assert_allclose(ours.compute_error(configuration), e, atol=1e-12)
        np.testing.assert_allclose(
            ours.compute_jacobian(configuration), theirs.compute_jacobian(configuration),
            atol=1e-12,
        )  # fmt: skip


def test_solve_all_on_a_whole_model_returns_whole_configurations(whole):
    chain = whole.chain("right_ee", whole.home)
    T = chain.fk(chain.clip(chain.home + 0.4))
    results = redik.solve_all(whole, T, n_starts=6, seed=0, frame="right_ee")
    assert results
    for result in results:
        assert result.q.shape == (whole.nq,)
        assert pose_errors(whole.fk(result.q, "right_ee"), T)[0] < 1e-6
        np.testing.assert_array_equal(result.q[:7], whole.home[:7])  # the base held


def test_solve_all_and_solve_pose_hold_the_other_joints_at_the_same_q0(whole):
    rng = np.random.default_rng(7)
    q0 = whole.clip(whole.integrate(whole.home, 0.3 * rng.standard_normal(whole.dof)))
    chain = whole.chain("right_ee", q0)  # the held joints at q0: its poses are q0's
    T = chain.fk(chain.clip(chain.q_of() + 0.3))
    held = ~np.isin(whole.qpos_indices, chain.qpos_indices)
    single = redik.solve_pose(whole, T, q0, frame="right_ee", seed=0)
    assert single.success, single.message
    np.testing.assert_array_equal(single.q[held], q0[held])
    results = redik.solve_all(whole, T, n_starts=4, seed=0, frame="right_ee", q0=q0)
    assert results
    for result in results:
        np.testing.assert_array_equal(result.q[held], q0[held])
        assert pose_errors(whole.fk(result.q, "right_ee"), T)[0] < 1e-6
    # q0 is the first start: its solution (the one solve_pose finds from it) is among them.
    assert min(np.abs(r.q - single.q).max() for r in results) < 1e-3


BALL_ARM_XML = """
<mujoco model="ball_arm">
  <compiler angle="radian"/>
  <default><joint armature="0.01"/></default>
  <worldbody>
    <body name="l1" pos="0 0 0.1">
      <joint name="j1" axis="0 0 1" range="-3 3"/>
      <geom type="capsule" fromto="0 0 0 0 0 0.3" size="0.03"/>
      <body name="l2" pos="0 0 0.3">
        <joint name="j2" axis="0 1 0" range="-2 2"/>
        <joint name="wrist_ball" type="ball"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
        <body name="l3" pos="0.3 0 0">
          <joint name="j3" axis="0 1 0" range="-2 2"/>
          <joint name="j4" axis="1 0 0" range="-2 2"/>
          <joint name="j5" axis="0 1 0" range="-2 2"/>
          <joint name="j6" axis="0 0 1" range="-2 2"/>
          <joint name="j7" axis="1 0 0" range="-2 2"/>
          <geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.03"/>
          <site name="ee" pos="0.2 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def test_explore_cli_holds_a_ball_joint_only_when_asked(tmp_path, capsys):
    from redik.apps.cli import main

    path = tmp_path / "ball_arm.xml"
    path.write_text(BALL_ARM_XML)
    out = tmp_path / "out"
    common = [str(path), "--frames", "0", "--starts", "8", "--spacing", "0.3", "--out", str(out)]
    assert main(["explore", *common]) == 2
    assert "ball joint 'wrist_ball'" in capsys.readouterr().err
    assert main(["explore", *common, "--fixed", "wrist_ball"]) == 0
    assert "dimension 1" in capsys.readouterr().out
    assert (out / "samples.npz").is_file()


def test_explore_self_motion_on_a_whole_model_uses_the_chain(model):
    from redik.solvers.redundancy import explore_self_motion

    ball = redik.Robot(mujoco.MjModel.from_xml_string(BALL_ARM_XML), joints="all")
    T = ball.fk(ball.home, "ee")
    motion = explore_self_motion(ball, T, frame="ee", seed=0, n_starts=8, max_samples=200)
    assert "wrist_ball" not in motion.joint_names and len(motion) > 0


def test_collision_rows_are_the_distance_gradient(whole):
    """Row k is −∂d/∂Δq of its pair, checked by finite differences through q ⊕ Δq."""
    limit = redik.CollisionAvoidanceLimit(
        [(["left_hand_geom"], ["table"])], minimum_distance=0.0, detection_distance=0.5, gain=1.0
    ).bind(whole)
    rng = np.random.default_rng(8)
    checked = 0
    for _ in range(20):
        q = whole.clip(whole.integrate(whole.home, 0.3 * rng.standard_normal(whole.dof)))
        whole.state.update(q)
        rows = limit.inequalities(None, None)
        if rows is None:
            continue
        G, h = rows
        d = limit.distances()[0]
        assert G.shape == (1, whole.dof) and h[0] == pytest.approx(d)
        step = 1e-6
        gradient = []
        for i in range(whole.dof):
            whole.state.update(whole.integrate(q, step * np.eye(whole.dof)[i]))
            gradient.append((limit.distances()[0] - d) / step)
        np.testing.assert_allclose(-G[0], gradient, atol=1e-4)
        checked += 1
    assert checked >= 3


def test_online_control_of_a_floating_robot_respects_velocity_and_position_limits(whole):
    rng = np.random.default_rng(9)
    T_left, T_right = _reachable_poses(whole, ["left_ee", "right_ee"], rng)
    tasks = [
        redik.FrameTask("left_ee", target=T_left, gain=0.5),
        redik.FrameTask("right_ee", target=T_right, gain=0.5),
        redik.PostureTask(priority=1),
    ]
    dt, speed = 0.01, 2.0
    problem = redik.Problem(whole, tasks, [redik.ConfigurationLimit(), redik.VelocityLimit(speed)])
    q = whole.home.copy()
    for _ in range(400):
        dq = problem.step(q, dt)
        assert np.abs(dq).max() <= speed * dt + 1e-9
        q = whole.integrate(q, dq)
        assert whole.within_limits(q)
    for frame, T in (("left_ee", T_left), ("right_ee", T_right)):
        assert pose_errors(whole.fk(q, frame), T)[0] < 1e-4


def test_chain_of_a_model_with_unnamed_and_bracketed_joints():
    xml = TORSO_XML.replace('<freejoint name="base"/>', "<freejoint/>").replace(
        'name="right_elbow"', 'name="right_elbow[1]"'
    )
    robot = redik.Robot(mujoco.MjModel.from_xml_string(xml), joints="all")
    assert robot.joint_names[0] == "joint0"
    chain = robot.chain("right_ee")
    assert "right_elbow[1]" in chain.joint_names and chain.dof == 6


def test_joint_space_terms_are_computed_once_per_target_not_per_step(whole, monkeypatch):
    """On a whole model the posture's factor ``α w²d²`` was recomputed (allocated) per task
    every step; it changes only with the task's target or cost."""
    posture = redik.PostureTask(priority=1)
    left = redik.FrameTask("left_ee", target=whole.fk(whole.home, "left_ee"))
    problem = redik.Problem(whole, [left, posture])
    calls = []
    original = posture.diagonal_terms
    monkeypatch.setattr(posture, "diagonal_terms", lambda: calls.append(1) or original())
    rng = np.random.default_rng(3)
    q = whole.clip(whole.integrate(whole.home, 0.2 * rng.standard_normal(whole.dof)))
    steps = [problem.step(q) for _ in range(4)]
    assert len(calls) == 1
    # The gradient is still the posture's α w²d² ⊙ (q ⊖ r): a lone posture level steps to r.
    alone = redik.Problem(whole, [redik.PostureTask(whole.home, priority=0)], limits=[])
    np.testing.assert_allclose(whole.integrate(q, alone.step(q)), whole.home, atol=1e-5)
    posture.set_target(q)
    problem.step(q)
    assert len(calls) == 2
    np.testing.assert_allclose(steps[0], steps[-1])
