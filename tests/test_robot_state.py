"""redik.kinematics.robot.state: forward kinematics into buffers, equal to the checked calls."""

from __future__ import annotations

import numpy as np

import redik


def test_hot_path_equals_checked_path(arm, rng):
    q = arm.random_q(rng)
    T, J = np.empty((4, 4)), np.empty((6, arm.dof))
    T[3] = (0, 0, 0, 1)
    arm.state.kinematics(q, arm.ee, T, J)
    np.testing.assert_array_equal(T, arm.fk(q))
    np.testing.assert_array_equal(J, arm.jacobian(q, reference="world"))


def test_scene_fast_path_equals_generic_path():
    """The bundled scenes use MuJoCo's Jacobian in place; a non-contiguous buffer copies."""
    robot = redik.load("panda")
    q = robot.random_q(3)
    T = np.eye(4)
    J_direct = np.empty((6, robot.dof))
    J_strided = np.empty((robot.dof, 6)).T  # not C-contiguous: takes the copying path
    robot.state.kinematics(q, robot.ee, T, J_direct)
    robot.state.kinematics(q, robot.ee, T, J_strided)
    np.testing.assert_array_equal(J_direct, J_strided)


def test_pose_views_follow_each_update_and_the_held_joints_stay(arm, rng):
    state = arm.state
    R, p = state.pose_views(arm.ee)
    held = np.delete(state.data.qpos, arm.qpos_indices).copy()
    for _ in range(5):
        q = arm.random_q(rng)
        state.update(q)
        T = arm.fk(q)
        np.testing.assert_array_equal(R, T[:3, :3])  # views: no copy to refresh
        np.testing.assert_array_equal(p, T[:3, 3])
        np.testing.assert_array_equal(state.data.qpos[arm.qpos_indices], q)
        np.testing.assert_array_equal(np.delete(state.data.qpos, arm.qpos_indices), held)


def test_a_chain_state_holds_the_other_joints_where_it_was_cut():
    whole = redik.load("panda", joints="all")
    q = whole.random_q(4)
    chain = whole.chain("ee", q)
    np.testing.assert_array_equal(chain.state.data.qpos, whole.full_qpos(q))
    T = np.eye(4)
    chain.state.kinematics(q[chain.qpos_indices], chain.ee, T)
    np.testing.assert_allclose(T, whole.fk(q, "ee"), atol=1e-15)
