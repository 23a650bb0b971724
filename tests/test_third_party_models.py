"""Third-party models from the package index: Baxter (bimanual URDF) and G1 (humanoid URDF).

Skipped when ``example-robot-data`` is not installed (the ``models`` extra).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import redik
from redik.apps.trajectory import CartesianPath, follow_path
from redik.lie import make_pose, pose_errors

pytest.importorskip("cmeel")

DOWN = np.diag([1.0, -1.0, -1.0])
ARM_BODIES = ["left_*", "right_*"]


def _load(name, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # Baxter's .DAE meshes are dropped with a warning
        path = name if "/" in str(name) else redik.models.example_robot_data(name)
        return redik.models.loading.load_model(path, **options)


@pytest.fixture(scope="module")
def baxter():
    model = _load("baxter", meshes=False)
    return redik.Robot(model, joints=["left_[sew][0-9]", "right_[sew][0-9]"])


@pytest.fixture(scope="module")
def g1():
    return redik.load("example-robot-data:g1", joints="all", floating_base=True)


def _arm_collisions(**options):
    return redik.CollisionAvoidanceLimit(
        [(["left_*"], ["right_*"]), (ARM_BODIES, ["head", "screen", "sonar_ring"])],
        minimum_distance=0.01,
        **options,
    )


def test_baxter_pose_ik_moves_one_arm_only(baxter):
    T = make_pose(DOWN, [0.7, 0.3, 0.1])
    result = redik.solve_pose(baxter, T, frame="left_gripper", seed=0)
    assert result.success, result.message
    right = [i for i, name in enumerate(baxter.joint_names) if name.startswith("right")]
    np.testing.assert_array_equal(result.q[right], baxter.home[right])


def test_baxter_two_priority_stack_and_two_hand_stack(baxter):
    T_left = make_pose(DOWN, [0.75, 0.2, 0.0])
    T_right = make_pose(DOWN, [0.75, -0.2, 0.0])
    one_hand = redik.Problem(
        baxter, [redik.FrameTask("left_gripper", target=T_left), redik.PostureTask(priority=1)]
    )
    result = redik.solve_problem(one_hand, baxter.home)
    assert result.success
    right = [i for i, name in enumerate(baxter.joint_names) if name.startswith("right")]
    # The posture (priority 1) holds the arm that has no task at home.
    np.testing.assert_allclose(result.q[right], baxter.home[right], atol=1e-9)

    collisions = _arm_collisions()
    tasks = [
        redik.FrameTask("left_gripper", target=T_left),
        redik.FrameTask("right_gripper", target=T_right),
        redik.PostureTask(priority=1),
    ]
    result = redik.solve_problem(
        redik.Problem(baxter, tasks, [redik.ConfigurationLimit(), collisions]), baxter.home
    )
    assert result.success, result.message
    for frame, T in (("left_gripper", T_left), ("right_gripper", T_right)):
        p_err, r_err = pose_errors(baxter.fk(result.q, frame), T)
        assert p_err < 1e-6 and r_err < 1e-5
    assert collisions.minimum_distance_at(result.q)[0] >= 0.01 - 1e-6


def test_baxter_collision_limit_binds_where_the_free_solution_collides(baxter):
    tasks = [
        redik.FrameTask("left_gripper", target=make_pose(DOWN, [0.75, 0.05, 0.0])),
        redik.FrameTask("right_gripper", target=make_pose(DOWN, [0.75, -0.05, 0.0])),
        redik.PostureTask(priority=1),
    ]
    checker = _arm_collisions().bind(baxter)
    free = redik.solve_problem(redik.Problem(baxter, tasks), baxter.home)
    assert checker.minimum_distance_at(free.q)[0] < 0.0
    guarded = redik.Problem(baxter, tasks, [redik.ConfigurationLimit(), _arm_collisions()])
    result = redik.solve_problem(guarded, baxter.home)
    assert min(checker.minimum_distance_at(q)[0] for q in result.history) >= 0.01 - 1e-6


def test_baxter_carries_a_box_along_a_path(baxter):
    """Both hands follow a line 15 cm up, the right hand at a fixed offset from the left."""
    start = make_pose(DOWN, [0.75, 0.15, 0.0])
    offset = make_pose(np.eye(3), [0.0, 0.3, 0.0])  # right gripper in the left's frame
    path = CartesianPath([start, make_pose(DOWN, [0.75, 0.15, 0.15])], [0.0, 1.0], "quintic")
    left = redik.FrameTask("left_gripper", target=start)
    right = redik.FrameTask("right_gripper", target=start @ offset)
    problem = redik.Problem(
        baxter,
        [left, right, redik.PostureTask(priority=1)],
        [redik.ConfigurationLimit(), _arm_collisions()],
    )

    def solver(T, q):
        left.set_target(T)
        right.set_target(T @ offset)
        return redik.solve_problem(problem, q)

    q0 = redik.solve_problem(problem, baxter.home).q
    trajectory = follow_path(baxter, path, q0, solver, rate=20.0, frame="left_gripper")
    assert trajectory.success.all() and trajectory.continuous
    assert trajectory.position_error.max() < 1e-6
    for q, T in zip(trajectory.q, trajectory.targets, strict=True):
        assert pose_errors(baxter.fk(q, "right_gripper"), T @ offset)[0] < 1e-6


def test_baxter_self_motion_of_one_arm_with_the_other_held(baxter):
    from redik.solvers.redundancy import explore_self_motion

    q = baxter.home.copy()
    q[:7] = [0.3, -0.5, 0.2, 1.0, 0.0, 0.5, 0.0]  # the right arm somewhere else
    left = baxter.chain("left_gripper", q)
    T = left.fk(np.array([0.2, -0.4, -0.3, 1.2, 0.3, 0.6, 0.1]))
    motion = explore_self_motion(left, T, seed=0, n_starts=8, max_samples=400)
    assert motion.dimension == 1 and len(motion) > 0
    assert motion.joint_names == tuple(
        f"left_{j}" for j in ("s0", "s1", "e0", "e1", "w0", "w1", "w2")
    )
    for sample in motion.samples[:: max(len(motion) // 10, 1)]:
        assert pose_errors(left.fk(sample), T)[0] < 1e-6
    # The held right arm is where q put it.
    np.testing.assert_allclose(left.state.data.qpos[baxter.qpos_indices[:7]], q[:7])


def test_urdfs_have_no_actuators_so_no_simulation(baxter):
    from redik.apps.sim import actuator_indices

    assert baxter.model.nu == 0
    with pytest.raises(redik.ModelError, match="has no actuator"):
        actuator_indices(baxter)


def test_g1_two_hands_with_feet_held_and_no_collision(g1):
    assert g1.joint_types[0] == "free" and (g1.nq, g1.dof) == (36, 35)
    feet = {f: g1.fk(g1.home, f) for f in ("left_ankle_roll_link", "right_ankle_roll_link")}
    hands = {
        "left_rubber_hand": make_pose(np.eye(3), [0.35, 0.12, 0.15]),
        "right_rubber_hand": make_pose(np.eye(3), [0.35, -0.12, 0.15]),
    }
    targets = {**hands, **feet}
    arms = ["left_shoulder_*", "left_elbow*", "left_wrist*"]
    arms += [a.replace("left", "right") for a in arms]
    collisions = redik.CollisionAvoidanceLimit(
        [(arms, ["torso_link", "pelvis*", "*hip*", "*knee*", "head_link"])],
        minimum_distance=0.01,
        detection_distance=0.08,
    )
    tasks = [redik.FrameTask(f, target=T) for f, T in targets.items()]
    problem = redik.Problem(
        g1, [*tasks, redik.PostureTask(priority=1)], [redik.ConfigurationLimit(), collisions]
    )
    result = redik.solve_problem(problem, g1.home)
    assert result.success, result.message
    for frame, T in targets.items():
        p_err, r_err = pose_errors(g1.fk(result.q, frame), T)
        assert p_err < 1e-6 and r_err < 1e-5
    assert np.linalg.norm(result.q[:3]) > 0.01  # the floating base moved
    np.testing.assert_allclose(np.linalg.norm(result.q[3:7]), 1.0, atol=1e-12)
    assert g1.within_limits(result.q)
    assert collisions.minimum_distance_at(result.q)[0] >= 0.01 - 1e-6
    free = redik.solve_problem(redik.Problem(g1, [*tasks, redik.PostureTask(priority=1)]), g1.home)
    assert free.success and collisions.minimum_distance_at(free.q)[0] < 0.0  # shoulder in torso

    # A path: both hands rise 10 cm, the feet still held; warm-started QP solves.
    up = make_pose(np.eye(3), [0.0, 0.0, 0.1])
    path = CartesianPath([hands["left_rubber_hand"], up @ hands["left_rubber_hand"]], [0.0, 1.0])
    right_offset = np.linalg.inv(hands["left_rubber_hand"]) @ hands["right_rubber_hand"]

    def solver(T, q):
        tasks[0].set_target(T)
        tasks[1].set_target(T @ right_offset)
        return redik.solve_problem(problem, q)

    trajectory = follow_path(g1, path, result.q, solver, rate=10.0, frame="left_rubber_hand")
    assert trajectory.success.all() and trajectory.continuous, trajectory.summary()
    assert trajectory.q.shape == (11, g1.nq)


def test_g1_frame_errors_and_jacobians_are_minks(g1):
    """On the floating base: FrameTask's error and Jacobian equal mink's FrameTask's at the
    same mink.Configuration (nv columns) and on redik's own state (dof columns, here = nv)."""
    import mink

    from redik.tasks.kinematics import KinematicState

    rng = np.random.default_rng(7)
    configuration = mink.Configuration(g1.model)
    state = KinematicState.for_robot(g1)
    for frame in ("left_rubber_hand", "pelvis", "right_ankle_roll_link"):
        for _ in range(3):
            q, q_target = g1.random_q(rng), g1.random_q(rng)
            T = g1.fk(q_target, frame)
            ours = redik.FrameTask(frame, target=T).bind(g1)
            theirs = mink.FrameTask(frame, "body", position_cost=1.0, orientation_cost=1.0)
            theirs.set_target(mink.SE3.from_matrix(T))
            configuration.update(g1.full_qpos(q))
            e, J = theirs.compute_error(configuration), theirs.compute_jacobian(configuration)
            assert np.abs(e).max() > 0.1  # far from the target: the log-map Jacobian matters
            np.testing.assert_allclose(ours.compute_error(configuration), e, atol=1e-12)
            np.testing.assert_allclose(ours.compute_jacobian(configuration), J, atol=1e-12)
            state.update(q)
            e_state, J_state = ours.error_and_jacobian(state)
            np.testing.assert_allclose(e_state, e, atol=1e-12)
            np.testing.assert_allclose(J_state, J, atol=1e-12)


def test_g1_hand_chain_runs_compiled_dls(g1):
    chain = g1.chain("left_rubber_hand")
    assert chain.joint_names[0] == "waist_yaw_joint" and chain.flat
    T = chain.fk(chain.clip(chain.home + 0.3))
    result = redik.solve_pose(chain, T, seed=0)
    assert result.success and result.method == "dls"


# (source, name, floating base, joints, fixed, frames): arms with fingers, a bimanual
# mobile manipulator, a humanoid; the frames get pose tasks at priority 0.
MODELS = [
    ("pybullet_data", "franka_panda", False, "all", ["*finger*"], ["panda_grasptarget"]),
    ("pybullet_data", "kuka_iiwa", False, "all", None, ["lbr_iiwa_link_7"]),
    ("example_robot_data", "ur5", False, "all", None, ["tool0"]),
    ("example_robot_data", "panda", False, "all", ["*finger*"], ["panda_hand_tcp"]),
    (
        "example_robot_data", "pr2", False,
        ["torso_lift_joint", "[rl]_shoulder_*", "[rl]_upper_arm*", "[rl]_elbow*",
         "[rl]_forearm_roll*", "[rl]_wrist_*"],
        None, ["r_gripper_tool_frame", "l_gripper_tool_frame"],
    ),
    (
        "example_robot_data", "talos_box", True, "all", ["gripper_*", "head_*"],
        ["gripper_left_base_link", "gripper_right_base_link", "left_sole_link",
         "right_sole_link"],
    ),
]  # fmt: skip


@pytest.mark.parametrize("spec", MODELS, ids=[spec[1] for spec in MODELS])
def test_third_party_model_stack_and_chain(spec):
    source, name, floating, joints, fixed, frames = spec
    path = getattr(redik.models, source)(name)
    robot = redik.Robot(
        _load(str(path), meshes=False, floating_base=floating), joints=joints, fixed=fixed
    )
    assert (robot.nq == robot.dof + 1) if floating else robot.flat
    rng = np.random.default_rng(0)
    q_target = robot.integrate(robot.home, 0.3 * rng.standard_normal(robot.dof))
    # Strictly inside the limits (these URDFs' zero home sits on some of them).
    values = robot.scalar_values(q_target)
    span = robot.upper - robot.lower
    limited = np.isfinite(span)
    values[limited] = np.clip(
        values[limited],
        robot.lower[limited] + 0.1 * span[limited],
        robot.upper[limited] - 0.1 * span[limited],
    )
    q_target = robot.with_scalar_values(q_target, values)
    targets = {frame: robot.fk(q_target, frame) for frame in frames}
    tasks = [redik.FrameTask(frame, target=T) for frame, T in targets.items()]
    result = redik.solve_problem(
        redik.Problem(robot, [*tasks, redik.PostureTask(priority=1)]), robot.home
    )
    assert result.success, result.message
    assert robot.within_limits(result.q)
    for frame, T in targets.items():
        p_err, r_err = pose_errors(robot.fk(result.q, frame), T)
        assert p_err < 1e-6 and r_err < 1e-5
    # The first frame's chain, the rest held at the solution: compiled DLS.
    chain = robot.chain(frames[0], result.q)
    T = chain.fk(chain.clip(chain.q_of() + 0.2))
    assert redik.solve_pose(chain, T, seed=0).success


def test_explore_cli_on_one_arm_of_baxter(tmp_path, capsys):
    from redik.apps.cli import main

    out = tmp_path / "explore"
    argv = ["explore", "example-robot-data:baxter", "--ee", "left_gripper", "--frames", "0"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert (
            main(
                [
                    *argv,
                    "--starts",
                    "8",
                    "--spacing",
                    "0.3",
                    "--out",
                    str(out),
                    "--fixed",
                    "head_pan",
                ]
            )
            == 0
        )
    assert "dimension 1" in capsys.readouterr().out
    summary = (out / "summary.json").read_text()
    assert "left_s0" in summary and "right_s0" not in summary


@pytest.mark.slow  # an example run
def test_baxter_with_added_servos_tracks_in_closed_loop():
    """examples/bimanual_simulate.py: the circle within 5 mm, the held gripper within 1 mm."""
    import runpy
    from pathlib import Path

    script = Path(__file__).resolve().parent.parent / "examples" / "bimanual_simulate.py"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        example = runpy.run_path(str(script))
    result = example["result"]
    assert result.max_position_error < 5e-3, result.summary()
    assert len(example["drift"]) == len(result.q) and max(example["drift"]) < 1e-3
