"""Workspace estimates: shapes, scores in [0, 1], known reachable and unreachable points, PNGs,
and the course's primary and dexterous workspaces of the planar 2R arm."""

from __future__ import annotations

import numpy as np
import pytest

import redik
from redik import Robot
from redik.apps import workspace
from redik.solvers.batch import Chain, forward_kinematics


@pytest.fixture(scope="module")
def panda() -> redik.Robot:
    return redik.load("panda")


def test_random_rotations_are_rotations():
    R = workspace.random_rotations(50, rng=0)
    assert R.shape == (50, 3, 3)
    np.testing.assert_allclose(
        R @ R.transpose(0, 2, 1), np.broadcast_to(np.eye(3), R.shape), atol=1e-12
    )
    np.testing.assert_allclose(np.linalg.det(R), 1.0)


def test_reachability_scores_known_points(panda):
    chain = Chain.from_robot(panda)
    q = panda.random_q(3, size=4)
    T = forward_kinematics(chain, q)
    centre, radius = chain.reach()
    far = centre + np.array([[radius + 0.5, 0, 0], [0, 0, -(radius + 2.0)]])
    grid = np.concatenate([T[:, :3, 3], far])
    # The FK orientation of each reachable point is among those tried there: it is reachable.
    orientations = np.concatenate([T[:, :3, :3], workspace.random_rotations(2, rng=1)])
    reach = workspace.reachability(panda, grid, orientations=orientations, seed=0, engine="local")
    assert reach.score.shape == (6,) and reach.solved.shape == (6, 6)
    assert np.all((reach.score >= 0) & (reach.score <= 1))
    for i in range(4):
        assert reach.solved[i, i]
        assert reach.score[i] > 0
    np.testing.assert_array_equal(reach.score[4:], 0.0)


def test_reachability_keeps_the_grid_shape_and_plots_a_slice(panda, tmp_path):
    xs = np.linspace(-0.9, 0.9, 4)
    grid = np.stack(np.meshgrid(xs, xs, [0.3, 0.5], indexing="ij"), axis=-1)
    reach = workspace.reachability(panda, grid, orientations=3, seed=0, restarts=1, engine="local")
    assert reach.score.shape == (4, 4, 2) and reach.solved.shape == (4, 4, 2, 3)
    assert np.all((reach.score >= 0) & (reach.score <= 1))
    path = reach.plot_slice(tmp_path / "slice.png", axis="z", value=0.5)
    assert path.stat().st_size > 1000 and path.read_bytes()[:4] == b"\x89PNG"


def test_sample_estimates_primary_and_dexterous_workspace(panda, tmp_path):
    result = workspace.sample(panda, 400, seed=2, orientations=3, resolution=4, engine="local")
    assert result.points.shape == (400, 3) and result.q.shape == (400, panda.dof)
    np.testing.assert_allclose(
        result.points, forward_kinematics(Chain.from_robot(panda), result.q)[:, :3, 3]
    )
    cells = result.cells.points
    assert cells.ndim == 2 and cells.shape[1] == 3 and len(cells) == len(result.score)
    assert np.all((result.score >= 0) & (result.score <= 1))
    # Every sample lies in an occupied cell.
    index = np.floor((result.points - result.points.min(axis=0)) / result.cell_size)
    centres = result.points.min(axis=0) + (index + 0.5) * result.cell_size
    occupied = set(map(tuple, np.round(cells, 9)))
    assert set(map(tuple, np.round(centres, 9))) <= occupied  # whole points, not coordinates
    assert result.score.max() > 0
    assert len(result.dexterous) == int((result.score >= 1).sum())
    for path in result.plot(tmp_path):
        assert path.read_bytes()[:4] == b"\x89PNG"


def test_default_orientations_are_ones_the_arm_takes():
    planar = redik.load("planar_2r")
    R = workspace.attainable_rotations(planar, 20, rng=0)
    # a planar arm turns about its plane's normal only: R e_z = e_z
    np.testing.assert_allclose(R[:, :, 2], np.tile([0.0, 0.0, 1.0], (20, 1)), atol=1e-12)
    angles = np.arctan2(R[:, 1, 0], R[:, 0, 0])
    assert np.ptp(angles) > np.pi  # spread over the turn, not one orientation
    reach = workspace.reachability(planar, np.zeros((1, 3)), orientations=5, seed=3)
    np.testing.assert_allclose(reach.orientations[:, :, 2], np.tile([0, 0, 1.0], (5, 1)))


# Course 002, "Workspace of planar 2R arm": WS1 = {|l1 − l2| ≤ ‖p‖ ≤ l1 + l2}; WS2 = {0} for
# l1 = l2 (every orientation of the plane at the origin, q2 = π) and WS2 = ∅ for l1 ≠ l2.
PROBE = np.array([[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [1.0, 0.0, 0.0], [1.5, 0.0, 0.0]])


@pytest.mark.parametrize(
    ("l1", "l2", "dexterous"),
    [(1.0, 1.0, [True, False, False, False]), (1.0, 0.5, [False, False, False, False])],
)
def test_planar_2r_primary_and_dexterous_workspace_are_the_courses(l1, l2, dexterous):
    robot = Robot.from_dh([(l1, 0.0, 0.0), (l2, 0.0, 0.0)])
    radii = np.linalg.norm(workspace.sample(robot, 2000, seed=0, resolution=4).points, axis=1)
    assert abs(l1 - l2) - 1e-9 <= radii.min() and radii.max() <= l1 + l2 + 1e-9
    assert radii.min() < abs(l1 - l2) + 0.05 and radii.max() > l1 + l2 - 0.05  # WS1 filled
    score = workspace.reachability(robot, PROBE, seed=0).score
    np.testing.assert_array_equal(score >= 1.0, dexterous)
    # Uniform SO(3) asks a planar arm for orientations it cannot take: nothing is dexterous.
    uniform = workspace.reachability(robot, PROBE, workspace.random_rotations(8, rng=0), seed=0)
    np.testing.assert_array_equal(uniform.score, 0.0)


def test_bad_inputs_raise(panda):
    with pytest.raises(redik.InvalidInput, match="grid"):
        workspace.reachability(panda, np.zeros((3, 2)))
    with pytest.raises(redik.InvalidInput, match="orientations"):
        workspace.reachability(panda, np.zeros((3, 3)), orientations=np.eye(3))
    with pytest.raises(redik.InvalidInput, match="axis"):
        workspace.reachability(panda, np.zeros((1, 3)), orientations=1, engine="local").plot_slice(
            "x.png", axis="w"
        )
    with pytest.raises(redik.InvalidInput):
        workspace.sample(panda, 0)
