"""PUMA, UR and Stanford arms from their DH tables: every solution, its textbook label, its
singularities, against redik.models.dh.forward (an independent FK)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import least_squares

import redik
from redik.core.exceptions import InvalidInput, InvalidPose
from redik.models.dh import forward, forward_all, row_transform
from redik.solvers.analytic import solver_for, wrap_angle
from tests.dh_tables import PUMA560, UR5E, puma_rows, stanford_rows, ur_rows

FULL = [(-np.pi, np.pi)] * 6


PUMA_VARIANTS = [PUMA560, (-0.4, 0.05, -0.15, 0.43), (0.4, -0.02, 0.0, 0.3)]
UR_VARIANTS = [UR5E, (0.089, 0.425, 0.392, -0.109, 0.095, -0.082)]
STANFORD_VARIANTS = [(0.154, 0.263, 0.0), (-0.1, 0.0, 0.4)]
REVOLUTE6 = np.ones(6, bool)
STANFORD_REVOLUTE = np.array([True, True, False, True, True, True])


def arm(rows, limits=FULL):
    limits = [
        (-2.0, 2.0) if row.joint == "prismatic" else bound
        for row, bound in zip(rows, limits, strict=False)
    ]
    return solver_for(redik.Robot.from_dh(rows, limits=limits))


def joint_distance(a: np.ndarray, b: np.ndarray, revolute: np.ndarray = REVOLUTE6) -> float:
    difference = np.asarray(a, float) - np.asarray(b, float)
    return float(np.abs(np.where(revolute, wrap_angle(difference), difference)).max())


def check_solutions(result, rows, T, q_true=None, revolute=REVOLUTE6, tol=1e-10):
    assert result.reachable and not result.reason
    assert len(set(result.labels)) == len(result)
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
    solver = arm(rows)
    assert solver.kind == "spherical_two_intersecting"
    for q in rng.uniform(-np.pi, np.pi, (25, 6)):
        T = forward(rows, q)
        result = solver(T, limits=None)
        assert len(result) == 8
        check_solutions(result, rows, T, q)


@pytest.mark.parametrize("params", UR_VARIANTS)
def test_ur_random_poses_every_solution_reproduces_the_pose(params):
    rng = np.random.default_rng(2)
    rows = ur_rows(*params)
    solver = arm(rows)
    assert solver.kind == "three_parallel_two_intersecting"
    counts = []
    for q in rng.uniform(-np.pi, np.pi, (25, 6)):
        T = forward(rows, q)
        result = solver(T, limits=None)
        counts.append(len(result))
        check_solutions(result, rows, T, q)
    assert 8 in counts and all(n % 2 == 0 for n in counts)


@pytest.mark.parametrize("params", STANFORD_VARIANTS)
def test_stanford_random_poses_give_both_signs_of_the_extension(params):
    """Eight solutions: the slide's two roots d3 = −b·h3 ± √…, each labelled by the side of
    the shoulder the wrist centre lies on along the slide (``out`` for d3 > 0 here)."""
    rng = np.random.default_rng(3)
    rows = stanford_rows(*params)
    solver = arm(rows)
    assert solver.kind == "spherical_two_intersecting_prismatic"
    for q in rng.uniform(-np.pi, np.pi, (25, 6)):
        q[2] = rng.uniform(0.05, 1.0)
        T = forward(rows, q)
        result = solver(T, limits=None)
        assert len(result) == 8
        for solution in result:
            assert (solution[2] > 0) == ("-out-" in solution.label)
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
    ("rows", "q"),
    [
        (puma_rows(*PUMA560), [0.3, -0.8, 1.1, 0.4, 0.9, -0.6]),
        (ur_rows(*UR5E), [0.2, -1.2, 1.5, -1.9, -1.2, 0.3]),
        (ur_rows(*UR5E), [2.9, 0.3, 0.2, -2.8, 2.7, 1.0]),
    ],
)
def test_solution_count_matches_a_multistart_numerical_search(rows, q):
    T = forward(rows, np.array(q))
    result = arm(rows)(T, limits=None)
    numeric = numeric_solutions(rows, T, starts=40)
    assert len(numeric) == len(result)
    for x in numeric:
        assert min(joint_distance(x, s) for s in result) < 1e-6


def test_puma_labels_follow_the_geometry():
    """Craig's and Paul's words from the DH frames: *left* when the offset d3 lies left of
    the vertical plane through the base axis and the wrist centre, *up* when the elbow is
    above the shoulder–wrist line (seen with the wrist in front), *noflip* for θ5 ∈ [0, π]."""
    rows = puma_rows(*PUMA560)
    solver = arm(rows)
    rng = np.random.default_rng(4)
    for q in rng.uniform(-np.pi, np.pi, (20, 6)):
        for solution in solver(forward(rows, q), limits=None):
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
    solver = arm(rows)
    rng = np.random.default_rng(5)
    for q in rng.uniform(-np.pi, np.pi, (20, 6)):
        for solution in solver(forward(rows, q), limits=None):
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
            assert (wrap_angle(solution[4]) >= 0) == solution.label.endswith("-noflip")


def test_puma_wrist_singularity_gives_one_representative_and_a_family():
    rows = puma_rows(*PUMA560)
    q = np.array([0.3, -0.8, 1.1, 0.4, 0.0, -0.6])
    T = forward(rows, q)
    result = arm(rows)(T, limits=None)
    check_solutions(result, rows, T)
    singular = [s for s in result if s.singular]
    # Only the generating arm branch has θ5 = 0; its two wrist slots are one family.
    assert len(result) == 7 and len(singular) == 1 and result.singular
    solution = singular[0]
    assert "θ4 is arbitrary" in solution.singular and solution.family.free == (3,)
    assert np.allclose(solution[:3], q[:3])
    for t in (-2.0, 0.5, 3.0):
        member = solution.family.at(t)
        assert np.isclose(member[3], t) and np.abs(forward(rows, member) - T).max() < 1e-10
        assert np.isclose(wrap_angle(member[3] + member[5]), wrap_angle(q[3] + q[5]))


def test_puma_near_singular_wrist_stays_exact():
    rows = puma_rows(*PUMA560)
    solver = arm(rows)
    for theta5 in (1e-5, 1e-8, 1e-12, np.pi - 1e-9):
        T = forward(rows, np.array([0.3, -0.8, 1.1, 0.4, theta5, -0.6]))
        check_solutions(solver(T, limits=None), rows, T)


def test_puma_boundaries_merge_branches_and_unreachable_has_a_reason():
    _, a3, _, d4 = PUMA560
    rows = puma_rows(*PUMA560)
    solver = arm(rows)
    stretched = np.array([0.3, -0.8, np.arctan2(d4, a3), 0.4, 0.7, 0.2])
    T = forward(rows, stretched)
    result = solver(T, limits=None)
    check_solutions(result, rows, T)
    assert len(result) == 4 and all("two branches coincide" in s.singular for s in result)

    far = np.eye(4)
    far[:3, 3] = (1.2, 0.3, 0.2)
    empty = solver(far, limits=None)
    assert not empty and not empty.reachable and "elbow subproblem" in empty.reason
    assert empty.as_array().shape == (0, 6) and empty.status == redik.Status.UNREACHABLE
    close = np.eye(4)
    close[:3, 3] = (0.05, 0.0, 0.3)
    assert "has no solution" in solver(close, limits=None).reason


def test_puma_base_axis_family_when_there_is_no_shoulder_offset():
    params = (0.4, 0.05, 0.0, 0.43)
    rows = puma_rows(*params)
    T = forward(rows, np.array([0.0, -2.0, 0.5, 0.3, 0.8, 0.1]))
    T[:2, 3] = 0.0  # move the target onto the base axis, keep the orientation
    result = arm(rows)(T, limits=None)
    check_solutions(result, rows, T)
    family = result[0].family
    assert family.free == (0,) and "θ1 is arbitrary" in result[0].singular
    for t in (-1.0, 2.5):
        member = family.at(t)
        assert np.isclose(member[0], t) and np.abs(forward(rows, member) - T).max() < 1e-10


def test_ur_wrist_singularity_family_frees_theta6():
    rows = ur_rows(*UR5E)
    T = forward(rows, np.array([0.2, -1.2, 1.5, -1.9, 0.0, 0.3]))
    result = arm(rows)(T, limits=None)
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
    solver = arm(ur_rows(*UR5E))
    far = np.eye(4)
    far[:3, 3] = (1.5, 0.2, 0.3)
    result = solver(far, limits=None)
    assert not result.reachable and "elbow subproblem" in result.reason and len(result) == 0
    axis = np.eye(4)
    axis[:3, 3] = (0.0, 0.05, 0.4)
    assert "shoulder subproblem" in solver(axis, limits=None).reason


def test_stanford_singular_cases():
    d2, d6 = 0.154, 0.263
    rows = stanford_rows(d2, d6)
    solver = arm(rows)
    T = forward(rows, np.array([0.5, 0.7, 0.0, 0.2, 0.9, -0.3]))  # wrist centre at the shoulder
    result = solver(T, limits=None)
    check_solutions(result, rows, T, revolute=STANFORD_REVOLUTE)
    assert any("θ2 is arbitrary" in s.singular for s in result)
    member = next(s for s in result if s.family is not None).family.at(1.3)
    assert np.abs(forward(rows, member) - T).max() < 1e-10
    close = np.eye(4)
    close[:3, 3] = (0.05, 0.0, 0.3 + d6)
    assert "shoulder subproblem" in solver(close, limits=None).reason


def test_joint_limits_filter_and_shift_by_two_pi():
    rows = ur_rows(*UR5E)
    solver = arm(rows)
    q = np.array([0.2, -1.2, 1.5, -1.9, -1.2, 0.3])
    T = forward(rows, q)
    everything = solver(T, limits=None)
    lower = np.array([-2 * np.pi, -np.pi, -np.pi, -2 * np.pi, -2 * np.pi, 0.0])
    upper = np.array([2 * np.pi, 0.0, np.pi, 2 * np.pi, 2 * np.pi, 2 * np.pi])
    limited = solver(T, limits=(lower, upper))
    assert 0 < len(limited) < len(everything)
    for solution in limited:
        assert np.all(solution >= lower) and np.all(solution <= upper)
        assert np.abs(forward(rows, solution) - T).max() < 1e-10
    assert min(joint_distance(s, q) for s in limited) < 1e-8
    expected = {s.label for s in everything if wrap_angle(s[1]) <= 0.0}
    assert {s.label for s in limited} == expected
    assert all(s[5] >= 0 for s in limited)  # θ6 moved into [0, 2π)
    raw = solver.raw(T, limits=(lower, upper))  # the same rows, in the kernel's order
    assert np.array_equal(np.unique(raw, axis=0), np.unique(limited.as_array(), axis=0))
    none = solver(T, limits=(np.full(6, 0.1), np.full(6, 0.2)))
    assert len(none) == 0 and none.reachable and "joint limits" in none.reason
    assert none.status == redik.Status.LIMITS


@pytest.mark.parametrize("rows", [puma_rows(*PUMA560), ur_rows(*UR5E)])
def test_batch_equals_single(rows):
    solver = arm(rows)
    rng = np.random.default_rng(6)
    T = np.stack([forward(rows, q) for q in rng.uniform(-np.pi, np.pi, (40, 6))])
    T[5, :3, 3] = (2.0, 0.0, 0.0)  # unreachable
    result = solver.batch(T, limits=None)
    assert result.q.shape == (40, 8, 6) and result.valid.shape == (40, 8)
    assert result.labels == solver.labels
    assert not result.valid[5].any() and np.isnan(result.q[5]).all()
    for b in range(40):
        one = solver(T[b], limits=None)
        assert len(one) == result.valid[b].sum()
        for solution in one:
            code = result.labels.index(solution.label)
            assert result.valid[b, code]
            assert joint_distance(result.q[b, code], solution) < 1e-12
    limits = (np.full(6, -2.0), np.full(6, 2.0))
    limited = solver.batch(T, limits=limits)
    for b in range(0, 40, 7):
        assert limited.valid[b].sum() == len(solver(T[b], limits=limits))


def test_bad_input_raises():
    rows = puma_rows(*PUMA560)
    solver = arm(rows)
    T = forward(rows, np.zeros(6))
    with pytest.raises(InvalidPose, match="rotation"):
        bad = T.copy()
        bad[:3, :3] *= 1.1
        solver(bad)
    with pytest.raises(InvalidPose, match="bottom row"):
        bad = T.copy()
        bad[3, 0] = 1.0
        solver(bad)
    with pytest.raises(InvalidPose, match="det"):
        bad = T.copy()
        bad[:3, 0] *= -1.0
        solver.raw(bad)
    with pytest.raises(InvalidInput, match=r"shape \(4, 4\)"):
        solver(T[:3])
    with pytest.raises(InvalidInput, match="finite"):
        bad = T.copy()
        bad[0, 3] = np.nan
        solver(bad)
    with pytest.raises(InvalidInput, match=r"T\[1\]"):
        stack = np.stack([T, T])
        stack[1, :3, :3] *= 2.0
        solver.batch(stack)
    with pytest.raises(InvalidInput, match="limits lower"):
        solver(T, limits=(np.full(6, 1.0), np.full(6, -1.0)))
    with pytest.raises(InvalidInput, match="6 numbers"):
        solver(T, limits=(np.zeros(5), np.ones(5)))
    with pytest.raises(InvalidInput, match="limits must be 'robot'"):
        solver(T, limits="everything")
