"""Self-motion exploration (redik.solvers.redundancy.selfmotion) on the bundled 6R, 7R and 8R
arms."""

from __future__ import annotations

import json

import mujoco
import numpy as np
import pytest
from scipy.spatial import cKDTree

import redik
from redik.solvers.pose import solve_pose
from redik.solvers.redundancy import (
    Manipulability,
    SelfMotion,
    explore_self_motion,
    gradient_projection_ik,
)
from redik.solvers.redundancy.corrector import (
    SAMPLE_POSITION_TOLERANCE,
    SAMPLE_ROTATION_TOLERANCE,
    BatchCorrector,
    Corrector,
)
from redik.solvers.redundancy.selfmotion.index import SampleIndex


def without_limits(scene: str) -> redik.Robot:
    """The bundled scene with every joint range removed: a 7R arm on the torus."""
    spec = mujoco.MjSpec.from_file(str(redik.models.scene_path(scene)))
    for joint in spec.joints:
        joint.limited = mujoco.mjtLimited.mjLIMITED_FALSE
    for actuator in spec.actuators:
        actuator.ctrllimited = mujoco.mjtLimited.mjLIMITED_FALSE
    return redik.Robot(spec.compile(), name=f"{scene}_unlimited")


def assert_every_sample_keeps_the_pose(robot: redik.Robot, motion: SelfMotion) -> None:
    assert len(motion) > 0
    assert motion.position_error.max() <= SAMPLE_POSITION_TOLERANCE
    assert motion.rotation_error.max() <= SAMPLE_ROTATION_TOLERANCE
    for q in motion.samples[:: max(1, len(motion) // 50)]:  # recomputed independently
        position, rotation = redik.lie.pose_errors(robot.fk(q), motion.T_target)
        assert position <= SAMPLE_POSITION_TOLERANCE and rotation <= SAMPLE_ROTATION_TOLERANCE
        assert robot.within_limits(q)


@pytest.fixture(scope="module")
def panda() -> redik.Robot:
    return redik.load("panda")


@pytest.fixture(scope="module")
def panda_motion(panda) -> SelfMotion:
    q = panda.random_q(np.random.default_rng(3))
    return explore_self_motion(panda, panda.fk(q), seed=0, initial=q)


def test_unlimited_7r_manifolds_are_closed_loops():
    robot = without_limits("iiwa14")
    rng = np.random.default_rng(7)
    q = robot.random_q(rng)
    motion = explore_self_motion(robot, robot.fk(q), spacing=0.08, seed=1, n_starts=24)
    assert motion.dimension == 1
    assert_every_sample_keeps_the_pose(robot, motion)
    assert motion.n_components >= 1
    assert motion.closed.all(), motion.ends
    for k in range(motion.n_components):
        loop = motion.component_samples(k)
        assert len(loop) > 10
        # Consecutive samples, and the last back to the first, are at most one spacing apart
        # (hinge angles modulo 2π: the arm has no limits).
        gaps = redik.lie.wrap_angle(np.diff(np.vstack([loop, loop[:1]]), axis=0))
        assert np.linalg.norm(gaps, axis=1).max() <= motion.spacing + 1e-12
    # The configuration the pose came from lies on one of the loops.
    assert motion.distance_to(q)[0] <= motion.spacing


def test_joint_limits_cut_the_loops_into_arcs_ending_on_a_limit(panda, panda_motion):
    motion = panda_motion
    assert_every_sample_keeps_the_pose(panda, motion)
    cut = [k for k in range(motion.n_components) if not motion.closed[k]]
    assert cut, "a random Panda pose has its self-motion loops cut by the limits"
    for k in cut:
        arc = motion.component_samples(k)
        assert np.linalg.norm(np.diff(arc, axis=0), axis=1).max() <= motion.spacing + 1e-12
        for side, end in zip((0, -1), motion.ends[k], strict=True):
            if end == "joint_limit":
                on_limit = np.minimum(
                    np.abs(arc[side] - panda.lower), np.abs(arc[side] - panda.upper)
                )
                assert on_limit.min() <= 1e-12


def test_best_is_at_least_as_good_as_gradient_projection_from_a_sample(panda, panda_motion):
    motion = panda_motion
    best = motion.best("manipulability")
    J = panda.jacobian(best, reference="world")
    assert np.isclose(
        Manipulability().value(panda, best, J), motion.criteria["manipulability"].max()
    )
    start = motion.samples[len(motion) // 2]
    local = gradient_projection_ik(panda, motion.T_target, start, Manipulability())
    assert local.success
    local_value = Manipulability().value(panda, local.q, panda.jacobian(local.q, reference="world"))
    # The manifold's best sample beats (or, sampled every 0.05 rad, nearly matches) a local
    # optimum of the same criterion.
    assert motion.criteria["manipulability"].max() >= 0.99 * local_value
    nearest = motion.best("posture_distance")
    assert motion.criteria["posture_distance"].min() == pytest.approx(
        np.linalg.norm(nearest - panda.home)
    )


@pytest.mark.parametrize("scene, pose_seed", [("panda", 11), ("iiwa14", 12)])
def test_independent_ik_solutions_lie_on_the_explored_manifold(scene, pose_seed):
    robot = redik.load(scene)
    rng = np.random.default_rng(pose_seed)
    T = robot.fk(robot.random_q(rng))
    motion = explore_self_motion(robot, T, seed=pose_seed)
    solutions = []
    for q0 in robot.random_q(rng, size=30):
        result = solve_pose(robot, T, q0, respect_limits=True, seed=int(rng.integers(2**63)))
        if result.success:
            solutions.append(result.q)
    assert len(solutions) >= 20
    distances = motion.distance_to(np.array(solutions))
    assert np.mean(distances <= motion.spacing) >= 0.95, np.sort(distances)[-5:]


def test_dexter8r_manifold_is_two_dimensional():
    robot = redik.load("dexter8r")
    T = robot.fk(robot.home)
    motion = explore_self_motion(
        robot, T, spacing=0.3, seed=0, n_starts=8, initial=robot.home, max_samples=600
    )
    assert motion.dimension == 2
    assert_every_sample_keeps_the_pose(robot, motion)
    # Local rank: the 12 nearest neighbours of a sample span a plane, not a line or a volume.
    tree = cKDTree(motion.samples)
    ratios = []
    for q in motion.samples[::10]:
        _, neighbours = tree.query(q, k=12)
        patch = motion.samples[neighbours] - motion.samples[neighbours].mean(axis=0)
        s = np.linalg.svd(patch, compute_uv=False)
        ratios.append((s[1] / s[0], s[2] / s[1]))
    ratios = np.median(np.array(ratios), axis=0)
    assert ratios[0] > 0.3  # a second direction as wide as the first
    assert ratios[1] < 0.2  # and no third
    # Neighbours are at most one spacing apart and no closer than the covering's exclusion.
    distances, _ = tree.query(motion.samples, k=2)
    assert distances[:, 1].max() <= motion.spacing + 1e-12


def test_dexter8r_independent_ik_solutions_lie_on_the_explored_surface():
    # The surface is covered through the limits, so patches no seed lands in are found too.
    robot = redik.load("dexter8r")
    rng = np.random.default_rng(21)
    T = robot.fk(robot.random_q(rng))
    motion = explore_self_motion(robot, T, spacing=0.45, seed=21, n_starts=16)
    assert_every_sample_keeps_the_pose(robot, motion)
    assert motion.n_components > 1  # the limits cut this surface into several patches
    solutions = []
    for q0 in robot.random_q(rng, size=100):
        result = solve_pose(robot, T, q0, respect_limits=True, seed=int(rng.integers(2**63)))
        if result.success:
            solutions.append(result.q)
    assert len(solutions) >= 80
    distances = motion.distance_to(np.array(solutions))
    assert np.mean(distances <= motion.spacing) >= 0.99, np.sort(distances)[-5:]


@pytest.fixture(scope="module")
def dexter_correctors() -> tuple[redik.Robot, Corrector, BatchCorrector, np.ndarray]:
    robot = redik.load("dexter8r")
    q = robot.random_q(np.random.default_rng(5))
    corrector = Corrector(robot, robot.fk(q), robot.frame(None))
    return robot, corrector, BatchCorrector(corrector), q


def test_batch_corrector_projects_onto_the_pose_and_spans_the_tangent_plane(dexter_correctors):
    robot, corrector, batch, q = dexter_correctors
    rng = np.random.default_rng(0)
    tangent = corrector.tangent_basis(q, 2)
    predictions = q + 0.2 * (tangent @ rng.normal(size=(2, 40))).T + 0.01 * rng.normal(size=(40, 8))
    corrected, converged = batch.correct(predictions)
    assert converged.all()
    for x in corrected:  # MuJoCo's kinematics, not the batch chain's
        position, rotation = corrector.pose_errors(x)
        assert (
            position <= 0.01 * SAMPLE_POSITION_TOLERANCE
            and rotation <= 0.01 * SAMPLE_ROTATION_TOLERANCE
        )
    # The same projection as one point at a time, to within the corrector's tolerance.
    one_by_one = np.array([corrector.correct(x)[0] for x in predictions[:5]])
    assert np.allclose(corrected[:5], one_by_one, atol=1e-3)
    bases = batch.tangent_bases(corrected, 2)
    for x, basis in zip(corrected[:5], bases, strict=False):
        assert np.allclose(robot.jacobian(x, reference="world") @ basis, 0.0, atol=1e-12)
        assert np.allclose(basis.T @ basis, np.eye(2), atol=1e-12)


def test_limit_points_lie_on_a_limit_and_keep_the_pose():
    robot = redik.load("dexter8r")
    inside = robot.random_q(np.random.default_rng(6))
    inside[2] = robot.upper[2] - 0.02  # joint 3 just below its upper limit
    corrector = Corrector(robot, robot.fk(inside), robot.frame(None))
    # Step along the surface, in the tangent direction that raises joint 3, past the limit.
    tangent = corrector.tangent_basis(inside, 2)
    direction = tangent @ tangent[2]
    direction /= np.linalg.norm(direction)
    outside, converged = corrector.correct(inside + 0.1 * direction)
    assert converged and outside[2] > robot.upper[2]
    points, placed = BatchCorrector(corrector).limit_points(inside[None], outside[None])
    assert placed.all()
    position, rotation = corrector.pose_errors(points[0])
    assert position <= SAMPLE_POSITION_TOLERANCE and rotation <= SAMPLE_ROTATION_TOLERANCE
    assert points[0][2] == robot.upper[2] and robot.within_limits(points[0])
    assert np.linalg.norm(points[0] - inside) < np.linalg.norm(outside - inside)


def test_shift_into_limits_takes_the_nearer_side_of_the_range(dexter_correctors):
    robot, corrector, _, _ = dexter_correctors
    q = np.array(robot.home)
    q[0] = robot.lower[0] - 0.03 + 2 * np.pi  # just below the lower limit, one turn up
    shifted, inside = corrector.shift_into_limits(q[None])
    assert not inside[0]
    assert shifted[0, 0] == pytest.approx(robot.lower[0] - 0.03)
    assert corrector.limit_violation(q) == pytest.approx(0.03)
    q[0] = robot.lower[0] + 0.1 + 2 * np.pi
    shifted, inside = corrector.shift_into_limits(q[None])
    assert inside[0] and shifted[0, 0] == pytest.approx(robot.lower[0] + 0.1)


@pytest.mark.parametrize("scene", ["puma560", "ur5e"])
def test_a_6r_arm_has_isolated_solutions(scene):
    robot = redik.load(scene)
    T = robot.fk(robot.home)
    motion = explore_self_motion(robot, T, seed=0, n_starts=48, initial=robot.home)
    assert motion.dimension == 0
    assert_every_sample_keeps_the_pose(robot, motion)
    assert 1 <= motion.n_components == len(motion)
    assert not motion.closed.any()
    # Distinct solutions, the home configuration among them.
    gaps = cKDTree(motion.samples).query(motion.samples, k=min(2, len(motion)))[0]
    if len(motion) > 1:
        assert gaps[:, 1].min() > 1e-4
    assert motion.distance_to(robot.home)[0] <= 1e-6


def test_criteria_scored_in_batch_match_one_sample_at_a_time(panda, panda_motion):
    from redik.solvers.redundancy import default_criteria

    for criterion in default_criteria(panda):
        for k in range(0, len(panda_motion), max(1, len(panda_motion) // 7)):
            q = panda_motion.samples[k]
            expected = criterion.value(panda, q, panda.jacobian(q, reference="world"))
            assert panda_motion.criteria[criterion.name][k] == pytest.approx(expected, abs=1e-12)


def test_summary_and_npz_round_trip(panda_motion, tmp_path):
    summary = json.loads(json.dumps(panda_motion.summary()))
    assert summary["samples"] == len(panda_motion)
    assert summary["dimension"] == 1
    assert len(summary["components"]) == panda_motion.n_components
    panda_motion.save(tmp_path / "motion.npz")
    stored = np.load(tmp_path / "motion.npz")
    assert np.array_equal(stored["samples"], panda_motion.samples)
    assert np.array_equal(
        stored["criterion_manipulability"], panda_motion.criteria["manipulability"]
    )


def test_walk_visits_a_component_in_small_steps(panda_motion):
    path = panda_motion.walk(0)
    steps = np.linalg.norm(np.diff(panda_motion.samples[path], axis=0), axis=1)
    assert len(path) == np.sum(panda_motion.component == 0)
    assert steps.max() <= panda_motion.spacing + 1e-12


def test_bad_inputs_raise(panda, panda_motion):
    T = panda.fk(panda.home)
    with pytest.raises(redik.InvalidInput, match="spacing must be a positive number"):
        explore_self_motion(panda, T, spacing=0.0)
    with pytest.raises(redik.InvalidPose):
        explore_self_motion(panda, np.eye(3))
    with pytest.raises(redik.InvalidInput, match="unknown criterion 'speed'"):
        panda_motion.best("speed")


def test_explore_cli_writes_samples_summary_and_pictures(tmp_path, monkeypatch):
    from redik.apps.cli import main

    monkeypatch.setenv("MUJOCO_GL", "egl")
    out = tmp_path / "panda"
    args = ["explore", "panda", "--pose", "0.4", "0.1", "0.5", "0", "1", "0", "0", "--starts", "16"]
    assert main([*args, "--out", str(out), "--frames", "3", "--size", "96", "72", "--no-mp4"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["samples"] > 0 and summary["max_position_error"] <= SAMPLE_POSITION_TOLERANCE
    assert np.allclose(np.array(summary["T_target"])[:3, 3], [0.4, 0.1, 0.5])
    assert np.load(out / "samples.npz")["samples"].shape == (summary["samples"], 7)
    for name in ("manifold_component", "manifold_manipulability", "selfmotion"):
        assert (out / f"{name}.{'gif' if name == 'selfmotion' else 'png'}").stat().st_size > 0
    assert len(list((out / "frames").glob("*.png"))) == 3
    with pytest.raises(SystemExit):
        main(["explore", "panda", "--pose", "1", "2", "3"])


def test_angles_a_hair_below_minus_pi_fit_the_periodic_box():
    # np.mod(q + π, 2π) rounds to exactly 2π one ulp below −π; cKDTree refused that value.
    index = SampleIndex(np.array([True, False]), 2)
    below = np.nextafter(-np.pi, -4.0)
    index.extend(np.random.default_rng(0).uniform(-3.0, 3.0, (100, 2)))
    index.extend(np.array([[below, 0.3], [below + 2 * np.pi * 3, 0.1]]))
    index._rebuild()
    embedded = index._embed(np.array([[below, 0.3], [np.pi, 0.0], [-np.pi, 0.0]]))
    assert np.all((embedded[:, 0] >= 0.0) & (embedded[:, 0] < 2 * np.pi))
    assert index.nearest(np.array([np.pi, 0.3])) == pytest.approx(0.0, abs=1e-12)
    assert index.within_each(np.array([[np.pi, 0.3]]), np.array([1e-9]))[0]


def test_iiwa14_at_its_home_keyframe_pose_is_explored():
    # The keyframe of MuJoCo Menagerie's iiwa14 (q1 = q3 = q5 = q7 = 0): tracing passes
    # through hinge angles of exactly ±π, which crashed the KD-tree (issue 11).
    robot = redik.load("iiwa14")
    q = np.array([0.0, 0.785398, 0.0, -1.5708, 0.0, 0.0, 0.0])
    motion = explore_self_motion(robot, robot.fk(q), seed=2, n_starts=16, initial=q)
    assert motion.status == "converged" and motion.success, motion.message
    assert_every_sample_keeps_the_pose(robot, motion)
    assert motion.distance_to(q)[0] <= motion.spacing


def test_an_unreachable_pose_has_a_status_a_reason_and_the_closest_error(panda):
    T = panda.fk(panda.home)
    T[:3, 3] = [3.0, 0.0, 0.5]  # 3 m away: the Panda reaches under 1 m
    motion = explore_self_motion(panda, T, seed=0, n_starts=4)
    assert not motion.success and len(motion) == 0 and motion.n_components == 0
    assert motion.status == "unreachable"
    assert "none of 4 IK starts reached the pose" in motion.message
    assert motion.closest_position_error > 1.5  # at least 3 m − the reach
    summary = motion.summary()
    assert summary["status"] == "unreachable" and summary["message"] == motion.message
    assert summary["max_position_error"] is None and summary["max_rotation_error"] is None
    assert summary["closest_position_error"] == pytest.approx(motion.closest_position_error)
    json.dumps(summary)
    nothing = explore_self_motion(panda, T, n_starts=0)
    assert nothing.status == "unreachable" and "no start" in nothing.message


def test_a_budget_too_small_for_the_manifold_says_so(panda):
    T = panda.fk(panda.home)
    whole = explore_self_motion(panda, T, seed=0, n_starts=8, initial=panda.home)
    assert whole.status == "converged" and len(whole) > 20
    cut = explore_self_motion(panda, T, seed=0, n_starts=8, initial=panda.home, max_samples=20)
    assert cut.status == "max_iterations" and cut.success and len(cut) == 20
    assert "max_samples=20 ran out" in cut.message


def test_a_pose_reached_only_outside_the_limits_has_status_limits():
    robot = redik.load("planar_2r")
    q = np.array([0.3, 2.9])  # inside the range only if the elbow could bend 2.9 rad
    spec = mujoco.MjSpec.from_file(str(redik.models.scene_path("planar_2r")))
    for joint in spec.joints:
        joint.range = [-1.0, 1.0]
        joint.limited = mujoco.mjtLimited.mjLIMITED_TRUE
    limited = redik.Robot(spec.compile(), name="planar_2r_narrow")
    motion = explore_self_motion(limited, robot.fk(q), seed=0, n_starts=8, initial=q)
    assert motion.status == "limits" and not motion.success
    assert "leave the joint limits" in motion.message


def test_explore_cli_reports_an_unreachable_pose(tmp_path, capsys):
    from redik.apps.cli import main

    args = ["explore", "panda", "--pose", "3", "0", "0.5", "1", "0", "0", "0", "--starts", "2"]
    assert main([*args, "--out", str(tmp_path), "--frames", "0"]) == 1
    out = capsys.readouterr().out
    assert "unreachable" in out and "none of 2 IK starts" in out
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["status"] == "unreachable" and summary["max_position_error"] is None


def test_the_corrector_takes_the_ikinbody_newton_steps_of_solve_pose(panda, rng):
    # One IKinBody step q ← q + J_b⁺ log(T⁻¹ T_d): the pose solver's Newton and the
    # self-motion corrector iterate alike (one through pinv, one through JJᵀ).
    T = panda.fk(panda.random_q(rng))
    q = panda.random_q(rng)
    newton = redik.solve_pose(
        panda, T, q, method="newton", respect_limits=False, restarts=0, max_iterations=3
    )
    corrector = Corrector(panda, T, panda.ee)
    for iterate in newton.history[1:]:
        q, _ = corrector.correct(q, max_iterations=1)
        np.testing.assert_allclose(q, iterate, atol=1e-12)
