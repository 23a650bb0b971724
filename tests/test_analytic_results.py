"""The result types of redik.solvers.analytic: labelled solutions, limits modulo 2π, wrapping."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import redik
from redik.core.exceptions import InvalidInput
from redik.solvers.analytic import JointSolution, planar_2r, solver_for, wrap_angle
from redik.solvers.analytic.results import limit_representatives


def test_wrap_angle_range_is_minus_pi_exclusive_to_pi_inclusive():
    values = np.array([np.pi, -np.pi, 3 * np.pi, -1e-20, 2 * np.pi - 1e-17, 7.0, -7.0])
    wrapped = wrap_angle(values)
    assert np.all(wrapped > -np.pi) and np.all(wrapped <= np.pi)
    assert wrapped[0] == np.pi and wrapped[1] == np.pi
    assert np.allclose(np.exp(1j * wrapped), np.exp(1j * values))


def test_joint_solution_is_an_array_with_a_label_that_arithmetic_drops():
    solution = JointSolution([0.1, 0.2], "elbow-up", "note")
    assert isinstance(solution, np.ndarray) and solution.label == "elbow-up"
    assert type(solution + 1.0) is np.ndarray and type(solution.q) is np.ndarray
    assert isinstance(float(solution.sum()), float)
    copy = pickle.loads(pickle.dumps(solution))
    assert copy.label == "elbow-up" and copy.singular == "note" and np.array_equal(copy, solution)
    assert "elbow-up" in repr(solution)


def test_limit_representatives_shift_by_two_pi_or_reject():
    revolute = np.array([True, True, False])
    lower = np.array([0.0, -np.pi, 0.0])
    upper = np.array([2 * np.pi, 0.0, 1.0])
    q = np.array([[-0.5, 0.3, 0.5], [0.5, -0.3, 0.5], [0.5, -0.3, 1.5], [-0.5, 7.0, 0.5]])
    shifted, inside = limit_representatives(q, lower, upper, revolute)
    assert inside.tolist() == [
        [True, False, True],
        [True, True, True],
        [True, True, False],
        [True, False, True],
    ]
    assert np.isclose(shifted[0, 0], 2 * np.pi - 0.5)
    q = np.array([[-0.5, -0.3 - 4 * np.pi, 0.5]])
    shifted, inside = limit_representatives(q, lower, upper, revolute)
    assert inside.all() and np.isclose(shifted[0, 1], -0.3)
    wide = limit_representatives(
        np.array([[3.0, 0.0, 0.0]]), np.full(3, -3 * np.pi), np.full(3, 3 * np.pi), revolute
    )
    assert wide[1].all() and wide[0][0, 0] == 3.0  # already in range: unchanged


def test_results_are_sequences_with_helpers():
    result = planar_2r(1.2, 0.5, 1.0, 0.8)
    assert len(result) == 2 and list(result) == list(result.solutions)
    assert result.as_array().shape == (2, 2)
    assert result.nearest(result[1] + 2 * np.pi).label == result[1].label
    assert result.by_label("elbow-up") is result[1]
    with pytest.raises(InvalidInput, match=r"q_ref must have shape \(2,\)"):
        result.nearest(np.zeros(3))
    empty = planar_2r(3.0, 0.0, 1.0, 0.8)
    assert not empty and empty.as_array().shape == (0, 2)
    with pytest.raises(InvalidInput, match="no solution to choose from: target is 3 m"):
        empty.nearest(np.zeros(2))


def test_limits_keep_the_in_range_representative_and_explain_an_empty_result():
    lower, upper = np.array([0.0, 0.0]), np.array([2 * np.pi, np.pi])
    result = planar_2r(1.2, -0.5, 1.0, 0.8, limits=(lower, upper))
    assert result.labels == ("elbow-down",) and 0.0 <= result[0][0] <= 2 * np.pi
    assert result[0][0] > np.pi  # the wrapped θ1 was negative: shifted by 2π
    blocked = planar_2r(1.2, -0.5, 1.0, 0.8, limits=(np.array([0.0, 3.0]), np.array([0.1, 3.1])))
    assert not blocked and blocked.reachable
    assert blocked.reason == (
        "none of the 2 solutions lies within the joint limits "
        "(joints out of range in some solution: [0, 1])"
    )


def test_results_are_built_lazily_immutable_and_picklable():
    """IKSolutions keeps the (k, n) array and labels and makes its JointSolution rows once,
    on first use; the public attributes are read-only; pickling keeps rows and labels."""
    robot = redik.load("ur5e")
    T = robot.fk(np.array([0.3, -1.2, 1.4, -1.6, -1.5, 0.4]))
    result = solver_for(robot)(T, limits=None)
    assert len(result) == len(result.labels) == 8
    np.testing.assert_array_equal(result.as_array(), np.array([s.q for s in result]))
    assert result.solutions is result.solutions  # made once
    assert [s.label for s in result] == list(result.labels)
    assert result.by_label(result.labels[3]) is result[3]
    assert result.nearest(result[5].q) is result[5]
    with pytest.raises(AttributeError):
        result.reachable = False  # type: ignore[misc]
    copy = pickle.loads(pickle.dumps(result))
    assert copy.labels == result.labels and np.array_equal(copy.as_array(), result.as_array())
    assert copy.reachable and "8 solution(s)" in repr(copy)
    assert result.as_array() is not result.as_array()  # a copy each time
