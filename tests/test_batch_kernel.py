"""The compiled kernel: its FK and Jacobian against MuJoCo's, its pose error and damped solve
against numpy, per-target determinism, and agreement of solve_batch with solve_pose."""

from __future__ import annotations

import numpy as np
import pytest

import redik
from redik.kinematics import compiled
from redik.solvers import dls
from redik.solvers.batch import Chain, forward_kinematics, solve_batch
from redik.solvers.pose import solve_pose

from .test_batch_kinematics import ROBOTS


@pytest.fixture(params=sorted(ROBOTS), ids=str)
def robot(request) -> redik.Robot:
    return ROBOTS[request.param]


def _kernel_pose_and_jacobian(chain: Chain, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    n = chain.dof
    R, p, axes, origins, J = (
        np.empty((3, 3)),
        np.empty(3),
        np.empty((n, 3)),
        np.empty((n, 3)),
        np.empty((6, n)),
    )
    base, links, revolute = chain.kernel_arrays()[:3]
    compiled.chain_kinematics(base, links, revolute, q, R, p, axes, origins)
    compiled.world_jacobian(revolute, p, axes, origins, J)
    return redik.lie.make_pose(R, p), J


def test_kernel_kinematics_match_mujoco(robot, rng):
    chain = Chain.from_robot(robot)
    for q in robot.random_q(rng, size=16):
        T, J = _kernel_pose_and_jacobian(chain, q)
        np.testing.assert_allclose(T, robot.fk(q), rtol=0, atol=1e-12)
        np.testing.assert_allclose(J, robot.jacobian(q, reference="world"), rtol=0, atol=1e-12)


def test_chain_to_another_frame_matches_mujoco(rng):
    """A frame moved by only some joints: the chain holds those, in the robot's order."""
    robot = ROBOTS["test_arm"]
    chain = Chain.from_robot(robot, frame="l3")
    np.testing.assert_array_equal(chain.columns, [0, 1, 2])
    for q in robot.random_q(rng, size=8):
        T, J = _kernel_pose_and_jacobian(chain, q[chain.columns])
        np.testing.assert_allclose(T, robot.fk(q, frame="l3"), rtol=0, atol=1e-12)
        full = robot.jacobian(q, frame="l3", reference="world")
        np.testing.assert_allclose(J, full[:, chain.columns], rtol=0, atol=1e-12)
        np.testing.assert_allclose(np.delete(full, chain.columns, axis=1), 0.0, atol=1e-12)


def test_kernel_pose_error_matches_the_batched_rotation_log(rng):
    from redik.apps.workspace import random_rotations
    from redik.lie import rotation_log

    Rd, R = random_rotations(50, rng=3), random_rotations(50, rng=4)
    axis = np.array([0.0, 0.6, 0.8])
    Rd[0] = R[0] @ redik.lie.so3_exp(axis * (np.pi - 1e-9))  # near θ = π
    Rd[1] = redik.lie.so3_exp(axis * 1e-9) @ R[1]  # near θ = 0
    expected = np.empty((3, 50))
    angles = rotation_log(Rd.transpose(1, 2, 0).copy(), R.transpose(1, 2, 0).copy(), expected)
    pd, p = rng.standard_normal((50, 3)), rng.standard_normal((50, 3))
    e = np.empty(6)
    for i in range(50):
        position, angle = compiled.pose_error(Rd[i], pd[i], R[i], p[i], e)
        np.testing.assert_allclose(e[:3], pd[i] - p[i], atol=1e-15)
        assert position == pytest.approx(np.linalg.norm(pd[i] - p[i]), rel=1e-14)
        assert angle == pytest.approx(angles[i], abs=1e-12)
        np.testing.assert_allclose(
            redik.lie.so3_exp(e[3:]), redik.lie.so3_exp(expected[:, i]), atol=1e-9
        )
        if i > 0:  # one vector away from θ = π (there ±axis are both logs)
            np.testing.assert_allclose(e[3:], expected[:, i], rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("n", [3, 6, 7])
def test_damped_solve_solves_the_damped_normal_equations(n, rng):
    m = min(n, 6)
    for _ in range(10):
        J, e = rng.standard_normal((6, n)), rng.standard_normal(6)
        free = rng.random(n) > 0.3
        damping = rng.uniform(1e-6, 1.0)
        dq = np.empty(n)
        dls.damped_solve(J, free, e, damping, np.empty((m, m)), np.empty(m), dq)
        Jf = J * free
        expected = np.linalg.solve(Jf.T @ Jf + damping * np.eye(n), Jf.T @ e)
        np.testing.assert_allclose(dq, expected, rtol=1e-8, atol=1e-10)
        np.testing.assert_array_equal(dq[~free], 0.0)


def test_damped_solve_equals_its_numpy_twin_damped_step(rng):
    # The compiled one-target step and the batched numpy one are the same formula.
    J, e = rng.standard_normal((6, 7, 20)), rng.standard_normal((6, 20))
    damping = rng.uniform(1e-6, 1.0, 20)
    batched = dls.damped_step(J, e, damping)
    free, dq = np.ones(7, dtype=bool), np.empty(7)
    for b in range(20):
        J_b = np.ascontiguousarray(J[:, :, b])
        dls.damped_solve(J_b, free, e[:, b].copy(), damping[b], np.empty((6, 6)), np.empty(6), dq)
        np.testing.assert_allclose(dq, batched[:, b], rtol=1e-9, atol=1e-12)


def test_results_do_not_depend_on_chunks_or_threads():
    robot = redik.load("panda")
    chain = Chain.from_robot(robot)
    T = forward_kinematics(chain, robot.random_q(31, size=300))
    whole = solve_batch(chain, T, seed=4, chunk_size=300)
    pieces = solve_batch(chain, T, seed=4, chunk_size=37, workers=1)
    for name in ("q", "iterations", "restarts", "status", "position_error"):
        np.testing.assert_array_equal(getattr(whole, name), getattr(pieces, name))
    assert whole.restarts.any()  # the per-target random streams were used


@pytest.mark.parametrize("name", ["panda", "iiwa14", "ur5e"])
def test_solve_pose_and_solve_batch_agree_on_success(name):
    """Reachable targets and some beyond reach: both solvers succeed on the same ones."""
    robot = redik.load(name)
    chain = Chain.from_robot(robot)
    T = forward_kinematics(chain, robot.random_q(12, size=30))
    T[::5, 0, 3] += 3.0  # out of reach
    batch = solve_batch(chain, T, seed=2)
    single = np.array([solve_pose(robot, T[i], seed=i).success for i in range(len(T))])
    np.testing.assert_array_equal(batch.success, single)
    assert not single[::5].any() and single.sum() == 24
