"""The process and Ray engines give the same results as the local one, chunk for chunk."""

from __future__ import annotations

import dataclasses
import importlib.util
import sys

import numpy as np
import pytest

import redik
from redik.solvers.batch import Chain, forward_kinematics, solve_batch
from redik.solvers.batch.engines import map_chunks


@pytest.fixture(scope="module")
def problem() -> tuple[Chain, np.ndarray]:
    robot = redik.load("panda")
    chain = Chain.from_robot(robot)
    T = forward_kinematics(chain, robot.random_q(21, size=600))
    T[17, 1, 1] = np.nan  # an invalid target travels through every engine the same way
    return chain, T


def _assert_identical(a, b) -> None:
    for field in dataclasses.fields(a):
        np.testing.assert_array_equal(getattr(a, field.name), getattr(b, field.name))


def _square(shared: int, x: int) -> int:
    return shared * x * x


def test_map_chunks_keeps_order_and_reports_progress():
    seen: list[int] = []
    chunks = ((x,) for x in range(9))
    out = map_chunks(_square, 2, chunks, engine="process", workers=2, on_result=seen.append)
    assert out == [2 * x * x for x in range(9)] == seen


@pytest.mark.parametrize("workers", [1, 2])
def test_process_engine_matches_local(problem, workers):
    chain, T = problem
    local = solve_batch(chain, T, seed=5, engine="local", chunk_size=128)
    pooled = solve_batch(chain, T, seed=5, engine="process", workers=workers, chunk_size=128)
    _assert_identical(local, pooled)
    assert local.status_names[17] == "invalid"


def test_missing_ray_says_how_to_install(problem, monkeypatch):
    chain, T = problem
    monkeypatch.setitem(sys.modules, "ray", None)  # import ray now raises ImportError
    with pytest.raises(redik.BackendError, match=r'pip install "redik\[ray\]"'):
        solve_batch(chain, T[:10], engine="ray")


@pytest.mark.skipif(importlib.util.find_spec("ray") is None, reason="ray is not installed")
def test_ray_engine_matches_local(problem):
    import ray

    chain, T = problem
    local = solve_batch(chain, T, seed=5, engine="local", chunk_size=128)
    started = not ray.is_initialized()
    try:
        remote = solve_batch(chain, T, seed=5, engine="ray", workers=2, chunk_size=128)
        assert ray.cluster_resources().get("CPU") == 2
    finally:
        if started:
            ray.shutdown()
    _assert_identical(local, remote)
