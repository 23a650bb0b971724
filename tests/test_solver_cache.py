"""redik.solvers.cache: one solver cache per robot, built once under a lock, gone with the robot."""

from __future__ import annotations

import gc
import time
import weakref
from concurrent.futures import ThreadPoolExecutor

import redik
from redik.solvers.cache import solver_cache
from tests.conftest import ARM_XML


def test_solver_cache_builds_an_entry_once_for_racing_threads():
    cache = solver_cache(redik.Robot.from_xml_string(ARM_XML))
    builds = []

    def build() -> object:
        time.sleep(0.01)  # every thread arrives while the first one builds
        builds.append(object())
        return builds[-1]

    with ThreadPoolExecutor(8) as pool:
        entries = list(pool.map(lambda _: cache.get_or_build("key", build), range(8)))
    assert len(builds) == 1 and all(entry is builds[0] for entry in entries)
    assert cache.get_or_build("key", build, valid=lambda entry: False) is builds[1]
    assert list(cache) == ["key"] and len(cache) == 1


def test_each_robot_has_its_own_cache_which_goes_with_it():
    robot, other = redik.Robot.from_xml_string(ARM_XML), redik.Robot.from_xml_string(ARM_XML)
    cache = solver_cache(robot)
    assert solver_cache(robot) is cache and solver_cache(other) is not cache
    cache["key"] = object()
    assert "key" not in solver_cache(other)
    gone = weakref.ref(cache)
    del robot, cache
    gc.collect()
    assert gone() is None
    for _ in range(20):  # a new robot, often at the address of the last, starts empty
        robot = redik.Robot.from_xml_string(ARM_XML)
        assert "key" not in solver_cache(robot)
        solver_cache(robot)["key"] = object()
        del robot
        gc.collect()


def test_racing_threads_get_one_cache_per_robot():
    robot = redik.Robot.from_xml_string(ARM_XML)
    with ThreadPoolExecutor(8) as pool:
        caches = list(pool.map(lambda _: solver_cache(robot), range(64)))
    assert all(cache is caches[0] for cache in caches)
