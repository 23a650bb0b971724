"""Closed-form solvers bound to the bundled scenes: parameters read from the MJCF numerics."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import redik
from redik.core.exceptions import InvalidInput, ModelError
from redik.models.scene_library import get_scene
from redik.solvers.analytic import params_from_model, solver_for, wrap_angle
from redik.solvers.analytic._solution import DEFAULT_TOL

SCENES = ["planar_2r", "planar_3r", "rrp_polar", "hexapod_leg", "puma560", "ur5e", "stanford_arm"]
POSITION_ONLY = {"planar_2r", "rrp_polar", "hexapod_leg"}


@pytest.mark.parametrize("name", SCENES)
def test_params_from_model_match_the_scene_library(name):
    robot = redik.load(name)
    params = params_from_model(robot.model, name)
    assert params == pytest.approx(dict(get_scene(name).parameters))


@pytest.mark.parametrize("name", SCENES)
def test_solver_for_scene_reaches_robot_fk_targets_within_limits(name):
    robot = redik.load(name)
    solver = solver_for(robot)
    rng = np.random.default_rng(0)
    for _ in range(15):
        q = robot.random_q(rng)
        T = robot.fk(q)
        result = solver(T[:3, 3] if name in POSITION_ONLY else T)
        assert result.reachable and len(result) >= 1
        found = False
        for solution in result:
            assert robot.within_limits(solution, tol=1e-9)
            reached = robot.fk(solution)
            if name in POSITION_ONLY:
                assert np.abs(reached[:3, 3] - T[:3, 3]).max() <= 1e-10
            else:
                assert np.abs(reached - T).max() <= 1e-10
            difference = np.where(robot.revolute, wrap_angle(solution - q), solution - q)
            found |= bool(np.abs(difference).max() < 1e-8)
        assert found


def test_solver_for_reports_unreachable_and_off_plane_targets():
    planar = solver_for(redik.load("planar_2r"))
    assert "off the arm's plane" in planar([1.0, 0.5, 0.2]).reason
    assert "beyond the reach" in planar([3.0, 0.0, 0.0]).reason
    puma = solver_for(redik.load("puma560"))
    assert len(puma(puma.base @ np.eye(4), limits=None)) == 0  # wrist centre on the base axis
    with pytest.raises(InvalidInput, match="limits must be"):
        puma(np.eye(4), limits="none")


def test_solver_for_takes_limits_as_one_array():
    """A (2, n) array of limits is a pair (lower, upper), as a tuple is (it raised numpy's
    ambiguous-truth ValueError before)."""
    robot = redik.load("puma560")
    puma = solver_for(robot)
    q = np.array([0.3, -0.4, 0.5, 0.2, 0.6, -0.1])
    T = robot.fk(q)
    wide = np.array([puma.lower, puma.upper])
    assert len(puma(T, limits=wide)) == len(puma(T, limits=(puma.lower, puma.upper))) >= 1
    narrow = np.array([q - 1e-3, q + 1e-3])
    assert len(puma(T, limits=narrow)) == 1
    with pytest.raises(InvalidInput, match="limits"):
        puma(T, limits=np.zeros((3, 6)))


def test_solver_for_refuses_a_model_that_does_not_match_its_family():
    with pytest.raises(ModelError, match="needed by the ur solver"):
        solver_for(redik.load("puma560"), family="ur")
    with pytest.raises(ModelError, match="has 6 joints, the planar_2r solver expects 2"):
        solver_for(redik.load("puma560"), family="planar_2r")
    xml = redik.scene_path("planar_3r").read_text()
    tampered = xml.replace('<numeric name="l1" data="1"/>', '<numeric name="l1" data="1.2"/>')
    assert tampered != xml
    with pytest.raises(ModelError, match="does not move like the planar_3r DH table"):
        solver_for(redik.Robot.from_xml_string(tampered))
    with pytest.raises(InvalidInput, match="no closed-form solver for 'panda'"):
        solver_for(redik.load("panda"))


@pytest.mark.parametrize("name", ["puma560", "ur5e", "stanford_arm"])
def test_puma_ur_stanford_take_the_compiled_path_with_the_family_labels(name):
    """AnalyticSolver solves PUMA, UR and Stanford targets with the compiled decomposition and names
    each solution by the family's slot: the same labels and joint vectors as the family's
    own kernel, with and without limits; a singular target goes to the family's kernel
    (its texts and families)."""
    robot = redik.load(name)
    fast = solver_for(robot)
    assert fast.compiled is not None
    family_kernel = dataclasses.replace(fast, compiled=None)
    rng = np.random.default_rng(21)
    for q in robot.random_q(rng, size=300):
        T = robot.fk(q)
        for limits in ("robot", None):
            assert fast._compiled_solutions(T, limits, DEFAULT_TOL) is not None
            a, b = fast(T, limits=limits), family_kernel(T, limits=limits)
            assert a.labels == b.labels
            np.testing.assert_allclose(a.as_array(), b.as_array(), atol=1e-9)
    q = robot.random_q(rng)
    q[4] = 0.0  # wrist singular
    T = robot.fk(q)
    assert fast._compiled_solutions(T, None, DEFAULT_TOL) is None
    a, b = fast(T, limits=None), family_kernel(T, limits=None)
    assert a.labels == b.labels and a.singular and len(a.families) == len(b.families) >= 1
