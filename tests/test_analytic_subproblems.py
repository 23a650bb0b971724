"""The subproblems SP1–SP6 (redik.solvers.analytic.subproblems) and the quartic they reduce to
(redik.solvers.analytic.polynomial): each answer put back into its own equation, against
numpy's roots, and on the degenerate inputs the kernels meet."""

from __future__ import annotations

import numpy as np
import pytest

from redik.solvers.analytic import polynomial, subproblems
from redik.solvers.analytic.vectors import rotate


def _unit(rng: np.random.Generator) -> np.ndarray:
    v = rng.normal(size=3)
    return v / np.linalg.norm(v)


def _rot(k, theta, p) -> np.ndarray:
    return np.array(rotate(tuple(k), theta, tuple(p)))


def test_quartic_roots_equal_numpys():
    rng = np.random.default_rng(0)
    out = np.empty(4)
    for _ in range(2000):
        k = int(rng.integers(0, 5))
        poly = np.poly(rng.normal(size=k)) if k else np.array([1.0])
        while len(poly) < 5:  # pad with factors without real roots, or one linear factor
            a, b = rng.normal(), abs(rng.normal()) + 0.1
            factor = [1.0, 2 * a, a * a + b * b] if len(poly) <= 3 else [1.0, rng.normal()]
            poly = np.polymul(poly, factor)
        poly = poly * rng.uniform(0.1, 10.0)
        count = polynomial.real_roots(poly, out)
        exact = np.roots(poly)
        exact = np.sort(exact[np.abs(exact.imag) < 1e-9].real)
        assert count == len(exact)
        np.testing.assert_allclose(np.sort(out[:count]), exact, atol=1e-10)


def test_quartic_keeps_a_double_root_and_flags_it():
    out = np.empty(4)
    for double in (0.3, -1.7, 2.5):
        poly = np.poly([double, double, -0.4, 1.1])
        count = polynomial.real_roots(poly, out)
        near = [x for x in out[:count] if abs(x - double) < 1e-6]
        assert near and all(polynomial.near_double(poly, x, 1e-6) for x in near)
        simple = [x for x in out[:count] if abs(x - double) >= 1e-6]
        assert sorted(np.round(simple, 9)) == [-0.4, 1.1]
        assert not any(polynomial.near_double(poly, x, 1e-6) for x in simple)
    assert polynomial.real_roots(np.zeros(5), out) == 0
    assert polynomial.real_roots(np.array([0.0, 0.0, 0.0, 2.0, -1.0]), out) == 1 and out[0] == 0.5


def test_sp1_to_sp4_put_back_into_their_equations():
    rng = np.random.default_rng(1)
    for _ in range(200):
        k1, k2, p1 = _unit(rng), _unit(rng), rng.normal(size=3)
        t1, t2 = rng.uniform(-np.pi, np.pi, 2)
        theta, c, _, _ = subproblems.sp1_cs(tuple(k1), tuple(p1), tuple(_rot(k1, t1, p1)))
        assert abs(np.angle(np.exp(1j * (theta - t1)))) < 1e-9 and np.isclose(np.cos(theta), c)
        p2 = _rot(k2, -t2, _rot(k1, t1, p1))  # rot(k1, t1) p1 = rot(k2, t2) p2
        a1, a2, b1, b2, status, _, _ = subproblems.sp2_cs(
            tuple(k1), tuple(p1), tuple(k2), tuple(p2), 0.0, 0.0, 1e-10
        )
        assert status in (subproblems.OK, subproblems.BOUNDARY)
        for x, y in ((a1, a2), (b1, b2)):
            np.testing.assert_allclose(_rot(k1, x, p1), _rot(k2, y, p2), atol=1e-9)
        p3 = rng.normal(size=3)
        d = np.linalg.norm(_rot(k1, t1, p1) - p3)
        plus, minus, status, *_ = subproblems.sp3_cs(tuple(k1), tuple(p1), tuple(p3), d, 1e-10)
        for x in (plus, minus):
            assert np.isclose(np.linalg.norm(_rot(k1, x, p1) - p3), d, atol=1e-9)
        h = _unit(rng)
        plus, minus, *_ = subproblems.sp4_cs(
            tuple(h), tuple(k1), tuple(p1), h @ _rot(k1, t1, p1), 1e-10
        )
        for x in (plus, minus):
            assert np.isclose(h @ _rot(k1, x, p1), h @ _rot(k1, t1, p1), atol=1e-9)


def test_sp2_keeps_its_digits_next_to_a_small_circle():
    """A vector almost on its axis (a wrist 1e-9 rad from its singularity): the height of the
    common image is read off the small circle, not lost to a cancellation."""
    k1, k2 = np.array([0.0, 0.0, 1.0]), np.array([0.0, 1.0, 0.0])
    p1 = _rot(k2, 1e-9, k1)  # rot(k2, 1e-9) z, 1e-9 off the axis k1
    a1, a2, b1, b2, status, _, _ = subproblems.sp2_cs(
        tuple(k1), tuple(p1), tuple(k2), tuple(k1), 0.0, 0.0, 1e-12
    )
    assert status == subproblems.OK
    for x, y in ((a1, a2), (b1, b2)):
        np.testing.assert_allclose(_rot(k1, x, p1), _rot(k2, y, k1), atol=1e-15)


def _sp5_residual(row, p0, k1, p1, k2, p2, k3, p3) -> float:
    t1, t2, t3 = row[:3]
    return float(np.abs(p0 + _rot(k1, t1, p1) - _rot(k2, t2, p2 + _rot(k3, t3, p3))).max())


def test_sp5_finds_the_generating_angles_and_only_solutions():
    rng = np.random.default_rng(2)
    out = np.empty((4, 4))
    for _ in range(300):
        k1, k2, k3 = _unit(rng), _unit(rng), _unit(rng)
        p1, p2, p3 = rng.normal(size=(3, 3))
        t = rng.uniform(-np.pi, np.pi, 3)
        p0 = _rot(k2, t[1], p2 + _rot(k3, t[2], p3)) - _rot(k1, t[0], p1)
        args = (p0, k1, p1, k2, p2, k3, p3)
        count = subproblems.sp5(*(tuple(v) for v in args), out)
        assert 1 <= count <= 4
        assert all(_sp5_residual(out[r], *args) < 1e-7 for r in range(count))
        gap = np.abs(np.angle(np.exp(1j * (out[:count, :3] - t)))).max(axis=1)
        assert gap.min() < 1e-6


@pytest.mark.parametrize("flat", ["first", "third"])
def test_sp5_with_a_circle_of_constant_height(flat):
    """k1 ∥ k2 (or k3 ∥ k2): that circle keeps its height, the other is cut at it."""
    rng = np.random.default_rng(3)
    out = np.empty((4, 4))
    for _ in range(100):
        k2 = _unit(rng)
        k1 = k2 if flat == "first" else _unit(rng)
        k3 = k2 if flat == "third" else _unit(rng)
        p1, p2, p3 = rng.normal(size=(3, 3))
        t = rng.uniform(-np.pi, np.pi, 3)
        p0 = _rot(k2, t[1], p2 + _rot(k3, t[2], p3)) - _rot(k1, t[0], p1)
        args = (p0, k1, p1, k2, p2, k3, p3)
        count = subproblems.sp5(*(tuple(v) for v in args), out)
        assert count >= 1 and all(_sp5_residual(out[r], *args) < 1e-7 for r in range(count))


def test_sp6_finds_the_generating_pair():
    rng = np.random.default_rng(4)
    out = np.empty((4, 3))
    for _ in range(300):
        h, k, p = rng.normal(size=(4, 3)), [_unit(rng) for _ in range(4)], rng.normal(size=(4, 3))
        t1, t2 = rng.uniform(-np.pi, np.pi, 2)
        d1 = h[0] @ _rot(k[0], t1, p[0]) + h[1] @ _rot(k[1], t2, p[1])
        d2 = h[2] @ _rot(k[2], t1, p[2]) + h[3] @ _rot(k[3], t2, p[3])
        vectors = [tuple(v) for trio in zip(h, k, p, strict=True) for v in trio]
        count = subproblems.sp6(*vectors, d1, d2, out)
        assert 1 <= count <= 4
        for x1, x2, _ in out[:count]:
            assert np.isclose(
                h[0] @ _rot(k[0], x1, p[0]) + h[1] @ _rot(k[1], x2, p[1]), d1, atol=1e-7
            )
            assert np.isclose(
                h[2] @ _rot(k[2], x1, p[2]) + h[3] @ _rot(k[3], x2, p[3]), d2, atol=1e-7
            )
        gap = np.abs(np.angle(np.exp(1j * (out[:count, :2] - (t1, t2))))).max(axis=1)
        assert gap.min() < 1e-6
