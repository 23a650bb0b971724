"""The compiled pieces of the Raghavan–Roth elimination (redik.solvers.analytic.elimination)
against direct evaluation: the DH table of a chain, the exact coefficients of both sides, the
QR and LU it solves with."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import redik
from redik.lie import inverse
from redik.models.dh import DHRow, parse_convention, row_transform
from redik.solvers.analytic import elimination
from redik.solvers.analytic.geometry import Chain, screws_of

FULL_TURN = [(-np.pi, np.pi)] * 6


def _random_chain(rng: np.random.Generator) -> tuple[redik.Robot, Chain]:
    axes = rng.normal(size=(6, 3))
    axes /= np.linalg.norm(axes, axis=1)[:, None]
    points = rng.uniform(-0.5, 0.5, (6, 3))
    M = np.eye(4)
    M[:3, :3] = Rotation.random(random_state=int(rng.integers(1 << 30))).as_matrix()
    M[:3, 3] = rng.uniform(-0.5, 0.5, 3)
    S = np.vstack([axes.T, np.cross(-axes, points).T])
    robot = redik.Robot.from_screws(S, M, limits=FULL_TURN, name="random_6r")
    return robot, Chain.from_screws(*screws_of(robot))


def test_dh_table_of_a_chain_moves_like_the_chain():
    robot, chain = _random_chain(np.random.default_rng(9))
    dh = elimination.dh_of_chain(chain)
    for q in np.random.default_rng(0).uniform(-np.pi, np.pi, (5, 6)):
        T = dh.base
        for i in range(6):
            T = T @ dh.links(i, q[i] + dh.offset[i])
        np.testing.assert_allclose(T @ dh.tool, robot.fk(q), atol=1e-12)


def test_links_and_inverses_equal_the_dh_and_lie_ones():
    rng = np.random.default_rng(3)
    for _ in range(5):
        theta, d, a, alpha = rng.uniform(-3.0, 3.0, 4)
        dh = elimination.DH(*(np.full(6, v) for v in (d, a, alpha, 0.0)), np.eye(4), np.eye(4))
        reference = row_transform(DHRow(a, d, alpha), theta, parse_convention("standard"))
        np.testing.assert_allclose(dh.links(2, theta), reference, atol=1e-15)
        np.testing.assert_allclose(
            elimination.inverse_stack(reference), inverse(reference), atol=1e-15
        )


@pytest.mark.parametrize("split", elimination.SPLITS)
def test_both_sides_are_linear_in_each_angle_and_read_off_exactly(split):
    """Raghavan & Roth's structure: the 14 quantities of each side are linear in
    {1, cos, sin} of each angle, so three samples per angle give them exactly."""
    rng = np.random.default_rng(8)
    robot, chain = _random_chain(rng)
    built = elimination.Elimination.build(chain, False, split, 0)
    a, dh = built.arrays, built.dh
    T = robot.fk(rng.uniform(-np.pi, np.pi, 6))
    _, local = elimination.local_target(
        T, False, built.length, a["base_inverse"], a["tool_inverse"]
    )
    right = elimination._right(local, a["backs"], a["posts"], elimination._FROM_SAMPLES)
    left_rows, first, second = ((1, 2, 3), 0, 5) if split == "rebased" else ((2, 3, 4), 0, 1)
    for _ in range(5):
        t = rng.uniform(-np.pi, np.pi, 6)
        links = [dh.links(i, t[i]) for i in range(6)]
        triple = links[left_rows[0]] @ links[left_rows[1]] @ links[left_rows[2]]
        direct = elimination.fourteen(triple[:3, 3], triple[:3, 2])
        bases = [np.array([1.0, np.cos(t[i]), np.sin(t[i])]) for i in left_rows]
        np.testing.assert_allclose(
            np.einsum("abck,a,b,c->k", a["left"], *bases), direct, atol=1e-12
        )
        if split == "rebased":
            other = (
                np.linalg.inv(links[0])
                @ local
                @ np.linalg.inv(links[5])
                @ np.linalg.inv(dh.links(4, 0.0))
            )
        else:
            other = np.linalg.inv(links[0] @ links[1]) @ local
        direct = elimination.fourteen(other[:3, 3], other[:3, 2])
        b1, b2 = (np.array([1.0, np.cos(t[i]), np.sin(t[i])]) for i in (first, second))
        np.testing.assert_allclose(np.einsum("abk,a,b->k", right, b1, b2), direct, atol=1e-12)


def test_householder_and_lu_solve_like_numpy():
    rng = np.random.default_rng(4)
    Q = rng.normal(size=(14, 8))
    Qfull, R = np.empty((14, 14)), np.empty((8, 8))
    elimination.householder(Q, Qfull, R)
    np.testing.assert_allclose(Qfull.T @ Qfull, np.eye(14), atol=1e-13)
    np.testing.assert_allclose(Qfull[:, :8] @ R, Q, atol=1e-13)
    np.testing.assert_allclose(Qfull[:, 8:].T @ Q, 0.0, atol=1e-13)  # the left null space
    assert np.allclose(np.tril(R, -1), 0.0)
    A, b = rng.normal(size=(12, 12)), rng.normal(size=12)
    LU = A.copy()
    permutation, regular = elimination.lu_factor(LU)
    x = np.empty(12)
    elimination.lu_apply(LU, permutation, b, x)
    np.testing.assert_allclose(x, np.linalg.solve(A, b), atol=1e-11)
    assert 0.0 < regular < 1.0
    singular = A.copy()
    singular[3] = singular[5]
    assert elimination.lu_factor(singular)[1] < 1e-12


def test_a_hidden_angle_at_the_tangents_pole_is_still_found():
    """The eigenvalue y = 0 is x = ∞, the half-angle tangent's pole: angle offset + π."""
    psi, real = elimination._root_angle(0.0, 0.0, 0.3)
    assert real and psi == pytest.approx(np.pi)
    psi, real = elimination._root_angle(1e-12, 0.5, 0.3)  # x ≈ 0.3 − 2i: not real
    assert not real
