"""PUMA, UR and Stanford closed-form IK against redik.models.dh.forward (an independent FK)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import least_squares

from redik.core.exceptions import InvalidInput, InvalidPose
from redik.models.dh import forward, forward_all, row_transform
from redik.solvers.analytic import puma, puma_batch, stanford, ur, ur_batch, wrap_angle
from redik.solvers.analytic.puma import dh_rows as puma_rows
from redik.solvers.analytic.stanford import REVOLUTE as STANFORD_REVOLUTE
from redik.solvers.analytic.stanford import dh_rows as stanford_rows
from redik.solvers.analytic.ur import UR5E
from redik.solvers.analytic.ur import dh_rows as ur_rows

PUMA560 = (0.4318, 0.01905, 0.1254, 0.4318)
PUMA_VARIANTS = [PUMA560, (-0.4, 0.05, -0.15, 0.43), (0.4, -0.02, 0.0, 0.3)]
UR_VARIANTS = [UR5E, (0.089, 0.425, 0.392, -0.109, 0.095, -0.082)]
STANFORD_VARIANTS = [(0.154, 0.263, 0.0), (-0.1, 0.0, 0.4)]
REVOLUTE6 = np.ones(6, bool)


def joint_distance(a: np.ndarray, b: np.ndarray, revolute: np.ndarray = REVOLUTE6) -> float:
    difference = np.asarray(a, float) - np.asarray(b, float)
    return float(np.abs(np.where(revolute, wrap_angle(difference), difference)).max())


def check_solutions(result, rows, T, q_true=None, revolute=REVOLUTE6, tol=1e-10):
    assert result.reachable and not result.reason
    for solution in result:
        assert np.all(np.isfinite(solution))
        assert np.all(np.abs(solution[revolute]) <= np.pi)
        assert np.abs(forward(rows, solution) - T).max() <= tol, solution.label
    for i, a in enumerate(result):
        for b in result[i + 1 :]:
            assert joint_distance(a, b, revolute) > 1e-9
    if q_true is not None:
        assert min(joint_distance(s, q_true, revolute) for s in result) < 1e-8


@pytest.mark.parametrize("params", PUMA_VARIANTS)
def test_puma_random_poses_give_eight_solutions_including_the_generating_q(params):
    rng = np.random.default_rng(1)
    rows = puma_rows(*params)
    for q in rng.uniform(-np.pi, np.pi, (25, 6)):
        T = forward(rows, q)
        result = puma(T, *params)
        assert len(result) == 8
        assert sorted(result.labels) == sorted(set(result.labels))
        check_solutions(result, rows, T, q)


@pytest.mark.parametrize("params", UR_VARIANTS)
def test_ur_random_poses_every_solution_reproduces_the_pose(params):
    rng = np.random.default_rng(2)
    rows = ur_rows(*params)
    counts = []
    for q in rng.uniform(-np.pi, np.pi, (25, 6)):
        T = forward(rows, q)
        result = ur(T, *params)
        counts.append(len(result))
        check_solutions(result, rows, T, q)
    assert 8 in counts and all(n % 2 == 0 for n in counts)


@pytest.mark.parametrize("params", STANFORD_VARIANTS)
def test_stanford_random_poses_give_four_solutions_with_nonnegative_extension(params):
    rng = np.random.default_rng(3)
    rows = stanford_rows(*params)
    for q in rng.uniform(-np.pi, np.pi, (25, 6)):
        q[2] = rng.uniform(0.05, 1.0)
        T = forward(rows, q)
        result = stanford(T, params[0], params[1], d1=params[2])
        assert len(result) == 4
        assert all(s[2] >= 0.0 for s in result)
        check_solutions(result, rows, T, q, STANFORD_REVOLUTE)


def numeric_solutions(rows, T, starts, seed=0):
    """Every distinct solution found by least squares from random starts (independent)."""
    # Standard-DH revolute rows: A_i(q) = Rz(q) A_i(0); precomputing A_i(0) keeps this fast.
    fixed = [row_transform(row, 0.0, "standard") for row in rows]

    def residual(q):
        pose = np.eye(4)
        for angle, link in zip(q, fixed, strict=True):
            c, s = np.cos(angle), np.sin(angle)
            pose = pose @ np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) @ link
        return (pose - T)[:3].ravel()

    rng = np.random.default_rng(seed)
    found = []
    for q0 in rng.uniform(-np.pi, np.pi, (starts, 6)):
        fit = least_squares(residual, q0, method="lm")
        if np.abs(fit.fun).max() < 1e-9 and all(joint_distance(fit.x, f) > 1e-5 for f in found):
            found.append(fit.x)
    return found


@pytest.mark.parametrize(
    ("solver", "rows", "params", "q"),
    [
        (puma, puma_rows(*PUMA560), PUMA560, [0.3, -0.8, 1.1, 0.4, 0.9, -0.6]),
        (ur, ur_rows(*UR5E), UR5E, [0.2, -1.2, 1.5, -1.9, -1.2, 0.3]),
        (ur, ur_rows(*UR5E), UR5E, [2.9, 0.3, 0.2, -2.8, 2.7, 1.0]),
    ],
)
def test_solution_count_matches_a_multistart_numerical_search(solver, rows, params, q):
    T = forward(rows, np.array(q))
    result = solver(T, *params)
    numeric = numeric_solutions(rows, T, starts=40)
    assert len(numeric) == len(result)
    for x in numeric:
        assert min(joint_distance(x, s) for s in result) < 1e-6


def test_puma_labels_follow_the_geometry():
    rows = puma_rows(*PUMA560)
    rng = np.random.default_rng(4)
    for q in rng.uniform(-np.pi, np.pi, (20, 6)):
        for solution in puma(forward(rows, q), *PUMA560):
            frames = forward_all(rows, solution)
            shoulder, elbow, wrist = frames[1][:3, 3], frames[2][:3, 3], frames[4][:3, 3]
            x1, z1 = frames[1][:3, 0], frames[1][:3, 2]
            side = np.cross(wrist * [1, 1, 0], PUMA560[2] * z1)[2]
            assert (side > 0) == solution.label.startswith("left")
            h_w, v_w = x1 @ (wrist - shoulder), wrist[2] - shoulder[2]
            h_e, v_e = x1 @ (elbow - shoulder), elbow[2] - shoulder[2]
            above = np.sign(h_w) * (h_w * v_e - v_w * h_e) > 0
            assert above == ("-up-" in solution.label)
            assert (wrap_angle(solution[4]) >= 0) == solution.label.endswith("-noflip")


def test_ur_labels_follow_the_geometry():
    rows = ur_rows(*UR5E)
    rng = np.random.default_rng(5)
    for q in rng.uniform(-np.pi, np.pi, (20, 6)):
        for solution in ur(forward(rows, q), *UR5E):
            frames = forward_all(rows, solution)
            shoulder, elbow, wrist = frames[1][:3, 3], frames[2][:3, 3], frames[3][:3, 3]
            x1, z1 = frames[1][:3, 0], frames[1][:3, 2]
            p5 = frames[5][:3, 3]
            side = np.cross(p5 * [1, 1, 0], UR5E[3] * z1)[2]
            assert (side > 0) == solution.label.startswith("left")
            front = np.sign(x1 @ p5)
            h_w, v_w = x1 @ (wrist - shoulder), wrist[2] - shoulder[2]
            h_e, v_e = x1 @ (elbow - shoulder), elbow[2] - shoulder[2]
            assert (front * (h_w * v_e - v_w * h_e) > 0) == ("-up-" in solution.label)


def test_puma_wrist_singularity_gives_one_representative_and_a_family():
    rows = puma_rows(*PUMA560)
    q = np.array([0.3, -0.8, 1.1, 0.4, 0.0, -0.6])
    T = forward(rows, q)
    result = puma(T, *PUMA560)
    check_solutions(result, rows, T)
    singular = [s for s in result if s.singular]
    # Only the generating arm branch has θ5 = 0; its two wrist slots are one family.
    assert len(result) == 7 and len(singular) == 1 and result.singular
    solution = singular[0]
    assert "θ4 + θ6" in solution.singular and solution.family.free == (3,)
    assert np.allclose(solution[:3], q[:3])
    combined = solution.family.invariants["theta4+theta6"]
    assert np.isclose(combined, wrap_angle(q[3] + q[5]))
    for t in (-2.0, 0.5, 3.0):
        member = solution.family.at(t)
        assert np.isclose(member[3], t) and np.abs(forward(rows, member) - T).max() < 1e-10


def test_puma_near_singular_wrist_stays_exact():
    rows = puma_rows(*PUMA560)
    for theta5 in (1e-5, 1e-8, 1e-12, np.pi - 1e-9):
        T = forward(rows, np.array([0.3, -0.8, 1.1, 0.4, theta5, -0.6]))
        check_solutions(puma(T, *PUMA560), rows, T)


def test_puma_boundaries_merge_branches_and_unreachable_has_a_reason():
    _, a3, _, d4 = PUMA560
    rows = puma_rows(*PUMA560)
    stretched = np.array([0.3, -0.8, np.arctan2(d4, a3), 0.4, 0.7, 0.2])
    T = forward(rows, stretched)
    result = puma(T, *PUMA560)
    check_solutions(result, rows, T)
    assert len(result) == 4 and all("stretched or folded" in s.singular for s in result)

    far = np.eye(4)
    far[:3, 3] = (1.2, 0.3, 0.2)
    empty = puma(far, *PUMA560)
    assert not empty and not empty.reachable and "beyond the reach" in empty.reason
    assert empty.as_array().shape == (0, 6)
    close = np.eye(4)
    close[:3, 3] = (0.05, 0.0, 0.3)
    assert "shoulder offset |d3|" in puma(close, *PUMA560).reason


def test_puma_base_axis_family_when_there_is_no_shoulder_offset():
    params = (0.4, 0.05, 0.0, 0.43)
    rows = puma_rows(*params)
    T = forward(rows, np.array([0.0, -2.0, 0.5, 0.3, 0.8, 0.1]))
    T[:2, 3] = 0.0  # move the target onto the base axis, keep the orientation
    result = puma(T, *params)
    check_solutions(result, rows, T)
    family = result[0].family
    assert family.free == (0,) and "θ1 is arbitrary" in result[0].singular
    for t in (-1.0, 2.5):
        member = family.at(t)
        assert np.isclose(member[0], t) and np.abs(forward(rows, member) - T).max() < 1e-10


def test_ur_wrist_singularity_family_frees_theta6():
    rows = ur_rows(*UR5E)
    T = forward(rows, np.array([0.2, -1.2, 1.5, -1.9, 0.0, 0.3]))
    result = ur(T, *UR5E)
    assert result.singular
    for solution in result:
        if not solution.singular:  # the other shoulder branch has θ5 ≠ 0
            continue
        assert "θ6 is arbitrary" in solution.singular and solution.family.free == (5,)
        assert np.isclose(solution[0], 0.2)
        for t in (-2.5, 1.0):
            member = solution.family.at(t)
            assert np.isclose(member[5], t)
            assert np.abs(forward(rows, member) - T).max() < 1e-10
    check_solutions(result, rows, T)


def test_ur_unreachable_reasons():
    far = np.eye(4)
    far[:3, 3] = (1.5, 0.2, 0.3)
    result = ur(far, *UR5E)
    assert not result.reachable and "frame-4 origin" in result.reason and len(result) == 0
    axis = np.eye(4)
    axis[:3, 3] = (0.0, 0.05, 0.4)
    assert "lateral offset |d4|" in ur(axis, *UR5E).reason


def test_stanford_singular_cases():
    d2, d6 = 0.154, 0.263
    rows = stanford_rows(d2, d6)
    T = forward(rows, np.array([0.5, 0.7, 0.0, 0.2, 0.9, -0.3]))  # wrist centre at the shoulder
    result = stanford(T, d2, d6)
    check_solutions(result, rows, T, revolute=STANFORD_REVOLUTE)
    assert any("θ2 is arbitrary" in s.singular for s in result)
    member = result[0].family.at(1.3)
    assert np.abs(forward(rows, member) - T).max() < 1e-10
    close = np.eye(4)
    close[:3, 3] = (0.05, 0.0, 0.3 + d6)
    assert "shoulder offset |d2|" in stanford(close, d2, d6).reason


def test_joint_limits_filter_and_shift_by_two_pi():
    rows = ur_rows(*UR5E)
    q = np.array([0.2, -1.2, 1.5, -1.9, -1.2, 0.3])
    T = forward(rows, q)
    everything = ur(T, *UR5E)
    lower = np.array([-2 * np.pi, -np.pi, -np.pi, -2 * np.pi, -2 * np.pi, 0.0])
    upper = np.array([2 * np.pi, 0.0, np.pi, 2 * np.pi, 2 * np.pi, 2 * np.pi])
    limited = ur(T, *UR5E, limits=(lower, upper))
    assert 0 < len(limited) < len(everything)
    for solution in limited:
        assert np.all(solution >= lower) and np.all(solution <= upper)
        assert np.abs(forward(rows, solution) - T).max() < 1e-10
    assert min(joint_distance(s, q) for s in limited) < 1e-8
    expected = {s.label for s in everything if wrap_angle(s[1]) <= 0.0}
    assert {s.label for s in limited} == expected
    assert all(s[5] >= 0 for s in limited)  # θ6 moved into [0, 2π)
    none = ur(T, *UR5E, limits=(np.full(6, 0.1), np.full(6, 0.2)))
    assert len(none) == 0 and none.reachable and "joint limits" in none.reason


@pytest.mark.parametrize(
    ("batch", "single", "rows", "params"),
    [
        (puma_batch, puma, puma_rows(*PUMA560), PUMA560),
        (ur_batch, ur, ur_rows(*UR5E), UR5E),
    ],
)
def test_batch_equals_single(batch, single, rows, params):
    rng = np.random.default_rng(6)
    T = np.stack([forward(rows, q) for q in rng.uniform(-np.pi, np.pi, (40, 6))])
    T[5, :3, 3] = (2.0, 0.0, 0.0)  # unreachable
    result = batch(T, *params)
    assert result.q.shape == (40, 8, 6) and result.valid.shape == (40, 8)
    assert not result.valid[5].any() and np.isnan(result.q[5]).all()
    for b in range(40):
        one = single(T[b], *params)
        assert len(one) == result.valid[b].sum()
        for solution in one:
            slot = result.labels.index(solution.label)
            assert result.valid[b, slot]
            assert joint_distance(result.q[b, slot], solution) < 1e-12
    limits = (np.full(6, -2.0), np.full(6, 2.0))
    limited = batch(T, *params, limits=limits)
    for b in range(0, 40, 7):
        assert limited.valid[b].sum() == len(single(T[b], *params, limits=limits))


def test_bad_input_raises():
    T = forward(puma_rows(*PUMA560), np.zeros(6))
    with pytest.raises(InvalidPose, match="rotation"):
        bad = T.copy()
        bad[:3, :3] *= 1.1
        puma(bad, *PUMA560)
    with pytest.raises(InvalidPose, match="bottom row"):
        bad = T.copy()
        bad[3, 0] = 1.0
        puma(bad, *PUMA560)
    with pytest.raises(InvalidPose, match="det"):
        bad = T.copy()
        bad[:3, 0] *= -1.0
        puma(bad, *PUMA560)
    with pytest.raises(InvalidInput, match=r"shape \(4, 4\)"):
        puma(T[:3], *PUMA560)
    with pytest.raises(InvalidInput, match="finite"):
        bad = T.copy()
        bad[0, 3] = np.nan
        puma(bad, *PUMA560)
    with pytest.raises(InvalidInput, match="a2 must be non-zero"):
        puma(T, 0.0, 0.01, 0.1, 0.4)
    with pytest.raises(InvalidInput, match="d6 must be non-zero"):
        ur(T, *UR5E[:5], 0.0)
    with pytest.raises(InvalidInput, match="d2 must be finite"):
        stanford(T, np.inf, 0.2)
    with pytest.raises(InvalidInput, match=r"T\[1\]"):
        stack = np.stack([T, T])
        stack[1, :3, :3] *= 2.0
        ur_batch(stack, *UR5E)
    with pytest.raises(InvalidInput, match="limits lower"):
        puma(T, *PUMA560, limits=(np.full(6, 1.0), np.full(6, -1.0)))
    with pytest.raises(InvalidInput, match="6 numbers"):
        puma(T, *PUMA560, limits=(np.zeros(5), np.ones(5)))
