"""The closed forms of the 6-joint classes (redik.solvers.analytic.six_joint) on bundled and
generated arms.

Every solution must reproduce the target by MuJoCo's FK (robot.fk, independent of the screw
chain the solver reads), include the configuration that generated the target, and equal what
many random-seeded iterative solves find (nothing missed, nothing extra).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

import redik
from redik.core.exceptions import InvalidInput, InvalidPose, ModelError, NearRotationWarning
from redik.models.dh import DHRow
from redik.solvers import analytic
from redik.solvers.analytic import wrap_angle
from redik.solvers.analytic.geometry import Chain, screws_of
from redik.solvers.analytic.six_joint import entry
from redik.solvers.pose import solve_all
from tests.dh_tables import UR5E, puma_rows, ur_rows

FULL_TURN = [(-np.pi, np.pi)] * 6
FK_TOL = 1e-9


def _distance(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(wrap_angle(np.asarray(a) - np.asarray(b))).max())


def _same_set(first: np.ndarray, second: np.ndarray, tol: float, count: bool = True) -> bool:
    """Every member of each set is within ``tol`` of one of the other (and, with ``count``,
    the sets have the same size)."""
    if count and len(first) != len(second):
        return False
    return all(min(_distance(a, b) for b in second) <= tol for a in first) and all(
        min(_distance(a, b) for a in first) <= tol for b in second
    )


def _screw_robot(axes, points, M, name: str) -> redik.Robot:
    axes = np.asarray(axes, dtype=float)
    points = np.asarray(points, dtype=float)
    S = np.vstack([axes.T, np.cross(-axes, points).T])
    return redik.Robot.from_screws(S, M, limits=FULL_TURN, name=name)


def _reversed_robot(robot: redik.Robot, name: str) -> redik.Robot:
    """The arm run backwards (its tool becomes the base): a spherical wrist becomes a
    spherical shoulder."""
    S, M = screws_of(robot)
    chain = Chain.from_screws(S, M).reversed()
    return _screw_robot(chain.h, chain.a, chain.M, name)


def _wrist_arm(rng: np.random.Generator, wrist: str) -> redik.Robot:
    """An elbow arm (waist z, shoulder and elbow y, shoulder axes meeting) with random link
    lengths and a spherical wrist of the given Euler convention."""
    base, upper, fore, tool = rng.uniform(0.1, 0.6, 4)
    offset = rng.uniform(-0.2, 0.2)
    unit = {"X": (1, 0, 0), "Y": (0, 1, 0), "Z": (0, 0, 1)}
    centre = (upper + fore, offset, base)
    axes = [(0, 0, 1), (0, 1, 0), (0, 1, 0)] + [unit[c] for c in wrist]
    points = [(0, 0, 0), (0, 0, base), (upper, offset, base), centre, centre, centre]
    M = np.eye(4)
    M[:3, 3] = (upper + fore + tool, offset, base)
    return _screw_robot(axes, points, M, f"elbow_{wrist.lower()}")


def _dh_robot(rows, name: str) -> redik.Robot:
    return redik.Robot.from_dh(rows, limits=FULL_TURN, name=name)


def _offset_elbow(rng: np.random.Generator) -> redik.Robot:
    """Axes 2 ∥ 3 and a shoulder offset a1 (axes 1 and 2 do not meet: IRB-type)."""
    a1, d1, a2, a3, d4, d6 = rng.uniform(0.05, 0.6, 6)
    half = np.pi / 2
    rows = (
        DHRow(a1, d1, -half),
        DHRow(a2, 0.0, 0.0),
        DHRow(a3, 0.0, -half),
        DHRow(0.0, d4, half),
        DHRow(0.0, 0.0, -half),
        DHRow(0.0, d6, 0.0),
    )
    return _dh_robot(rows, "offset_elbow")


def _general_spherical(rng: np.random.Generator) -> redik.Robot:
    """Random skew first three axes (no two meeting or parallel) and a spherical wrist."""
    a = rng.uniform(0.1, 0.5, 3)
    d = rng.uniform(-0.3, 0.3, 3)
    alpha = rng.uniform(0.3, 1.3, 3) * rng.choice([-1.0, 1.0], 3)
    rows = (
        DHRow(a[0], d[0], alpha[0]),
        DHRow(a[1], d[1], alpha[1]),
        DHRow(a[2], d[2], alpha[2]),
        DHRow(0.0, rng.uniform(0.2, 0.5), np.pi / 2),
        DHRow(0.0, 0.0, -np.pi / 2),
        DHRow(0.0, rng.uniform(0.05, 0.2), 0.0),
    )
    return _dh_robot(rows, "skew_spherical")


def _random_puma(rng: np.random.Generator) -> tuple[redik.Robot, tuple]:
    params = (rng.uniform(0.2, 0.6), rng.uniform(-0.1, 0.1), rng.uniform(-0.2, 0.2))
    params = (params[0], params[1], params[2], rng.uniform(0.2, 0.6))
    return _dh_robot(puma_rows(*params), "random_puma"), params


def _random_ur(rng: np.random.Generator) -> tuple[redik.Robot, tuple]:
    d1, d4, d5, d6 = rng.uniform(0.05, 0.2, 4)
    a2, a3 = -rng.uniform(0.2, 0.6, 2)
    params = (d1, a2, a3, d4, d5, d6)
    return _dh_robot(ur_rows(*params), "random_ur"), params


def _check_poses(robot: redik.Robot, n_poses: int, seed: int) -> list[tuple[np.ndarray, object]]:
    """Every solution reproduces the pose by MuJoCo's FK and the generating q is among them;
    raw and labelled paths agree. Returns (T, solutions) per pose."""
    solver = analytic.solver_for(robot)
    rng = np.random.default_rng(seed)
    results = []
    for _ in range(n_poses):
        q_true = robot.random_q(rng)
        T = robot.fk(q_true)
        solutions = solver(T, limits=None)
        assert solutions.reachable and len(solutions) >= 1
        for q in solutions:
            assert np.abs(robot.fk(q.q) - T).max() <= FK_TOL, (robot.name, q)
        assert min(_distance(q, q_true) for q in solutions) <= 1e-7, robot.name
        assert len(set(solutions.labels)) == len(solutions)
        assert _same_set(solver.raw(T, limits=None), solutions.as_array(), 1e-12)
        results.append((T, solutions))
    return results


def test_random_puma_arms_give_eight_solutions():
    rng = np.random.default_rng(1)
    for _ in range(4):
        robot, _ = _random_puma(rng)
        assert analytic.solver_for(robot).kind == "spherical_two_intersecting"
        for _, solutions in _check_poses(robot, 5, seed=int(rng.integers(1 << 30))):
            assert len(solutions) == 8


def test_random_ur_arms_use_the_three_parallel_class():
    rng = np.random.default_rng(2)
    for _ in range(4):
        robot, _ = _random_ur(rng)
        assert analytic.solver_for(robot).kind == "three_parallel_two_intersecting"
        _check_poses(robot, 5, seed=int(rng.integers(1 << 30)))


@pytest.mark.parametrize("wrist", ["ZYZ", "ZYX", "ZXZ"])
def test_elbow_arms_from_screws_with_each_wrist_convention(wrist):
    rng = np.random.default_rng(len(wrist) + ord(wrist[1]))
    for _ in range(3):
        robot = _wrist_arm(rng, wrist)
        assert analytic.solver_for(robot).kind == "spherical_two_intersecting"
        for _, solutions in _check_poses(robot, 5, seed=int(rng.integers(1 << 30))):
            assert len(solutions) == 8


def test_offset_elbow_arms_use_the_two_parallel_class():
    rng = np.random.default_rng(3)
    for _ in range(4):
        robot = _offset_elbow(rng)
        assert analytic.solver_for(robot).kind == "spherical_two_parallel"
        _check_poses(robot, 5, seed=int(rng.integers(1 << 30)))


def test_skew_arms_with_a_spherical_wrist_use_sp5():
    rng = np.random.default_rng(4)
    for _ in range(3):
        robot = _general_spherical(rng)
        assert analytic.solver_for(robot).kind == "spherical"
        _check_poses(robot, 4, seed=int(rng.integers(1 << 30)))


@pytest.mark.parametrize("kind", ["spherical", "three_parallel"])
def test_random_ik_geo_arms_of_the_sp5_and_sp6_classes(kind):
    """Arms made as ik-geo's setups make them (unit axes, offsets in [−1, 1]³): the class of
    each is found from its screws and every target's generating configuration is returned."""
    from redik.apps.bench.analytic import robot_of
    from redik.solvers.analytic.geometry import random_arm

    rng = np.random.default_rng(15)
    for index in range(4):
        robot = robot_of(*random_arm(kind, rng), name=f"{kind}_{index}")
        assert analytic.solver_for(robot).kind == kind
        _check_poses(robot, 5, seed=index)


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["spherical", "three_parallel"])
def test_sp5_and_sp6_arms_lack_no_root_of_a_600_start_multistart(kind):
    from redik.apps.bench.analytic import robot_of
    from redik.solvers.analytic.geometry import random_arm

    robot = robot_of(*random_arm(kind, np.random.default_rng(16)))
    solver = analytic.solver_for(robot)
    rng = np.random.default_rng(17)
    for seed in range(2):
        T = robot.fk(rng.uniform(-np.pi, np.pi, 6))
        exact = solver(T, limits=None).as_array()
        numeric = [r.q for r in solve_all(robot, T, n_starts=600, seed=seed, pos_tol=1e-9)]
        # Every root the multistart reaches is one of ours; it may reach fewer.
        assert all(min(_distance(x, e) for e in exact) < 1e-5 for x in numeric)


def test_reversed_arms_spherical_shoulder_and_three_parallel_at_the_tool():
    rng = np.random.default_rng(5)
    for builder, kind in ((_random_puma, "spherical_two_intersecting"), (_random_ur, None)):
        forward_robot, _ = builder(rng)
        robot = _reversed_robot(forward_robot, "reversed")
        solver = analytic.solver_for(robot)
        if kind is not None:
            assert (solver.kind, solver.reversed) == (kind, True)
        _check_poses(robot, 5, seed=int(rng.integers(1 << 30)))


def _reversed_puma(rng: np.random.Generator) -> redik.Robot:
    return _reversed_robot(_random_puma(rng)[0], "spherical_shoulder")


@pytest.mark.parametrize(
    "builder",
    [
        _offset_elbow,
        _general_spherical,
        lambda rng: _wrist_arm(rng, "ZYX"),
        lambda rng: _random_ur(rng)[0],
        _reversed_puma,
    ],
    ids=["offset_elbow", "skew_spherical", "elbow_zyx", "random_ur", "spherical_shoulder"],
)
def test_solution_set_equals_many_random_seeded_iterative_solves(builder):
    rng = np.random.default_rng(6)
    robot = builder(rng)
    solver = analytic.solver_for(robot)
    for index in range(2):
        T = robot.fk(robot.random_q(rng))
        analytic_set = solver(T).as_array()
        iterative = np.array([r.q for r in solve_all(robot, T, n_starts=120, seed=index)])
        for q in iterative:
            assert np.abs(robot.fk(q) - T).max() < 1e-5
        # Iterative solutions converge to 1e-6 m / 1e-5 rad; near a singularity (the elbow
        # almost folded) their joints are then only good to ~1e-3 and one solution can leave
        # two clusters, so the sizes are not compared and the distance allows 5e-3.
        assert _same_set(iterative, analytic_set, 5e-3, count=False), (
            f"{robot.name}: solve_all found {len(iterative)}, closed form {len(analytic_set)}"
        )


def test_wrist_singularity_gives_a_family_whose_members_reach_the_target():
    robot = _wrist_arm(np.random.default_rng(7), "ZYZ")
    solver = analytic.solver_for(robot)
    T = robot.fk(np.array([0.3, -0.4, 0.9, 0.5, 0.0, -0.2]))  # θ5 = 0: axes 4 and 6 aligned
    solutions = solver(T, limits=None)
    assert solutions.singular and solutions.families
    family = solutions.families[0]
    assert family.free == (3,)
    for t in (-2.0, 0.0, 1.3):
        member = family.at(t)
        assert abs(wrap_angle(member[3] - t)) < 1e-12
        assert np.abs(robot.fk(member) - T).max() <= FK_TOL


def test_unreachable_target_is_empty_with_a_reason():
    robot = redik.load("puma560")
    solver = analytic.solver_for(robot)
    T = robot.fk(robot.home)
    T[:3, 3] = (3.0, 0.0, 0.0)
    result = solver(T)
    assert not result.reachable and len(result) == 0 and "no branch" in result.reason
    assert solver.raw(T).shape == (0, 6)


def test_bad_input_is_refused_with_redik_errors():
    solver = analytic.solver_for(redik.load("ur5e"))
    T = np.eye(4)
    T[0, 0] = np.nan
    with pytest.raises(InvalidInput):
        solver(T)
    with pytest.raises(InvalidInput):
        solver.raw(T)
    skewed = np.eye(4)
    skewed[0, 1] = 0.3
    with pytest.raises(InvalidPose):
        solver.raw(skewed)
    with pytest.raises(InvalidInput):
        solver.raw(np.eye(3))
    with pytest.raises(InvalidInput):
        solver(np.eye(4), limits="none")
    with pytest.raises(InvalidInput):
        solver.raw(np.eye(4), limits="none")


def test_raw_checks_a_pose_by_the_same_rule_as_redik_lie():
    """The compiled check is redik.kinematics.compiled.valid_target, as_pose's "use as it is":
    a translation beyond MAX_COORDINATE is refused on the raw path too (it used to be solved
    and silently give no solution), and a bottom row within the tolerance is accepted."""
    robot = redik.load("ur5e")
    solver = analytic.solver_for(robot)
    far = np.eye(4)
    far[0, 3] = 2e10
    with pytest.raises(InvalidPose, match="translation"):
        solver.raw(far)
    with pytest.raises(InvalidPose, match="translation"):
        solver(far)
    T = robot.fk(robot.random_q(np.random.default_rng(4)))
    nudged = T.copy()
    nudged[3, :3] = 1e-8
    assert _same_set(solver.raw(nudged, limits=None), solver.raw(T, limits=None), 1e-12)


def test_a_near_rotation_is_projected_with_a_warning_on_both_paths():
    robot = redik.load("ur5e")
    solver = analytic.solver_for(robot)
    T = robot.fk(robot.random_q(np.random.default_rng(11)))
    typed = T.copy()
    typed[:3, :3] = np.round(T[:3, :3], 4)  # a rotation typed with 4 decimals
    with pytest.warns(NearRotationWarning):
        raw = solver.raw(typed, limits=None)
    with pytest.warns(NearRotationWarning):
        labelled = solver(typed, limits=None)
    assert len(raw) >= 1 and _same_set(raw, labelled.as_array(), 1e-12)
    assert all(np.abs(robot.fk(q)[:3, 3] - T[:3, 3]).max() < 1e-3 for q in raw)


def test_a_prismatic_joint_outside_the_stanford_class_has_no_closed_form():
    S, M = screws_of(redik.load("stanford_arm"))
    moved = redik.Robot.from_screws(
        S[:, [2, 0, 1, 3, 4, 5]], M, limits=FULL_TURN, name="slide_first"
    )
    with pytest.raises(ModelError, match="no closed-form class fits"):
        analytic.solver_for(moved, method="closed_form")
    with pytest.raises(ModelError, match="prismatic"):
        analytic.solver_for(moved)


def test_ur5e_parameters_reach_eight_solutions():
    robot = _dh_robot(ur_rows(*UR5E), "ur5e_dh")
    counts = [len(s) for _, s in _check_poses(robot, 10, seed=10)]
    assert max(counts) == 8


def test_wrist_centre_on_the_first_axis_leaves_theta1_free():
    base, upper, fore, tool = 0.3, 0.4, 0.35, 0.1
    centre = (upper + fore, 0, base)
    axes = [(0, 0, 1), (0, 1, 0), (0, 1, 0), (0, 0, 1), (0, 1, 0), (0, 0, 1)]
    points = [(0, 0, 0), (0, 0, base), (upper, 0, base), centre, centre, centre]
    M = np.eye(4)
    M[:3, 3] = (upper + fore, 0, base + tool)
    robot = _screw_robot(axes, points, M, "elbow_zyz")
    T = robot.fk(np.array([0.2, 0.3, 0.9, 0.4, 0.8, -0.3]))
    T[:3, 3] = np.array([0, 0, base + 0.5]) + T[:3, :3] @ np.array([0, 0, tool])
    solutions = analytic.solver_for(robot)(T, limits=None)
    assert len(solutions) == 4 and len(solutions.families) == 4
    for family in solutions.families:
        assert family.free == (0,)
        for t in (-1.0, 0.5, 2.5):
            member = family.at(t)
            assert abs(wrap_angle(member[0] - t)) < 1e-12
            assert np.abs(robot.fk(member) - T).max() <= FK_TOL


def test_ur_wrist_singularity_is_polished_and_gives_theta6_families():
    """θ5 = 0 makes SP4 ill-conditioned (θ5 to √ε); the polish restores the pose, and θ6 is
    free on the two branches through the singular wrist."""
    robot = redik.load("ur5e")
    T = robot.fk(np.array([0.3, -1.0, 1.2, 0.4, 0.0, 0.7]))
    ours = analytic.solver_for(robot)(T, limits=None)
    for solution in ours:
        assert np.abs(robot.fk(solution.q) - T).max() <= FK_TOL
    assert len(ours.families) == 2
    for family in ours.families:
        assert family.free == (5,)
        for t in (-1.0, 2.0):
            member = family.at(t)
            assert abs(wrap_angle(member[5] - t)) < 1e-12
            assert np.abs(robot.fk(member) - T).max() <= FK_TOL


def _arm_singular_configuration(robot: redik.Robot, q: np.ndarray) -> np.ndarray | None:
    """``q`` with θ3 moved to where the wrist centre's Jacobian in (θ1, θ2, θ3) is singular
    (two arm solutions merge there), or None if θ3 never makes it so."""
    solver = analytic.solver_for(robot)
    home = np.eye(4)
    home[:3, :3], home[:3, 3] = solver.geometry[13:16], solver.geometry[12]
    centre = np.linalg.inv(home) @ np.r_[solver.geometry[9], 1.0]

    def determinant(t3: float) -> float:
        trial = np.r_[q[:2], t3, q[3:]]
        J = np.empty((3, 3))
        for j in range(3):
            step = np.zeros(6)
            step[j] = 1e-6
            J[:, j] = (robot.fk(trial + step) @ centre - robot.fk(trial - step) @ centre)[:3]
        return float(np.linalg.det(J / 2e-6))

    grid = np.linspace(-np.pi, np.pi, 91)
    values = [determinant(t) for t in grid]
    for i in range(90):
        if np.sign(values[i]) != np.sign(values[i + 1]):
            t3 = brentq(determinant, grid[i], grid[i + 1], xtol=1e-15)
            return np.r_[q[:2], t3, q[3:]]
    return None


def test_sp5_finds_double_roots_where_two_arm_solutions_merge():
    """At an arm singularity SP5's quartic has a double root (two arm solutions merge); the
    configuration that made the target must still be found, and flagged singular."""
    rng = np.random.default_rng(12)
    checked = 0
    while checked < 4:
        robot = _general_spherical(rng)
        q = _arm_singular_configuration(robot, robot.random_q(rng))
        if q is None:
            continue
        T = robot.fk(q)
        solutions = analytic.solver_for(robot)(T, limits=None)
        assert len(solutions) >= 2
        for solution in solutions:
            assert np.abs(robot.fk(solution.q) - T).max() <= FK_TOL
        # θ1 of a double root is determined to about √ε, the pose to rounding.
        nearest = min(solutions, key=lambda s: _distance(s, q))
        assert _distance(nearest, q) <= 1e-6 and nearest.singular
        checked += 1


def test_raw_takes_any_array_like_target_without_compiling_a_new_kernel():
    robot = redik.load("puma560")
    solver = analytic.solver_for(robot)
    T = robot.fk(robot.random_q(np.random.default_rng(13)))
    expected = solver.raw(T, limits=None)
    signatures = len(entry(solver.kind).signatures)
    for variant in (T.tolist(), np.asfortranarray(T), np.repeat(T, 2, axis=0)[::2]):
        assert _same_set(solver.raw(variant, limits=None), expected, 1e-12)
    # Other arrays are converted by the caller, not compiled for.
    assert len(entry(solver.kind).signatures) == signatures


def test_stanford_arm_slides_both_ways():
    """RRPRRR: the slide's line meets a sphere about the shoulder point (d3 ±), then SP2 and
    the wrist. Within the scene's limits (d3 ≥ 0.3) up to four solutions; without limits the
    d3 < 0 branches come too, each reaching the target by MuJoCo's FK."""
    robot = redik.load("stanford_arm")
    solver = analytic.solver_for(robot)
    assert solver.kind == "spherical_two_intersecting_prismatic"
    rng = np.random.default_rng(17)
    counts = []
    for q in robot.random_q(rng, size=200):
        T = robot.fk(q)
        ours = solver(T)
        assert _same_set(solver.raw(T), ours.as_array(), 0.0)
        every = solver(T, limits=None)
        assert len(every) >= len(ours)
        assert any(q_ < 0.0 for q_ in every.as_array()[:, 2])
        for solution in every:
            assert np.abs(robot.fk(solution) - T).max() < FK_TOL
        assert (
            min(_distance(np.delete(s, 2), np.delete(q, 2)) + abs(s[2] - q[2]) for s in ours) < 1e-9
        )
        assert all("-out-" in label for label in ours.labels)
        counts.append(len(ours))
    assert max(counts) == 4
