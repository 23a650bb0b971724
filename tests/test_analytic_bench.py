"""``redik bench analytic``'s comparison with ik-geo builds the same arm and poses (no timing
claims are tested: benchmarks are not tests)."""

from __future__ import annotations

import time

import numpy as np
import pytest

import redik
from redik.apps.bench.analytic import measure_ik_geo


@pytest.mark.parametrize("name", ["puma560", "ur5e"])
def test_ik_geo_gets_the_same_arm_and_finds_the_same_number_of_solutions(name):
    ik_geo = pytest.importorskip("ik_geo")
    row = measure_ik_geo(redik.load(name), 20, 1, 3, ik_geo, time.perf_counter)
    assert row is not None
    # ik-geo's answers reach redik's targets by redik's FK: the geometry was translated right.
    assert row["ik_geo_error"] < 1e-9
    assert row["solutions"] == pytest.approx(row["ik_geo_solutions"])
    assert row["redik_us"] > 0.0 and row["ik_geo_us"] > 0.0 and row["labelled_us"] > 0.0


def test_ik_geo_general_solver_gets_the_same_arm():
    """The third table's ik-geo gen_six_dof is built from the same screw chain: its answers
    reach redik's target to its own (approximate, 2-D search) accuracy."""
    ik_geo = pytest.importorskip("ik_geo")
    from redik.apps.bench.analytic import GENERAL_ROWS, _ik_geo_general
    from redik.models.dh import DHRow

    robot = redik.Robot.from_dh(
        [DHRow(*row) for row in GENERAL_ROWS], limits=[(-3.14, 3.14)] * 6, name="general"
    )
    call = _ik_geo_general(robot, ik_geo)
    T = robot.fk(robot.random_q(np.random.default_rng(0)))
    answers = call(T)
    assert len(answers) >= 1
    assert min(np.abs(robot.fk(q) - T).max() for q in answers) < 1e-2
