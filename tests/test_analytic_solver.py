"""solver_for: the closed form of a robot found from its screw axes, never from its name."""

from __future__ import annotations

import re

import numpy as np
import pytest

import redik
from redik.core.exceptions import InvalidInput, ModelError
from redik.models.dh import DHRow
from redik.models.scene_library import get_scene
from redik.solvers.analytic import SixJointSolver, SmallArmSolver, solver_for, wrap_angle

SCENES = ["planar_2r", "planar_3r", "rrp_polar", "hexapod_leg", "puma560", "ur5e", "stanford_arm"]
POSITION_ONLY = {"planar_2r", "rrp_polar", "hexapod_leg"}


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


@pytest.mark.parametrize("name", ["planar_2r", "planar_3r", "rrp_polar", "hexapod_leg"])
def test_small_arm_parameters_are_read_off_the_axes(name):
    """The lengths come from the screw axes and equal the scene library's (the heights d1 and
    z_offset are measured from the first axis' point nearest the world origin, which is the
    scene's base origin)."""
    solver = solver_for(redik.load(name))
    assert isinstance(solver, SmallArmSolver) and solver.kind == name
    expected = dict(get_scene(name).parameters)
    for key, value in expected.items():
        assert solver.params[key] == pytest.approx(value, abs=1e-12), key


def _strip_numerics(xml: str) -> str:
    """The MJCF without its <custom> block (the DH numerics a family solver once needed)."""
    stripped = re.sub(r"^\s*<custom>.*?</custom>", "", xml, flags=re.DOTALL | re.MULTILINE)
    assert "<numeric" not in stripped
    return stripped


@pytest.mark.parametrize("file_name", ["ur5e.xml", "robot.xml", "puma560.xml"])
def test_the_ur5e_xml_solves_under_any_file_name(tmp_path, file_name):
    """The bundled UR5e scene without its numerics, saved as Menagerie's ur5e.xml, as
    robot.xml and under another arm's name: the same class and solutions each time (the
    model's name once chose a family and then required its numerics)."""
    path = tmp_path / file_name
    path.write_text(_strip_numerics(redik.models.scene_path("ur5e").read_text()))
    robot = redik.load(path)
    reference = redik.load("ur5e")
    solver = solver_for(robot)
    assert isinstance(solver, SixJointSolver) and solver.kind == "three_parallel_two_intersecting"
    rng = np.random.default_rng(3)
    for q in reference.random_q(rng, size=10):
        T = reference.fk(q)
        ours = solver(T)
        np.testing.assert_allclose(robot.fk(q), T, atol=1e-12)
        assert ours.labels == solver_for(reference)(T).labels
        np.testing.assert_allclose(ours.as_array(), solver_for(reference)(T).as_array())


def test_a_planar_arm_saved_under_a_6r_name_is_still_planar(tmp_path):
    path = tmp_path / "puma560.xml"
    path.write_text(_strip_numerics(redik.models.scene_path("planar_3r").read_text()))
    assert solver_for(redik.load(path)).kind == "planar_3r"


def test_solver_for_reports_unreachable_and_off_plane_targets():
    planar = solver_for(redik.load("planar_2r"))
    assert "off the arm's plane" in planar([1.0, 0.5, 0.2]).reason
    assert "beyond the reach" in planar([3.0, 0.0, 0.0]).reason
    with pytest.raises(InvalidInput, match="limits must be"):
        planar([1.0, 0.5, 0.0], limits="none")


def test_solver_for_takes_limits_as_one_array():
    """A (2, n) array of limits is a pair (lower, upper), as a tuple is."""
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


def test_arms_without_a_closed_form_are_refused_by_what_their_axes_are():
    with pytest.raises(ModelError, match="no closed form fits 'panda' \\(7 joints\\)"):
        solver_for(redik.load("panda"))
    anthropomorphic = redik.Robot.from_dh(
        [DHRow(0.0, 0.3, np.pi / 2), DHRow(0.4, 0.0, 0.0), DHRow(0.3, 0.1, 0.0)],
        limits=[(-np.pi, np.pi)] * 3,
        name="offset_3r",
    )
    with pytest.raises(ModelError, match="its axes are none of"):
        solver_for(anthropomorphic)
    with pytest.raises(InvalidInput, match="method='elimination' is for 6-joint arms"):
        solver_for(redik.load("planar_2r"), method="elimination")
    with pytest.raises(InvalidInput, match="method must be"):
        solver_for(redik.load("ur5e"), method="decomposed")  # type: ignore[arg-type]
    rng = np.random.default_rng(9)
    rows = [
        DHRow(rng.uniform(0.1, 0.4), rng.uniform(-0.2, 0.2), rng.uniform(0.3, 1.2))
        for _ in range(6)
    ]
    general = redik.Robot.from_dh(rows, limits=[(-np.pi, np.pi)] * 6, name="general_6r")
    with pytest.raises(ModelError, match="no closed-form class fits 'general_6r'"):
        solver_for(general, method="closed_form")
    assert (solver_for(general).kind, solver_for(general).method) == ("general", "elimination")


@pytest.mark.slow
def test_compile_ahead_runs_every_class_once():
    """python -m redik.solvers.analytic.compile: one step per 6-joint class, the two splits
    of the elimination and the small solvers' selection, each solving its generated arm."""
    from redik.core.compile_ahead import compile_all
    from redik.solvers.analytic.compile import STEPS
    from redik.solvers.analytic.geometry import KINDS

    lines = []
    seconds = compile_all(STEPS, report=lines.append)
    assert set(seconds) == set(STEPS) and set(KINDS) <= set(seconds)
    assert len(lines) == len(STEPS) and all(value >= 0.0 for value in seconds.values())


@pytest.mark.parametrize("name", ["planar_2r", "rrp_polar"])
def test_small_arm_batch_equals_single_calls(name):
    robot = redik.load(name)
    solver = solver_for(robot)
    rng = np.random.default_rng(5)
    T = np.stack([robot.fk(q) for q in robot.random_q(rng, size=20)])
    T[3, :3, 3] = (5.0, 0.0, 0.0)  # out of reach
    batch = solver.batch(T)
    assert batch.q.shape[:2] == batch.valid.shape == (20, len(batch.labels))
    for b in range(20):
        one = solver(T[b])
        assert batch.valid[b].sum() == len(one)
        for solution in one:
            code = batch.labels.index(solution.label)
            np.testing.assert_allclose(batch.q[b, code], solution, atol=1e-12)
