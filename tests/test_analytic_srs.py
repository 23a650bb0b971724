"""Exact self-motion of an S-R-S arm by the arm angle (redik.solvers.analytic.srs) on iiwa14,
checked
by MuJoCo's FK and against the numerical exploration of explore_self_motion."""

from __future__ import annotations

import numpy as np
import pytest

import redik
from redik.core.exceptions import ModelError
from redik.lie import wrap_angle
from redik.solvers.analytic.srs import SRSArm, self_motion_curves


def _torus(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.abs(wrap_angle(np.asarray(a) - b)).max(axis=-1)


@pytest.fixture(scope="module")
def iiwa():
    return redik.load("iiwa14")


def test_every_arm_angle_gives_eight_configurations_reaching_the_pose(iiwa):
    arm = SRSArm.from_robot(iiwa)
    rng = np.random.default_rng(1)
    for _ in range(3):
        T = iiwa.fk(iiwa.random_q(rng))
        q, valid = arm.at(T, np.linspace(-np.pi, np.pi, 7))
        assert valid.all()
        for configuration in q.reshape(-1, 7):
            assert np.abs(iiwa.fk(configuration) - T).max() < 1e-9


def test_the_loops_are_continuous_closed_and_pass_through_the_generating_q(iiwa):
    rng = np.random.default_rng(2)
    for _ in range(3):
        q_true = iiwa.random_q(rng)
        T = iiwa.fk(q_true)
        curves = self_motion_curves(iiwa, T, spacing=0.05)
        assert 1 <= len(curves) <= 8
        for curve in curves:
            closed = np.vstack([curve, curve[:1]])
            assert _torus(closed[1:], closed[:-1]).max() <= 0.05 + 1e-12
            for q in curve[:: max(len(curve) // 10, 1)]:
                assert np.abs(iiwa.fk(q) - T).max() < 1e-9
        assert min(_torus(c, q_true).min() for c in curves) <= 0.05


def test_exact_exploration_matches_the_numerical_one(iiwa):
    rng = np.random.default_rng(3)
    T = iiwa.fk(iiwa.random_q(rng))
    spacing = 0.05
    exact = redik.explore_self_motion(iiwa, T, spacing=spacing, seed=0, exact=True)
    numeric = redik.explore_self_motion(iiwa, T, spacing=spacing, seed=0, n_starts=64)
    assert exact.success and numeric.success and len(exact) and len(numeric)
    assert np.abs(exact.position_error).max() < 1e-9
    for q in exact.samples:
        assert iiwa.within_limits(q, tol=1e-9)
    # Every numerically traced sample lies on an exact loop and the exact samples lie on the
    # numerically traced curves (both sampled at the spacing, so within one spacing).
    assert max(_torus(exact.samples, q).min() for q in numeric.samples) <= spacing
    assert max(_torus(numeric.samples, q).min() for q in exact.samples) <= spacing
    assert exact.n_components == numeric.n_components


def test_arms_that_are_not_srs_are_refused():
    with pytest.raises(ModelError, match="spherical shoulder and wrist"):
        SRSArm.from_robot(redik.load("panda"))
    with pytest.raises(ModelError, match="7R"):
        SRSArm.from_robot(redik.load("ur5e"))
