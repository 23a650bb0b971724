"""redik.lie.angles: exact angle wrapping, turns into a range, Euler angles."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from redik import lie
from redik.core.exceptions import InvalidInput
from tests.samples import random_rotation


@pytest.mark.parametrize("convention", ["xyz", "zyx", "zyz", "zxz"])
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
    from redik.solvers.analytic.chain import wrap as _wrap
    from redik.solvers.analytic.vectors import rotate

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


@pytest.mark.parametrize("convention", ["xyz", "zyx", "zyz", "zxz"])
def test_euler_angles_are_scipys_intrinsic_angles_in_their_ranges(rng, convention):
    for _ in range(50):
        R = random_rotation(rng)
        angles = lie.euler_angles(R, convention)
        expected = Rotation.from_matrix(R).as_euler(convention.upper())
        np.testing.assert_allclose(angles, expected, atol=1e-12)
        middle = (-math.pi / 2, math.pi / 2) if convention[0] != convention[2] else (0, math.pi)
        assert middle[0] <= angles[1] <= middle[1]
        assert np.all(np.abs(angles) <= math.pi)


def test_zxz_reads_the_angles_a_zxz_wrist_was_built_from():
    alpha, beta, gamma = 0.4, 1.1, -2.2
    R = lie.so3_exp([0, 0, alpha]) @ lie.so3_exp([beta, 0, 0]) @ lie.so3_exp([0, 0, gamma])
    np.testing.assert_allclose(lie.euler_angles(R, "ZXZ"), [alpha, beta, gamma], atol=1e-15)
    # The same rotation in ZYZ: the first and last angles move by a quarter turn.
    np.testing.assert_allclose(
        lie.euler_angles(R, "zyz"), [alpha - math.pi / 2, beta, gamma + math.pi / 2], atol=1e-15
    )


def test_euler_angles_refuse_an_unknown_convention():
    with pytest.raises(InvalidInput, match=r"'xyz', 'zyx', 'zyz', 'zxz'\], got 'xzx'"):
        lie.euler_angles(np.eye(3), "xzx")
