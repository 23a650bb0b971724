"""Planar 2R/3R, RRP polar, hexapod leg and spherical wrist closed-form IK."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from redik.core.exceptions import InvalidInput, InvalidRotation
from redik.solvers.analytic import (
    hexapod_leg,
    planar_2r,
    planar_2r_batch,
    planar_3r,
    planar_3r_family,
    rrp_polar,
    spherical_wrist,
    wrap_angle,
)

L1, L2, L3 = 1.0, 0.8, 0.3


def tip_2r(q, l1=L1, l2=L2):
    return np.array(
        [l1 * np.cos(q[0]) + l2 * np.cos(q[0] + q[1]), l1 * np.sin(q[0]) + l2 * np.sin(q[0] + q[1])]
    )


def tip_3r(q):
    x, y = tip_2r(q[:2]) + L3 * np.array([np.cos(q.sum()), np.sin(q.sum())])
    return np.array([x, y, wrap_angle(q.sum())])


def polar_point(q, d1):
    return np.array(
        [
            q[2] * np.cos(q[1]) * np.cos(q[0]),
            q[2] * np.cos(q[1]) * np.sin(q[0]),
            d1 + q[2] * np.sin(q[1]),
        ]
    )


def foot(q, coxa, femur, tibia, z_offset):
    u = coxa + femur * np.cos(q[1]) + tibia * np.cos(q[1] + q[2])
    z = z_offset + femur * np.sin(q[1]) + tibia * np.sin(q[1] + q[2])
    return np.array([u * np.cos(q[0]), u * np.sin(q[0]), z])


def contains(result, q, revolute=None):
    revolute = np.ones(len(q), bool) if revolute is None else revolute
    return any(np.abs(np.where(revolute, wrap_angle(s - q), s - q)).max() < 1e-8 for s in result)


def test_planar_2r_random_targets_two_branches():
    rng = np.random.default_rng(0)
    for q in rng.uniform(-np.pi, np.pi, (200, 2)):
        x, y = tip_2r(q)
        result = planar_2r(x, y, L1, L2)
        assert len(result) == 2 and result.labels == ("elbow-down", "elbow-up")
        assert result[0][1] > 0 > result[1][1]
        assert contains(result, q)
        for solution in result:
            assert np.abs(tip_2r(solution) - (x, y)).max() <= 1e-10


def test_planar_2r_elbow_down_means_elbow_below_the_line_for_targets_in_front():
    result = planar_2r(1.2, 0.3, L1, L2)
    for solution in result:
        elbow = L1 * np.array([np.cos(solution[0]), np.sin(solution[0])])
        below = np.cross([1.2, 0.3, 0.0], [*elbow, 0.0])[2] < 0
        assert below == (solution.label == "elbow-down")


def test_planar_2r_boundary_singular_and_unreachable():
    stretched = planar_2r(0.0, L1 + L2, L1, L2)
    assert len(stretched) == 1 and stretched[0].label == "elbow-straight" and stretched.singular
    assert np.allclose(stretched[0], [np.pi / 2, 0.0])
    folded = planar_2r(L1 - L2, 0.0, L1, L2)
    assert len(folded) == 1 and folded[0].label == "elbow-folded"
    assert np.abs(tip_2r(folded[0]) - (L1 - L2, 0.0)).max() < 1e-12

    origin = planar_2r(0.0, 0.0, 1.0, 1.0)
    assert len(origin) == 1 and "θ1 is arbitrary" in origin[0].singular
    family = origin.families[0]
    assert family.free == (0,)
    for t in (-2.0, 0.7):
        assert np.allclose(tip_2r(family.at(t), 1.0, 1.0), 0.0, atol=1e-12)

    far = planar_2r(2.3, 0.0, 1.0, 1.0)
    assert not far and not far.reachable
    assert far.reason == "target is 2.3 m from the shoulder, beyond the reach 1 + 1 = 2 m"
    inside = planar_2r(0.1, 0.0, L1, L2)
    assert not inside.reachable and "inside the unreachable disc" in inside.reason
    # Within the tolerance outside the boundary: clipped onto it, never NaN.
    almost = planar_2r(L1 + L2 + 5e-11, 0.0, L1, L2)
    assert len(almost) == 1 and np.all(np.isfinite(almost[0]))


def test_planar_2r_batch_equals_single_and_limits():
    rng = np.random.default_rng(1)
    xy = np.array([tip_2r(q) for q in rng.uniform(-np.pi, np.pi, (50, 2))])
    xy[3] = (5.0, 0.0)
    batch = planar_2r_batch(xy, L1, L2)
    assert batch.q.shape == (50, 2, 2) and batch.labels == ("elbow-down", "elbow-up")
    assert not batch.valid[3].any() and np.isnan(batch.q[3]).all()
    for b in range(50):
        single = planar_2r(*xy[b], L1, L2)
        assert len(single) == batch.valid[b].sum()
        for solution in single:
            assert np.allclose(batch.q[b, batch.labels.index(solution.label)], solution, atol=1e-12)
    limits = (np.array([-np.pi, 0.0]), np.array([np.pi, np.pi]))
    limited = planar_2r_batch(xy, L1, L2, limits=limits)
    assert not limited.valid[:, 1].any() and limited.valid[:, 0].sum() == 49


def test_planar_3r_two_solutions_and_family_intervals():
    rng = np.random.default_rng(2)
    for q in rng.uniform(-np.pi, np.pi, (100, 3)):
        x, y, phi = tip_3r(q)
        result = planar_3r(x, y, phi, L1, L2, L3)
        assert contains(result, q)
        for solution in result:
            assert np.abs(tip_3r(solution) - (x, y, phi)).max() <= 1e-10
        family = planar_3r_family(x, y, L1, L2, L3)
        assert family.contains(phi) and len(family(phi)) == len(result)

    # Reachable headings: compare the closed-form intervals with a dense sweep.
    family = planar_3r_family(1.9, 0.2, L1, L2, L3)
    assert len(family.phi_intervals) == 1
    for phi in np.linspace(-np.pi, np.pi, 721):
        assert family.contains(phi) == bool(family(phi)), phi
    for x, y, l3, pieces in ((0.5, 0.0, 0.4, 1), (1.0, 0.1, 0.9, 2), (-0.3, -0.2, 0.1, 1)):
        family = planar_3r_family(x, y, L1, L2, l3)
        assert len(family.phi_intervals) == pieces
        ends = [end for interval in family.phi_intervals for end in interval]
        for phi in np.linspace(-np.pi, np.pi, 721):
            if min(abs(wrap_angle(phi - end)) for end in ends) > 1e-6:
                assert family.contains(phi) == bool(family(phi)), (x, y, l3, phi)
    assert planar_3r_family(3.0, 0.0, L1, L2, L3).phi_intervals == ()
    unreachable = planar_3r(3.0, 0.0, 0.0, L1, L2, L3)
    assert not unreachable.reachable and "wrist point" in unreachable.reason


def test_rrp_polar_regular_and_singular():
    d1 = 0.5
    rng = np.random.default_rng(3)
    revolute = np.array([True, True, False])
    for q in rng.uniform(-np.pi, np.pi, (100, 3)):
        q[1] = rng.uniform(-1.5, 1.5)
        q[2] = rng.uniform(0.1, 1.0)
        p = polar_point(q, d1)
        result = rrp_polar(p, d1)
        assert result.labels == ("front", "back") and contains(result, q, revolute)
        for solution in result:
            assert solution[2] >= 0 and np.abs(polar_point(solution, d1) - p).max() <= 1e-10
    on_axis = rrp_polar([0.0, 0.0, 1.2], d1)
    assert len(on_axis) == 1 and "θ1 is arbitrary" in on_axis[0].singular
    assert np.allclose(polar_point(on_axis.families[0].at(2.0), d1), [0, 0, 1.2])
    shoulder = rrp_polar([0.0, 0.0, d1], d1)
    family = shoulder.families[0]
    assert family.free == (0, 1) and np.allclose(polar_point(family.at(0.3, -1.0), d1), [0, 0, d1])
    limited = rrp_polar(
        polar_point(np.array([0.2, 0.3, 0.6]), d1), d1, limits=([-1, -1, 0], [1, 1, 1])
    )
    assert limited.labels == ("front",)


def test_hexapod_leg_branches_and_preferred_knee():
    dims = (0.052, 0.082, 0.142, -0.015)
    rng = np.random.default_rng(4)
    for _ in range(100):
        q = np.array([rng.uniform(-1.2, 1.2), rng.uniform(-1.5, 1.5), rng.uniform(-2.6, 0.5)])
        p = foot(q, *dims)
        result = hexapod_leg(p, *dims)
        assert result.preferred == "knee-up" and contains(result, q)
        for solution in result:
            assert np.abs(foot(solution, *dims) - p).max() <= 1e-10
            if solution.label.endswith("knee-up"):
                assert solution[2] < 0
    standing = hexapod_leg([0.15, 0.0, -0.12], *dims)
    knee_up = standing.by_label("knee-up")
    knee = dims[0] + dims[1] * np.cos(knee_up[1]), dims[3] + dims[1] * np.sin(knee_up[1])
    assert knee[1] > -0.12 and standing.labels[:2] == ("knee-down", "knee-up")
    with pytest.raises(InvalidInput, match="knee-sideways"):
        standing.by_label("knee-sideways")
    far = hexapod_leg([0.5, 0.0, 0.0], *dims)
    assert not far.reachable and "beyond the reach" in far.reason
    under = hexapod_leg([0.0, 0.0, -0.1], *dims)
    assert under.singular and all(s.family.free == (0,) for s in under)
    assert np.allclose(foot(under[0].family.at(1.0), *dims), [0, 0, -0.1], atol=1e-12)


@pytest.mark.parametrize("convention", ["ZYZ", "ZXZ", "ZYX"])
def test_spherical_wrist_both_solutions(convention):
    rng = np.random.default_rng(5)
    for angles in rng.uniform(-np.pi, np.pi, (100, 3)):
        R = Rotation.from_euler(convention, angles).as_matrix()
        result = spherical_wrist(R, convention)
        assert result.labels == ("noflip", "flip") and contains(result, angles)
        for solution in result:
            back = Rotation.from_euler(convention, solution).as_matrix()
            assert np.abs(back - R).max() <= 1e-10


@pytest.mark.parametrize(
    ("convention", "angles", "key", "combined"),
    [
        ("ZYZ", (0.3, 0.0, 0.5), "theta4+theta6", 0.8),
        ("ZYZ", (0.3, np.pi, 0.5), "theta4-theta6", -0.2),
        ("ZXZ", (0.3, 0.0, 0.5), "theta4+theta6", 0.8),
        ("ZXZ", (0.3, np.pi, 0.5), "theta4-theta6", -0.2),
        ("ZYX", (0.3, np.pi / 2, 0.5), "alpha-gamma", -0.2),
        ("ZYX", (0.3, -np.pi / 2, 0.5), "alpha+gamma", 0.8),
    ],
)
def test_spherical_wrist_singular_reports_the_combined_angle(convention, angles, key, combined):
    R = Rotation.from_euler(convention, angles).as_matrix()
    result = spherical_wrist(R, convention)
    assert len(result) == 1 and result.singular
    family = result[0].family
    assert np.isclose(family.invariants[key], combined)
    for t in (-1.0, 2.0):
        back = Rotation.from_euler(convention, family.at(t)).as_matrix()
        assert np.abs(back - R).max() <= 1e-10


def test_bad_input_raises_with_the_value_named():
    with pytest.raises(InvalidInput, match=r"l1 must be a positive length in metres, got -1\.0"):
        planar_2r(1.0, 0.0, -1.0, 1.0)
    with pytest.raises(InvalidInput, match="x must be finite"):
        planar_2r(np.nan, 0.0, 1.0, 1.0)
    with pytest.raises(InvalidInput, match="y must be a real number"):
        planar_2r(1.0, [0.0, 1.0], 1.0, 1.0)
    with pytest.raises(InvalidInput, match=r"xy must have shape \(B, 2\), got \(3,\)"):
        planar_2r_batch(np.zeros(3), 1.0, 1.0)
    with pytest.raises(InvalidInput, match=r"p must have shape \(3\), got \(2,\)"):
        rrp_polar([1.0, 2.0], 0.5)
    with pytest.raises(InvalidInput, match="tibia must be a positive length"):
        hexapod_leg([0.1, 0.0, 0.0], 0.05, 0.08, 0.0)
    with pytest.raises(InvalidRotation, match="det"):
        spherical_wrist(np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(InvalidRotation, match="orthonormal"):
        spherical_wrist(np.eye(3) * 1.01)
    with pytest.raises(InvalidInput, match="convention must be"):
        spherical_wrist(np.eye(3), "XYZ")
