"""The closed-form solution set equals what many iterative solves find (issue 6).

For random reachable poses of the bundled PUMA 560 and UR5e, the analytic solutions within
the robot's joint limits and the distinct within-limits solutions of :func:`redik.solve_all`
must be the same set. Both sides apply the limits the same way: a revolute joint whose range
spans 2π or more is compared modulo 2π (solve_all clusters those joints so; the analytic filter
keeps one in-range representative), every other joint as is.
"""

from __future__ import annotations

import numpy as np
import pytest

import redik
from redik.solvers.analytic import solver_for, wrap_angle
from redik.solvers.pose import solve_all

#: A solve_all solution is within pos 1e-6 m / rot 1e-5 rad of the target, so its joints are
#: within about 1e-4 rad of the exact solution; distinct solutions are much farther apart.
MATCH_TOL = 1e-3


def _distance(robot: redik.Robot, q: np.ndarray, p: np.ndarray) -> float:
    periodic = robot.revolute & ((robot.upper - robot.lower) >= 2.0 * np.pi)
    difference = np.where(periodic, wrap_angle(q - p), q - p)
    return float(np.abs(difference).max())


@pytest.mark.parametrize(("name", "n_starts"), [("puma560", 80), ("ur5e", 120)])
def test_analytic_solutions_equal_the_distinct_solve_all_solutions(name, n_starts):
    robot = redik.load(name)
    solver = solver_for(robot)
    rng = np.random.default_rng(6)
    for index in range(3):
        T = robot.fk(robot.random_q(rng))
        analytic = solver(T).as_array()
        iterative = [r.q for r in solve_all(robot, T, n_starts=n_starts, seed=index)]
        assert len(analytic) >= 1
        for q in iterative:
            assert robot.within_limits(q, tol=1e-9)
            nearest = min(_distance(robot, q, a) for a in analytic)
            assert nearest <= MATCH_TOL, f"{name} pose {index}: solve_all found {q}, not analytic"
        for a in analytic:
            nearest = min((_distance(robot, q, a) for q in iterative), default=np.inf)
            assert nearest <= MATCH_TOL, f"{name} pose {index}: solve_all missed {a}"
        assert len(iterative) == len(analytic)
