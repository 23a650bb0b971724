"""``redik bench analytic``'s comparison with ik-geo builds the same arm and poses (no timing
claims are tested: benchmarks are not tests)."""

from __future__ import annotations

import time

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
