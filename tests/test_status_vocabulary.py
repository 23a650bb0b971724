"""One situation, one status: a target beyond the chain's reach from every entry point."""

from __future__ import annotations

import numpy as np
import pytest

import redik
from redik.kinematics.chain import Chain
from redik.lie import make_pose
from redik.solvers.dls import reach_excess
from redik.solvers.pose.frame import PoseFrame

FAR = make_pose(np.eye(3), [3.0, 0.0, 0.5])
"""3 m from the base: every bundled arm reaches less than 1.5 m."""


@pytest.fixture(scope="module")
def iiwa14() -> redik.Robot:
    return redik.load("iiwa14")


@pytest.mark.parametrize("respect_limits", [True, False])
def test_solve_pose(iiwa14, respect_limits):
    result = redik.solve_pose(iiwa14, FAR, seed=0, respect_limits=respect_limits)
    assert result.status == "unreachable" and not result.success
    assert "beyond the reach" in result.message and "limit" not in result.message


def test_solve_batch(iiwa14):
    T = np.stack([FAR, iiwa14.fk(iiwa14.home)])
    result = redik.solve_batch(iiwa14, T, seed=0)
    assert result.status_names.tolist() == ["unreachable", "converged"]
    assert result.restarts[0] <= 2  # beyond reach: a closest q is all there is to find


@pytest.mark.parametrize("limits", [None, []])
def test_solve_problem(iiwa14, limits):
    problem = redik.Problem(iiwa14, [redik.FrameTask("ee", target=FAR)], limits)
    result = redik.solve_problem(problem, iiwa14.home)
    assert result.status == "unreachable" and not result.success
    assert "beyond the reach" in result.message and "limit" not in result.message


def test_explore_self_motion(iiwa14):
    motion = redik.explore_self_motion(iiwa14, FAR, seed=0, n_starts=4)
    assert motion.status == "unreachable" and not motion.success
    assert "beyond the reach" in motion.message


@pytest.mark.parametrize("name", ["iiwa14", "panda", "ur5e", "puma560", "dexter8r"])
def test_batch_and_pose_test_one_reach_bound(name):
    """The batch kernel's bound (the compiled chain's) is solve_pose's (the model's anchors)."""
    robot = redik.load(name)
    centre, radius = Chain.from_robot(robot).reach()
    frame = PoseFrame(robot, robot.ee)
    np.testing.assert_allclose(centre, frame.origin, atol=1e-12)
    assert radius == pytest.approx(frame.reach, rel=1e-12)
    reach = np.array([*centre, radius])
    for distance in (0.5 * radius, radius * (1 + 1e-12), radius + 0.25):
        p = centre + distance * np.array([0.6, 0.0, 0.8])
        assert reach_excess(reach, p) == pytest.approx(frame.reach_excess(p), abs=1e-12)
