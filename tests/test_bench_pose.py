"""redik bench pose: every library's model agrees with redik's, and one score judges all."""

from __future__ import annotations

import numpy as np
import pytest

import redik
from redik.apps.bench import pose

ARMS = ("panda", "iiwa14", "ur5e")


@pytest.mark.parametrize("name", ARMS)
def test_rtb_ets_built_from_the_dh_table_has_redik_fk(name, rng):
    pytest.importorskip("roboticstoolbox")
    robot = redik.load(name)
    ets = pose.rtb_ets(robot)
    assert ets.n == robot.dof
    assert np.allclose(ets.qlim, np.vstack((robot.lower, robot.upper)))
    for q in robot.random_q(rng, size=20):
        assert np.allclose(ets.fkine(q).A, robot.fk(q), atol=1e-12)


@pytest.mark.parametrize("name", ARMS)
def test_tracik_urdf_from_the_dh_table_has_redik_fk(name, rng):
    pytracik = pytest.importorskip("pytracik")
    robot = redik.load(name)
    rows, convention, tool, base = pose._dh_table(robot)
    urdf = pose._dh_to_urdf(rows, convention, tool, robot)
    solver = pytracik.TRAC_IK("base", "tool", urdf, 0.005, 1e-6, pytracik.SolveType.Speed)
    for q in robot.random_q(rng, size=20):
        assert np.allclose(base @ pytracik.fk(solver, q), robot.fk(q), atol=1e-12)


def test_score_is_strict_on_pose_and_limits(rng):
    robot = redik.load("panda")
    score = pose.Score(robot)
    q = robot.random_q(rng)
    T_target = robot.fk(q)
    assert score(q, T_target)
    assert not score(None, T_target)
    assert not score(np.full(robot.dof, np.nan), T_target)
    assert not score(q[:-1], T_target)
    nudged = q.copy()
    nudged[0] += 2e-5  # ~1e-5 m at the flange: outside the position tolerance
    assert not score(nudged, T_target)
    outside = robot.home.copy()
    outside[3] = robot.upper[3] + 1e-9
    assert not score(outside, robot.fk(outside))


def test_interleaved_run_scores_redik_and_rtb(rng):
    pytest.importorskip("roboticstoolbox")
    robot = redik.load("iiwa14")
    solvers = {
        "redik dls": pose._redik_solver(robot, "dls"),
        pose.REFERENCE: pose._rtb_solver(robot),
    }
    rows = pose._measure(robot, solvers, n=5, seed=0)
    assert [(r[1], r[2]) for r in rows] == [
        (mode, label) for mode in pose.SEED_MODES for label in solvers
    ]
    for _, _, label, success, milliseconds in rows:
        assert milliseconds.shape == (5,) and np.all(milliseconds > 0)
        if label == "redik dls":
            assert success == 100.0
