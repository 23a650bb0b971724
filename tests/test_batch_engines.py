"""The process and Ray engines give the same results as the local one, chunk for chunk; an
Engine owns its pool (kept between calls, stopped on close and at exit)."""

from __future__ import annotations

import dataclasses
import importlib.util
import os
import subprocess
import sys
import time

import numpy as np
import pytest

import redik
from redik.solvers.batch import Chain, forward_kinematics, solve_batch
from redik.solvers.batch.engines import (
    Engine,
    close_shared_engines,
    default_workers,
    map_chunks,
    shared_engine,
)


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


@pytest.mark.slow
def test_map_chunks_keeps_order_and_reports_progress():
    seen: list[int] = []
    chunks = ((x,) for x in range(9))
    out = map_chunks(_square, 2, chunks, engine="process", workers=2, on_result=seen.append)
    assert out == [2 * x * x for x in range(9)] == seen


@pytest.mark.slow
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


@pytest.mark.slow
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


def _pid(shared: None, x: int) -> int:
    return os.getpid()


def _wait_gone(pids: set[int], timeout: float = 10.0) -> set[int]:
    """The pids still alive after up to ``timeout`` seconds."""
    deadline = time.monotonic() + timeout
    alive = set(pids)
    while alive and time.monotonic() < deadline:
        for pid in list(alive):
            try:
                os.kill(pid, 0)
            except ProcessLookupError:
                alive.discard(pid)
            else:  # a child not yet reaped counts as gone once it is a zombie
                with open(f"/proc/{pid}/stat") as stat:
                    if stat.read().split(") ", 1)[1].startswith("Z"):
                        alive.discard(pid)
        time.sleep(0.05)
    return alive


@pytest.mark.slow
def test_an_engine_keeps_its_pool_between_calls_and_closes_it():
    with Engine("process", workers=2) as engine:
        assert not engine.in_process
        first = set(engine.map(_pid, None, ((i,) for i in range(16))))
        second = set(engine.map(_pid, None, ((i,) for i in range(16))))
        assert os.getpid() not in first
        assert len(first | second) <= 2  # the same two workers served both calls
    assert engine.closed
    assert not _wait_gone(first | second)
    with pytest.raises(redik.InvalidInput, match="closed"):
        engine.map(_pid, None, [(0,)])
    engine.close()  # closing twice is harmless


@pytest.mark.slow
def test_solve_batch_on_an_engine_object_matches_local(problem):
    chain, T = problem
    local = solve_batch(chain, T, seed=5, engine="local", chunk_size=128)
    with Engine("process", workers=2) as engine:
        pooled = solve_batch(chain, T, seed=5, engine=engine, chunk_size=128)
        again = solve_batch(chain, T, seed=5, engine=engine, chunk_size=200)
        with pytest.raises(redik.InvalidInput, match="belong to the engine"):
            solve_batch(chain, T, engine=engine, workers=2)
    _assert_identical(local, pooled)
    _assert_identical(local, again)
    with pytest.raises(redik.InvalidInput, match="closed"):
        solve_batch(chain, T, engine=engine)


def test_engine_names_share_one_engine_until_closed():
    engine = shared_engine("process", 2)
    assert shared_engine("process", 2) is engine
    assert shared_engine("process", 3) is not engine
    assert shared_engine("local") is shared_engine("local", default_workers())
    close_shared_engines()
    assert engine.closed
    renewed = shared_engine("process", 2)
    assert renewed is not engine and not renewed.closed


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("gpu",), "engine must be one of"),
        (("process", 0), "workers"),
        (("process", True), "workers"),
        (("process", 2.5), "workers"),
        (("local", None, "10.0.0.1:6379"), "address"),
    ],
)
def test_bad_engine_arguments_are_refused(args, message):
    with pytest.raises(redik.InvalidInput, match=message):
        Engine(*args)


@pytest.mark.slow
def test_a_shared_pool_stops_when_the_interpreter_exits():
    script = (
        "from redik.solvers.batch.engines import map_chunks\n"
        "import os\n"
        "def pid(shared, x):\n"
        "    return os.getpid()\n"
        "print(*sorted(set(map_chunks(pid, None, [(i,) for i in range(8)], 'process', 2))))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=120, check=True
    )
    workers = {int(pid) for pid in done.stdout.split()}
    assert workers and not _wait_gone(workers)
