"""``redik bench analytic`` compares like with like: ik-geo gets the same arm and targets, the
random arms are of the class they claim (no timing claims are tested: benchmarks are not
tests)."""

from __future__ import annotations

import numpy as np
import pytest

import redik
from redik.apps.bench.analytic import (
    CLASSES,
    ik_geo_arm,
    jaco,
    robot_of,
    shadow_first_finger,
    two_special_arms,
)
from redik.solvers.analytic import solver_for
from redik.solvers.analytic.geometry import Chain, random_arm, screws_of


@pytest.mark.parametrize("kind", CLASSES)
def test_random_arms_are_of_their_class_and_ik_geo_solves_the_same_arm(kind):
    """redik finds the class from the screws (the searched classes have none: the
    elimination); ik-geo's exact answers for a target reach it by redik's FK, so the geometry
    was handed over right."""
    ik_geo = pytest.importorskip("ik_geo")
    rng = np.random.default_rng(0)
    robot = robot_of(*random_arm(kind, rng))
    solver = solver_for(robot)
    closed = kind in CLASSES[:5]
    assert solver.kind == (kind if closed else "general")
    call = ik_geo_arm(robot, kind, ik_geo)
    best = []
    for q in rng.uniform(-np.pi, np.pi, (5, 6)):
        T = robot.fk(q)
        # ik-geo flags nearly every answer of its searches least-squares: take them all there
        # (a search can miss a target altogether: the median over targets is compared).
        answers = [np.asarray(x) for x, least_squares in call(T) if not (closed and least_squares)]
        best.append(min((np.abs(robot.fk(x) - T).max() for x in answers), default=np.inf))
    assert np.median(best) < (1e-9 if closed else 1e-2)


@pytest.mark.parametrize("name", ["puma560", "ur5e"])
def test_ik_geo_finds_the_bundled_arms_solutions(name):
    ik_geo = pytest.importorskip("ik_geo")
    robot = redik.load(name)
    solver = solver_for(robot)
    call = ik_geo_arm(robot, solver.kind, ik_geo)
    for q in robot.random_q(np.random.default_rng(1), size=5):
        T = robot.fk(q)
        ours = solver.raw(T, limits=None)
        theirs = np.array([x for x, least_squares in call(T) if not least_squares])
        assert min(np.abs(robot.fk(x) - T).max() for x in theirs) < 1e-9
        assert all(np.abs(redik.lie.wrap_angle(ours - x)).max(axis=1).min() < 1e-8 for x in theirs)


def test_the_special_arms_have_the_geometry_they_claim():
    """Consecutive axes of the Jaco meet or are parallel, angled 90°, 0°, 90°, 60°, 60°; the
    finger has 3∩4 and 4∥5∥6; the two-special arms are named by their pairs."""
    arm = Chain.from_screws(*screws_of(jaco()))
    angles = [np.degrees(np.arccos(abs(arm.h[i] @ arm.h[i + 1]))) for i in range(5)]
    np.testing.assert_allclose(angles, [90, 0, 90, 60, 60], atol=1e-9)
    assert all(arm.parallel(i, i + 1) or arm.meeting_point(i, i + 1) is not None for i in range(5))
    assert arm.common_point(3, 4, 5) is None
    finger = Chain.from_screws(*screws_of(shadow_first_finger()))
    assert finger.meeting_point(2, 3) is not None
    assert finger.parallel(3, 4) and finger.parallel(4, 5)
    arms = two_special_arms()
    assert len(arms) == 40 and len({name for name, _ in arms}) == 40
