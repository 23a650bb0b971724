"""redik.core.rotation_policy: one tolerance for every rotation and pose a user passes."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import redik
from redik import lie
from redik.core.exceptions import InvalidInput, InvalidPose, InvalidRotation, NearRotationWarning
from redik.core.rotation_policy import (
    as_pose,
    as_quaternion,
    as_rotation,
    check_rotations,
    closest_rotation,
    rotation_defect,
)
from tests.samples import random_rotation


def test_bad_inputs_raise_clear_errors():
    with pytest.raises(InvalidRotation, match="shape"):
        as_rotation(np.eye(4))
    with pytest.raises(InvalidRotation, match="NaN"):
        as_rotation(np.full((3, 3), np.nan))
    with pytest.raises(InvalidRotation, match="det"):
        as_rotation(np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(InvalidRotation, match="not a rotation"):
        as_rotation(2 * np.eye(3))
    bad_row = np.eye(4)
    bad_row[3, 0] = 1.0
    with pytest.raises(InvalidPose, match=r"\[0, 0, 0, 1\]"):
        as_pose(bad_row)
    with pytest.raises(InvalidPose, match="shape"):
        as_pose(np.eye(3))
    with pytest.raises(InvalidPose):
        as_pose(np.diag([1.0, 1.0, -1.0, 1.0]))
    with pytest.raises(InvalidInput, match="unit quaternion"):
        as_quaternion([1.0, 1.0, 0.0, 0.0])
    with pytest.raises(InvalidInput, match="convention"):
        lie.euler_angles(np.eye(3), "abc")


# Modern Robotics, IKinBody quiz (Ch. 6): the target as printed, three decimals.
QUIZ_T = np.array(
    [[-0.585, -0.811, 0, 0.076], [0.811, -0.585, 0, 2.608], [0, 0, 1, 0], [0, 0, 0, 1]]
)


def rotation_4_decimals() -> np.ndarray:
    return np.round(lie.so3_exp(np.array([0.3, -1.2, 0.7])), 4)


def rotation_off_by_1e_2() -> np.ndarray:
    R = lie.so3_exp(np.array([0.3, -1.2, 0.7]))
    R[0, 0] += 1e-2
    return R


def test_quiz_matrix_as_printed_is_projected_with_a_warning():
    assert 1e-5 < rotation_defect(QUIZ_T[:3, :3])[0] < 1e-4
    with pytest.warns(NearRotationWarning, match="closest rotation") as caught:
        T = as_pose(QUIZ_T)
    assert caught[0].filename == __file__  # attributed to the caller, not to redik
    R = T[:3, :3]
    np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-15)
    assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-15)
    np.testing.assert_array_equal(T[:3, 3], QUIZ_T[:3, 3])
    np.testing.assert_allclose(R, QUIZ_T[:3, :3], atol=5e-5)  # moved by less than the rounding
    # The projection is the nearest rotation: no rotation about z is closer in Frobenius norm.
    angles = np.linspace(-np.pi, np.pi, 20001)
    distances = [np.linalg.norm(lie.so3_exp([0, 0, a]) - QUIZ_T[:3, :3]) for a in angles]
    assert np.linalg.norm(R - QUIZ_T[:3, :3]) <= min(distances) + 1e-12


def test_four_decimal_rotation_is_projected_and_strict_refuses_both():
    R = rotation_4_decimals()
    with pytest.warns(NearRotationWarning):
        projected = as_rotation(R)
    np.testing.assert_allclose(projected, lie.so3_exp(np.array([0.3, -1.2, 0.7])), atol=1e-4)
    with pytest.raises(InvalidRotation, match="strict=True accepts"):
        as_rotation(R, strict=True)
    with pytest.raises(InvalidPose, match="strict=True accepts"):
        as_pose(QUIZ_T, strict=True)


def test_rotation_off_by_1e_2_and_reflections_are_refused_even_when_close():
    with pytest.raises(InvalidRotation, match=r"max\|RᵀR − I\| ≤ 0.002"):
        as_rotation(rotation_off_by_1e_2())
    reflection = np.diag([1.0, 1.0, -1.0]) + 1e-5  # tiny defect, det −1
    with pytest.raises(InvalidRotation, match="det"):
        as_rotation(reflection)


def test_exact_rotations_pass_unchanged_and_silently(rng):
    R = random_rotation(rng)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert as_rotation(R) is not None
        np.testing.assert_array_equal(as_rotation(R), R)
        np.testing.assert_array_equal(as_rotation(R, strict=True), R)


def test_closest_rotation_is_vectorised_and_fixes_the_determinant(rng):
    stack = np.array([random_rotation(rng) for _ in range(5)])
    noisy = stack + rng.normal(scale=1e-4, size=stack.shape)
    projected = closest_rotation(noisy)
    np.testing.assert_allclose(
        np.einsum("bki,bkj->bij", projected, projected), np.eye(3)[None].repeat(5, 0), atol=1e-14
    )
    np.testing.assert_allclose(np.linalg.det(projected), 1.0, atol=1e-14)
    np.testing.assert_allclose(projected, stack, atol=1e-3)
    assert np.linalg.det(closest_rotation(np.diag([1.0, 1.0, -1.0]))) == pytest.approx(1.0)


def test_check_rotations_reports_per_matrix_and_warns_once(rng):
    stack = np.array([random_rotation(rng), QUIZ_T[:3, :3], rotation_off_by_1e_2(), np.eye(3)])
    with pytest.warns(NearRotationWarning, match="1 of the 4") as caught:
        R, accepted = check_rotations(stack)
    assert len(caught) == 1
    assert accepted.tolist() == [True, True, False, True]
    np.testing.assert_allclose(R[1].T @ R[1], np.eye(3), atol=1e-15)
    np.testing.assert_array_equal(R[2], stack[2])
    R, accepted = check_rotations(stack, strict=True)
    assert accepted.tolist() == [True, False, False, True]


def _families(strict: bool):
    """Each family's pose entry point, as ``accepts(T) -> bool`` (True: used, False: refused)."""
    robot = redik.load("ur5e")
    solver = redik.solvers.analytic.solver_for(robot)

    def batch(T):
        result = redik.solve_batch(robot, T[None], restarts=0, max_iterations=1, strict=strict)
        return result.status_names[0] != "invalid"

    return {
        "as_pose": lambda T: as_pose(T, strict=strict),
        "analytic.solver_for": lambda T: solver(T, strict=strict),
        "analytic raw": lambda T: solver.raw(T, strict=strict),
        "analytic batch": lambda T: solver.batch(T[None], strict=strict),
        "solve_pose": lambda T: redik.solve_pose(
            robot, T, method="newton", max_iterations=1, restarts=0, strict=strict
        ),
        "FrameTask": lambda T: redik.FrameTask("ee", target=T, strict=strict),
        "FrameTask.set_target": lambda T: redik.FrameTask("ee", target=np.eye(4)).set_target(
            T, strict=strict
        ),
        "OrientationTask": lambda T: redik.OrientationTask("ee", target=T[:3, :3], strict=strict),
        "analytic.spherical_wrist": lambda T: redik.solvers.analytic.spherical_wrist(
            T[:3, :3], strict=strict
        ),
        "solve_batch": batch,
    }


@pytest.mark.parametrize("strict", [False, True])
def test_every_solver_family_accepts_and_refuses_the_same_matrices(strict):
    exact = lie.make_pose(lie.so3_exp(np.array([0.3, -1.2, 0.7])), [0.3, 0.2, 0.4])
    cases = {
        "exact": (exact, True),
        "quiz (3 decimals)": (QUIZ_T, not strict),
        "4 decimals": (lie.make_pose(rotation_4_decimals(), [0.3, 0.2, 0.4]), not strict),
        "off by 1e-2": (lie.make_pose(rotation_off_by_1e_2(), [0.3, 0.2, 0.4]), False),
        "reflection": (np.diag([1.0, 1.0, -1.0, 1.0]), False),
    }
    verdicts = {}
    for family, call in _families(strict).items():
        for case, (T, _) in cases.items():
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                try:
                    outcome = call(T)
                    accepted = outcome if isinstance(outcome, bool) else True
                except (InvalidPose, InvalidRotation):
                    accepted = False
            projected = any(issubclass(w.category, NearRotationWarning) for w in caught)
            verdicts[family, case] = (accepted, projected)
    for (family, case), (accepted, projected) in verdicts.items():
        expected = cases[case][1]
        assert accepted == expected, (family, case)
        assert projected == (accepted and case not in ("exact",)), (family, case)


def test_the_policy_helpers_refuse_non_numeric_input():
    # Found by the fuzzing of lie's public helpers: np.linalg.svd / np.fmod raised raw
    # TypeErrors and ValueErrors on strings, None and ragged lists.
    for junk in ("", None, [[1.0], [2.0, 3.0]], np.zeros(3) + 1j):
        for helper in (closest_rotation, rotation_defect, check_rotations):
            with pytest.raises(InvalidRotation):
                helper(junk)
        with pytest.raises(InvalidInput, match="angle"):
            lie.wrap_angle(junk)
    with pytest.raises(InvalidRotation, match=r"\(\.\.\., 3, 3\)"):
        closest_rotation(np.eye(4))
    with pytest.raises(InvalidRotation, match="finite"):
        closest_rotation(np.full((3, 3), np.nan))
    with pytest.raises(InvalidRotation, match=r"\(B, 3, 3\)"):
        check_rotations(np.eye(3))
