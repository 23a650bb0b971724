"""redik bench qp's G1 stack: its collision pairs, and redik's step equal to mink's."""

from __future__ import annotations

import pytest

import redik
from redik.apps.bench import _qp_anchors as qp_anchors


@pytest.fixture(scope="module")
def g1():
    return redik.load(qp_anchors.G1, joints="all", floating_base=True)


def test_g1_pairs_are_arm_against_body_and_spread_over_the_list(g1):
    every = qp_anchors.g1_pairs(g1, 10**6)
    assert len(every) > qp_anchors.G1_PAIRS
    some = qp_anchors.g1_pairs(g1, 5)
    assert len(set(some)) == 5 and set(some) <= set(every) and some[0] == every[0]
    assert qp_anchors.g1_pairs(g1) == qp_anchors.g1_pairs(g1, qp_anchors.G1_PAIRS)
    assert qp_anchors.g1_pairs(g1, 0) == []


@pytest.mark.slow
@pytest.mark.parametrize("pairs", [0, 3])
def test_g1_step_of_redik_equals_minks(pairs):
    medians, difference, count = qp_anchors.g1_steps(5, pairs)
    assert count == pairs
    assert set(medians) == {"redik weighted", "mink weighted"}
    assert difference < 1e-6
