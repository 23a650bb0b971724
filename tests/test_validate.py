"""Boundary checks of scalar options (redik/core/validate.py): one integer check everywhere."""

from __future__ import annotations

import numpy as np
import pytest

import redik
from redik.apps import workspace
from redik.core.validate import integer, seed
from redik.solvers.analytic.srs import self_motion_curves


def test_integer_takes_python_and_numpy_integers_and_refuses_the_rest():
    assert integer(3, "n") == 3 and type(integer(np.int64(3), "n")) is int
    assert integer(None, "n", allow_none=True) is None
    for bad in (True, 3.0, "3", None, 1j, [3]):
        with pytest.raises(redik.InvalidInput, match=r"n must be an integer ≥ 0, got"):
            integer(bad, "n")
    with pytest.raises(redik.InvalidInput, match=r"n must be an integer ≥ 2 \(or None\), got 1"):
        integer(1, "n", 2, allow_none=True)


def test_every_count_option_uses_the_one_check():
    planar = redik.load("planar_2r")
    T = planar.fk(planar.home)
    calls = {
        "max_iterations": lambda v: redik.solve_pose(planar, T, max_iterations=v),
        "restarts": lambda v: redik.solve_pose(planar, T, restarts=v),
        "n_starts": lambda v: redik.solve_all(planar, T, n_starts=v),
        "chunk_size": lambda v: redik.solve_batch(planar, T[None], chunk_size=v),
        "workers": lambda v: redik.solve_batch(planar, T[None], workers=v),
        "priority": lambda v: redik.PostureTask(priority=v),
        "max_samples": lambda v: redik.explore_self_motion(planar, T, max_samples=v),
    }
    for name, call in calls.items():
        for bad in (2.0, True, "2"):
            with pytest.raises(redik.InvalidInput, match=f"{name}.* must be an integer ≥"):
                call(bad)
    with pytest.raises(redik.InvalidInput, match="max_iterations must be an integer ≥ 0"):
        redik.solve_equations(lambda q: q, [1.0], [0.0], max_iterations=-1)


def test_a_numpy_integer_is_a_count_everywhere():
    # self_motion_curves refused np.int64 (an isinstance(samples, int) check of its own).
    iiwa = redik.load("iiwa14")
    curves = self_motion_curves(iiwa, iiwa.fk(iiwa.home), spacing=0.2, samples=np.int64(64))
    assert curves and all(np.all(np.isfinite(curve)) for curve in curves)
    assert redik.PostureTask(priority=np.int64(1)).priority == 1


def test_seed_is_an_integer_or_none_and_refuses_bools_and_generators():
    assert seed(None) is None
    assert seed(3) == 3 and type(seed(np.uint32(3))) is int
    for bad in (True, False, np.True_, -1, 1.0, "1", [1]):
        with pytest.raises(redik.InvalidInput, match=r"seed must be None or an integer ≥ 0, got"):
            seed(bad)
    for bad in (np.random.default_rng(0), np.random.SeedSequence(0), np.random.PCG64(0)):
        with pytest.raises(
            redik.InvalidInput, match=rf"got a numpy {type(bad).__name__}: pass an int"
        ):
            seed(bad)


def test_every_seed_option_uses_the_one_check():
    """``seed=True`` was taken for seed 1 by solve_pose, solve_all, explore_self_motion and the
    workspace maps (numpy's default_rng accepts a bool), while ``respect_limits=1`` is refused."""
    planar = redik.load("planar_2r")
    T = planar.fk(planar.home)
    panda = redik.load("panda")
    T_panda = panda.fk(panda.home)
    calls = {
        "solve_pose dls": lambda v: redik.solve_pose(planar, T, seed=v),
        "solve_pose newton": lambda v: redik.solve_pose(
            planar, T, method="newton", restarts=1, seed=v
        ),
        "solve_pose qp": lambda v: redik.solve_pose(planar, T, method="qp", restarts=1, seed=v),
        "solve_all": lambda v: redik.solve_all(planar, T, n_starts=2, seed=v),
        "solve_batch": lambda v: redik.solve_batch(planar, T[None], seed=v),
        "explore_self_motion": lambda v: redik.explore_self_motion(
            panda, T_panda, max_samples=20, seed=v
        ),
        "reachability": lambda v: workspace.reachability(
            planar, np.zeros((1, 3)), orientations=1, seed=v
        ),
        "sample": lambda v: workspace.sample(planar, 2, orientations=1, seed=v),
    }
    for name, call in calls.items():
        for bad in (True, -1, 1.5, np.random.default_rng(1), np.random.SeedSequence(1)):
            with pytest.raises(redik.InvalidInput, match=r"seed must be None or an integer ≥ 0"):
                call(bad)
        assert call(np.int64(1)) is not None, name  # a numpy integer is a seed everywhere


def test_real_array_refuses_what_numpy_would_truncate_or_fail_on():
    from redik.core.validate import MAX_COORDINATE, as_vector, real_array

    assert real_array([1, 2], "x").dtype == float
    for bad, why in (([1j, 2], "dtype complex"), (["a"], "dtype <U1"), ([[1], [2, 3]], "real")):
        with pytest.raises(redik.InvalidInput, match=f"x must .*{why}"):
            real_array(bad, "x")
    with pytest.raises(redik.InvalidPose, match="T must hold real numbers"):
        real_array("eye", "T", redik.InvalidPose)
    np.testing.assert_array_equal(as_vector((1, 2, 3), 3, "p"), [1.0, 2.0, 3.0])
    with pytest.raises(redik.InvalidInput, match=r"p must have shape \(3,\), got \(2,\)"):
        as_vector([1, 2], 3, "p")
    with pytest.raises(redik.InvalidInput, match="p must be finite, holds NaN or inf"):
        as_vector([1, np.nan, 2], 3, "p")
    assert MAX_COORDINATE == 1e10  # MuJoCo's mjMAXVAL
