"""SE(3) helpers: exp/log identities, adjoint, metrics, SLERP; checked against mink.lie."""

from __future__ import annotations

import itertools
import math
import warnings
from fractions import Fraction

import mink
import numpy as np
import pytest

import redik
from redik import lie
from redik.core.exceptions import InvalidInput, InvalidPose, InvalidRotation, NearRotationWarning


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    quat = rng.normal(size=4)
    return lie.matrix_from_quat(quat / np.linalg.norm(quat))


def random_pose(rng: np.random.Generator) -> np.ndarray:
    return lie.make_pose(random_rotation(rng), rng.uniform(-2, 2, 3))


@pytest.mark.parametrize(
    "angle", [0.0, 1e-300, 1e-16, 1e-12, 1e-7, 1e-3, 0.5, 2.0, math.pi - 1e-6, math.pi]
)
def test_so3_log_inverts_exp_at_every_angle(rng, angle):
    for _ in range(20):
        axis = rng.normal(size=3)
        omega = angle * axis / np.linalg.norm(axis)
        R = lie.so3_exp(omega)
        np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-14)
        back = lie.so3_log(R)
        if angle <= 1e-3:  # relative: below 2e-15 rad MuJoCo's quat2Vel loses the axis
            assert np.abs(back - omega).max() <= 1e-14 * angle
        elif angle < math.pi - 1e-3:
            np.testing.assert_allclose(back, omega, atol=1e-12)
        else:  # ±axis both valid at π: compare the rotations
            np.testing.assert_allclose(lie.so3_exp(back), R, atol=1e-9)
            assert abs(np.linalg.norm(back) - angle) < 1e-8


def test_se3_exp_log_roundtrip_and_match_mink(rng):
    for _ in range(200):
        T = random_pose(rng)
        xi = lie.se3_log(T)
        np.testing.assert_allclose(lie.se3_exp(xi), T, atol=1e-12)
        np.testing.assert_allclose(xi, mink.SE3.from_matrix(T).log(), atol=1e-10)
        xi_small = rng.normal(size=6) * 1e-8
        np.testing.assert_allclose(lie.se3_log(lie.se3_exp(xi_small)), xi_small, atol=1e-20)
        np.testing.assert_allclose(lie.se3_exp(xi), mink.SE3.exp(xi).as_matrix(), atol=1e-12)


def test_adjoint_matches_mink_and_maps_twists(rng):
    for _ in range(50):
        T = random_pose(rng)
        np.testing.assert_allclose(lie.adjoint(T), mink.SE3.from_matrix(T).adjoint(), atol=1e-12)
        xi = rng.normal(size=6)
        # T exp(ξ) T⁻¹ = exp(Ad_T ξ)
        lhs = T @ lie.se3_exp(xi) @ lie.inverse(T)
        np.testing.assert_allclose(lhs, lie.se3_exp(lie.adjoint(T) @ xi), atol=1e-10)
        np.testing.assert_allclose(lie.inverse(T) @ T, np.eye(4), atol=1e-12)


def test_quaternion_roundtrip(rng):
    for _ in range(50):
        R = random_rotation(rng)
        quat = lie.quat_from_matrix(R)
        assert quat[0] >= 0.0
        np.testing.assert_allclose(lie.matrix_from_quat(quat), R, atol=1e-12)


def test_rotation_metrics_agree(rng):
    for angle in [1e-6, 1e-3, 0.1, 1.0, 3.0]:
        R_a = random_rotation(rng)
        axis = rng.normal(size=3)
        R_b = R_a @ lie.so3_exp(angle * axis / np.linalg.norm(axis))
        q_a, q_b = lie.quat_from_matrix(R_a), lie.quat_from_matrix(R_b)
        assert lie.rotation_angle(R_a, R_b) == pytest.approx(angle, rel=1e-9)
        assert lie.quaternion_geodesic_distance(q_a, q_b) == pytest.approx(angle, rel=1e-9)
        assert lie.quaternion_geodesic_distance(q_a, -q_b) == pytest.approx(angle, rel=1e-9)
        assert lie.quaternion_chordal_distance(q_a, -q_b) == pytest.approx(
            2 * math.sin(angle / 4), rel=1e-8
        )
        # The trace formula is only good to ~sqrt(eps) at small angles.
        assert lie.rotation_angle_trace(R_a, R_b) == pytest.approx(angle, abs=3e-8)


def test_trace_formula_loses_precision_where_log_does_not():
    R_b = lie.so3_exp(np.array([0.0, 0.0, 1e-9]))
    assert lie.rotation_angle(np.eye(3), R_b) == pytest.approx(1e-9, rel=1e-6)
    assert lie.rotation_angle_trace(np.eye(3), R_b) == 0.0  # cos(1e-9) rounds to 1


def test_exp_coordinate_difference_and_small_euler_difference(rng):
    T_a = random_pose(rng)
    xi = np.array([0.01, -0.02, 0.03, 1e-3, -2e-3, 1.5e-3])
    T_b = T_a @ lie.se3_exp(xi)
    np.testing.assert_allclose(lie.exp_coordinate_difference(T_a, T_b), xi, atol=1e-12)
    p, r = lie.pose_errors(T_a, T_b)
    assert r == pytest.approx(np.linalg.norm(xi[3:]), rel=1e-9)
    assert p == pytest.approx(np.linalg.norm(T_b[:3, 3] - T_a[:3, 3]))
    # For small rotations about x, the xyz Euler difference reads the angle directly.
    R = lie.so3_exp(np.array([0.2, 0.1, -0.3]))
    d = lie.euler_difference(R, R @ lie.so3_exp(np.array([0.0, 0.0, 1e-4])), "xyz")
    assert d[2] == pytest.approx(1e-4, rel=1e-2)


@pytest.mark.parametrize("convention", ["xyz", "zyx", "zyz"])
def test_euler_angles_reconstruct(rng, convention):
    axes = {"x": 0, "y": 1, "z": 2}
    for _ in range(20):
        R = random_rotation(rng)
        angles = lie.euler_angles(R, convention)
        rebuilt = np.eye(3)
        for axis, angle in zip(convention, angles, strict=True):
            omega = np.zeros(3)
            omega[axes[axis]] = angle
            rebuilt = rebuilt @ lie.so3_exp(omega)
        np.testing.assert_allclose(rebuilt, R, atol=1e-10)


def test_slerp_endpoints_and_constant_speed(rng):
    for _ in range(20):
        q_a = lie.quat_from_matrix(random_rotation(rng))
        q_b = lie.quat_from_matrix(random_rotation(rng))
        assert lie.quaternion_geodesic_distance(lie.slerp(q_a, q_b, 0.0), q_a) < 1e-12
        assert lie.quaternion_geodesic_distance(lie.slerp(q_a, q_b, 1.0), q_b) < 1e-7
        total = lie.quaternion_geodesic_distance(q_a, q_b)
        ts = np.linspace(0, 1, 11)
        points = [lie.slerp(q_a, q_b, t) for t in ts]
        steps = [lie.quaternion_geodesic_distance(a, b) for a, b in itertools.pairwise(points)]
        np.testing.assert_allclose(steps, total / 10, rtol=1e-6, atol=1e-12)
        for quat in points:
            assert np.linalg.norm(quat) == pytest.approx(1.0)


def test_interpolate_pose_matches_mink(rng):
    T_a, T_b = random_pose(rng), random_pose(rng)
    for t in (0.0, 0.3, 1.0):
        mine = lie.interpolate_pose(T_a, T_b, t)
        np.testing.assert_allclose(mine[:3, 3], (1 - t) * T_a[:3, 3] + t * T_b[:3, 3])
        R_ref = mink.SO3.from_matrix(T_a[:3, :3]).interpolate(mink.SO3.from_matrix(T_b[:3, :3]), t)
        np.testing.assert_allclose(mine[:3, :3], R_ref.as_matrix(), atol=1e-9)


def test_bad_inputs_raise_clear_errors():
    with pytest.raises(InvalidRotation, match="shape"):
        lie.as_rotation(np.eye(4))
    with pytest.raises(InvalidRotation, match="NaN"):
        lie.as_rotation(np.full((3, 3), np.nan))
    with pytest.raises(InvalidRotation, match="det"):
        lie.as_rotation(np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(InvalidRotation, match="not a rotation"):
        lie.as_rotation(2 * np.eye(3))
    bad_row = np.eye(4)
    bad_row[3, 0] = 1.0
    with pytest.raises(InvalidPose, match=r"\[0, 0, 0, 1\]"):
        lie.as_pose(bad_row)
    with pytest.raises(InvalidPose, match="shape"):
        lie.as_pose(np.eye(3))
    with pytest.raises(InvalidPose):
        lie.as_pose(np.diag([1.0, 1.0, -1.0, 1.0]))
    with pytest.raises(InvalidInput, match="unit quaternion"):
        lie.as_quaternion([1.0, 1.0, 0.0, 0.0])
    with pytest.raises(InvalidInput, match="convention"):
        lie.euler_angles(np.eye(3), "abc")


# --------------------------------------------------------------------------------------
# One rotation tolerance policy (issues 11 and 15)

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
    assert 1e-5 < lie.rotation_defect(QUIZ_T[:3, :3])[0] < 1e-4
    with pytest.warns(NearRotationWarning, match="closest rotation") as caught:
        T = lie.as_pose(QUIZ_T)
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
        projected = lie.as_rotation(R)
    np.testing.assert_allclose(projected, lie.so3_exp(np.array([0.3, -1.2, 0.7])), atol=1e-4)
    with pytest.raises(InvalidRotation, match="strict=True accepts"):
        lie.as_rotation(R, strict=True)
    with pytest.raises(InvalidPose, match="strict=True accepts"):
        lie.as_pose(QUIZ_T, strict=True)


def test_rotation_off_by_1e_2_and_reflections_are_refused_even_when_close():
    with pytest.raises(InvalidRotation, match=r"max\|RᵀR − I\| ≤ 0.002"):
        lie.as_rotation(rotation_off_by_1e_2())
    reflection = np.diag([1.0, 1.0, -1.0]) + 1e-5  # tiny defect, det −1
    with pytest.raises(InvalidRotation, match="det"):
        lie.as_rotation(reflection)


def test_exact_rotations_pass_unchanged_and_silently(rng):
    R = random_rotation(rng)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert lie.as_rotation(R) is not None
        np.testing.assert_array_equal(lie.as_rotation(R), R)
        np.testing.assert_array_equal(lie.as_rotation(R, strict=True), R)


def test_closest_rotation_is_vectorised_and_fixes_the_determinant(rng):
    stack = np.array([random_rotation(rng) for _ in range(5)])
    noisy = stack + rng.normal(scale=1e-4, size=stack.shape)
    projected = lie.closest_rotation(noisy)
    np.testing.assert_allclose(
        np.einsum("bki,bkj->bij", projected, projected), np.eye(3)[None].repeat(5, 0), atol=1e-14
    )
    np.testing.assert_allclose(np.linalg.det(projected), 1.0, atol=1e-14)
    np.testing.assert_allclose(projected, stack, atol=1e-3)
    assert np.linalg.det(lie.closest_rotation(np.diag([1.0, 1.0, -1.0]))) == pytest.approx(1.0)


def test_check_rotations_reports_per_matrix_and_warns_once(rng):
    stack = np.array([random_rotation(rng), QUIZ_T[:3, :3], rotation_off_by_1e_2(), np.eye(3)])
    with pytest.warns(NearRotationWarning, match="1 of the 4") as caught:
        R, accepted = lie.check_rotations(stack)
    assert len(caught) == 1
    assert accepted.tolist() == [True, True, False, True]
    np.testing.assert_allclose(R[1].T @ R[1], np.eye(3), atol=1e-15)
    np.testing.assert_array_equal(R[2], stack[2])
    R, accepted = lie.check_rotations(stack, strict=True)
    assert accepted.tolist() == [True, False, False, True]


def _families(strict: bool):
    """Each family's pose entry point, as ``accepts(T) -> bool`` (True: used, False: refused)."""
    robot = redik.load("ur5e")
    solver = redik.solvers.analytic.solver_for(robot)
    decomposed = redik.solvers.analytic.solver_for(robot, "decomposed")

    def batch(T):
        result = redik.solve_batch(robot, T[None], restarts=0, max_iterations=1, strict=strict)
        return result.status_names[0] != "invalid"

    return {
        "lie.as_pose": lambda T: lie.as_pose(T, strict=strict),
        "analytic.solver_for": lambda T: solver(T, strict=strict),
        "analytic decomposed": lambda T: decomposed(T, strict=strict),
        "analytic decomposed raw": lambda T: decomposed.raw(T, strict=strict),
        "analytic.ur": lambda T: redik.solvers.analytic.ur(
            T, *redik.solvers.analytic.UR5E, strict=strict
        ),
        "analytic.ur_batch": lambda T: redik.solvers.analytic.ur_batch(
            T[None], *redik.solvers.analytic.UR5E, strict=strict
        ),
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


# --------------------------------------------------------------------------------------
# Angle wrapping


def _exact_remainder(a: float) -> float:
    """``a − 2πk`` in (−π, π] computed in rational arithmetic with the double 2π."""
    two_pi = Fraction(2 * math.pi)
    r = Fraction(a) - two_pi * math.floor(Fraction(a) / two_pi)
    return float(r - two_pi if r > two_pi / 2 else r)


@pytest.mark.parametrize(
    "angle",
    [math.pi, -math.pi, 3 * math.pi, -3 * math.pi, 5 * math.pi, 1e6, -1e6, 1e300, -1e300,
     2 * math.pi, -1e-20, 1e-300, math.nextafter(-math.pi, 0), math.nextafter(math.pi, 4),
     math.nextafter(-math.pi, -4), 0.5, -2.5],
)  # fmt: skip
def test_wrap_angle_is_exact_and_in_range(angle):
    for wrapped in (lie.wrap_angle(angle), lie.wrap_angle(np.array([angle]))[0]):
        assert -math.pi < wrapped <= math.pi
        assert wrapped == _exact_remainder(angle)
    if abs(math.remainder(angle, math.pi)) == 0 and math.fmod(angle / math.pi, 2) != 0:
        assert lie.wrap_angle(angle) == math.pi  # ±π, ±3π, ±5π: exactly π


def test_wrap_angle_never_returns_minus_pi_and_is_odd(rng):
    # Just above −π + 2πk, the textbook π − ((π − a) mod 2π) rounds the mod up to 2π.
    angles = np.concatenate(
        [
            np.nextafter(np.pi * np.arange(-41, 42, 2), np.inf),
            np.nextafter(np.pi * np.arange(-41, 42, 2), -np.inf),
            rng.uniform(-1e3, 1e3, 10_000),
        ]
    )
    wrapped = lie.wrap_angle(angles)
    assert np.all(wrapped > -np.pi) and np.all(wrapped <= np.pi)
    inner = np.abs(wrapped) < np.pi
    np.testing.assert_array_equal(lie.wrap_angle(-angles)[inner], -wrapped[inner])
    np.testing.assert_allclose(np.exp(1j * wrapped), np.exp(1j * angles), atol=1e-12)
    assert np.isnan(lie.wrap_angle([np.nan, np.inf, -np.inf])).all()
    assert np.isnan(lie.wrap_angle(np.inf))
    assert isinstance(lie.wrap_angle(3), float) and lie.wrap_angle(3) == 3.0


def test_wrap_into_range_turns_an_angle_into_lower_plus_a_turn(rng):
    lower = rng.uniform(-7.0, 1.0, 500)
    angles = rng.uniform(-30.0, 30.0, 500)
    turned = lie.wrap_into_range(angles, lower)
    assert np.all(turned >= lower) and np.all(turned <= lower + 2.0 * np.pi)
    np.testing.assert_allclose(np.exp(1j * turned), np.exp(1j * angles), atol=1e-12)
    inside = (angles >= lower) & (angles < lower + 2.0 * np.pi)
    np.testing.assert_allclose(turned[inside], angles[inside], atol=1e-13)
    symmetric = lie.wrap_into_range(angles, -np.pi)  # wrap_angle's (−π, π] but for the end
    np.testing.assert_allclose(symmetric, lie.wrap_angle(angles), atol=1e-13)


def test_analytic_wraps_with_the_same_function():
    from redik.solvers import analytic

    assert analytic.wrap_angle is lie.wrap_angle


def test_the_compiled_twins_in_the_closed_form_kernels_equal_lie(rng):
    # The decomposition kernels (numba, one scalar at a time) wrap and rotate with their own
    # compiled twins of wrap_angle and so3_exp: equal to the references, bit for bit for the
    # wrap over the few turns a kernel angle spans.
    from redik.solvers.analytic._decomposed_kernels import _wrap
    from redik.solvers.analytic.subproblems import rotate

    turns = np.pi * np.arange(-9, 10, 2)
    angles = np.concatenate(
        [rng.uniform(-9 * np.pi, 9 * np.pi, 2000), turns, np.nextafter(turns, np.inf)]
    )
    angles = np.concatenate([angles, np.nextafter(turns, -np.inf)])
    np.testing.assert_array_equal([_wrap(a) for a in angles], lie.wrap_angle(angles))
    large = np.concatenate([rng.uniform(-1e6, 1e6, 200), [1e300, -1e300, 7.5 * np.pi]])
    np.testing.assert_array_equal([_wrap(a) for a in large], lie.wrap_angle(large))
    for _ in range(50):
        k, p = rng.standard_normal(3), rng.standard_normal(3)
        k /= np.linalg.norm(k)
        theta = rng.uniform(-4, 4)
        np.testing.assert_allclose(rotate(k, theta, p), lie.so3_exp(theta * k) @ p, atol=1e-14)


def test_the_policy_helpers_refuse_non_numeric_input():
    # Found by the fuzzing of lie's public helpers: np.linalg.svd / np.fmod raised raw
    # TypeErrors and ValueErrors on strings, None and ragged lists.
    for junk in ("", None, [[1.0], [2.0, 3.0]], np.zeros(3) + 1j):
        for helper in (lie.closest_rotation, lie.rotation_defect, lie.check_rotations):
            with pytest.raises(InvalidRotation):
                helper(junk)
        with pytest.raises(InvalidInput, match="angle"):
            lie.wrap_angle(junk)
    with pytest.raises(InvalidRotation, match=r"\(\.\.\., 3, 3\)"):
        lie.closest_rotation(np.eye(4))
    with pytest.raises(InvalidRotation, match="finite"):
        lie.closest_rotation(np.full((3, 3), np.nan))
    with pytest.raises(InvalidRotation, match=r"\(B, 3, 3\)"):
        lie.check_rotations(np.eye(3))


def test_apply_inverse_v_inverts_v_and_is_the_so3_inverse_left_jacobian(rng):
    for angle in (0.0, 1e-9, 1e-7, 2e-6, 0.999e-3, 1.001e-3, 0.5, 2.0, np.pi - 1e-6):
        axis = rng.standard_normal(3)
        omega, p = angle * axis / np.linalg.norm(axis), rng.standard_normal(3)
        W = lie.skew(omega)
        t2 = angle**2  # MR (3.86); its coefficients by their series where they cancel
        a = 0.5 - t2 / 24 + t2**2 / 720 if angle < 1e-2 else (1 - math.cos(angle)) / t2
        b = (
            1 / 6 - t2 / 120 + t2**2 / 5040
            if angle < 1e-2
            else (angle - math.sin(angle)) / t2 / angle
        )
        V = np.eye(3) + a * W + b * W @ W
        v = lie.apply_inverse_v(*omega, *p)
        np.testing.assert_allclose(V @ v, p, rtol=0, atol=1e-12 * max(1.0, 1.0 / (np.pi - angle)))
        # One formula: V(ω)⁻¹ is J_l⁻¹(ω) on SO(3), the block of the SE(3) one.
        np.testing.assert_allclose(lie.so3_left_jacobian_inverse(omega) @ p, v, atol=1e-14)


def series_left_jacobian_inverse(xi: np.ndarray) -> np.ndarray:
    """(Σ ad^k/(k+1)!)⁻¹: the definition, summed to convergence."""
    ad = np.zeros((6, 6))
    ad[:3, :3] = ad[3:, 3:] = lie.skew(xi[3:])
    ad[:3, 3:] = lie.skew(xi[:3])
    J, power = np.zeros((6, 6)), np.eye(6)
    for k in range(40):
        J += power / math.factorial(k + 1)
        power = power @ ad
    return np.linalg.inv(J)


@pytest.mark.parametrize("angle", [0.0, 1e-9, 1e-4, 0.999e-3, 1.001e-3, 0.1, 1.0, 2.5, 3.1])
def test_left_jacobian_inverse_closed_form_matches_its_series_and_mink(angle, rng):
    xi = rng.normal(size=6)
    xi[3:] *= angle / np.linalg.norm(xi[3:])
    reference = series_left_jacobian_inverse(xi)
    np.testing.assert_allclose(lie.se3_left_jacobian_inverse(xi), reference, atol=1e-12)
    so3 = lie.so3_left_jacobian_inverse(xi[3:])
    np.testing.assert_allclose(so3, reference[3:, 3:], atol=1e-12)
    if angle >= 0.1:  # below, mink's closed form divides by 1 − cos θ (5e-9 off at 1e-4,
        # 8e-4 at 1e-7, inf at 1e-9), and returns the identity on SE(3) for θ < 1.5e-8
        np.testing.assert_allclose(so3, mink.SO3.ljacinv(xi[3:]), atol=1e-12)
        np.testing.assert_allclose(
            lie.se3_left_jacobian_inverse(xi), mink.SE3.ljacinv(xi), atol=1e-11
        )


@pytest.mark.parametrize("batch", [(), (5,), (2, 3)])
def test_world_jacobian_to_matches_the_adjoint_relations(batch, rng):
    n = 4
    J = rng.standard_normal((6, n, *batch))
    R = np.einsum("ij,...->ij...", lie.so3_exp(rng.standard_normal(3)), np.ones(batch))
    p = rng.standard_normal((3, *batch))
    body = lie.world_jacobian_to("body", J, R, p)
    space = lie.world_jacobian_to("space", J, R, p)
    for index in np.ndindex(*batch):
        at = (slice(None), slice(None), *index)
        Ri, Ji = R[at], J[at]
        T = lie.make_pose(Ri, p[(slice(None), *index)])
        # world (ṗ, ω) → body (Rᵀṗ, Rᵀω) → space = Ad_T body.
        expected_body = np.vstack((Ri.T @ Ji[:3], Ri.T @ Ji[3:]))
        np.testing.assert_allclose(body[at], expected_body, atol=1e-12)
        np.testing.assert_allclose(space[at], lie.adjoint(T) @ expected_body, atol=1e-12)
    np.testing.assert_array_equal(lie.world_jacobian_to("world", J, R, p), J)
    for reference, expected in (("body", body), ("space", space)):
        in_place = J.copy()
        lie.world_jacobian_to(reference, in_place, R, p, out=in_place)
        np.testing.assert_allclose(in_place, expected, atol=1e-15)
    with pytest.raises(InvalidInput, match="reference"):
        lie.world_jacobian_to("hybrid", J, R, p)
