"""The compiled plan of Problem.step: the general path's steps, its kernels against references."""

from __future__ import annotations

import daqp
import mink
import mujoco
import numpy as np
import pytest

import redik
from redik.core.exceptions import InvalidConfiguration, InvalidInput, TargetNotSet
from redik.limits import (
    AccelerationLimit,
    CollisionAvoidanceLimit,
    ConfigurationLimit,
    VelocityLimit,
)
from redik.qp import Problem
from redik.qp.compiled.box_qp import box_qp
from redik.qp.compiled.collision import near_pairs
from redik.qp.compiled.frames import dof_chain, point_jacobian
from redik.qp.compiled.joint_gradient import rotation_difference
from redik.qp.compiled.lower_level import null_space
from redik.qp.compiled.rows_qp import rows_qp
from redik.qp.hierarchy import row_null_space
from redik.tasks import (
    DampingTask,
    FrameTask,
    JointLimitAvoidanceTask,
    PositionTask,
    PostureTask,
)
from tests.test_whole_model import TORSO_XML

WEIGHTED_TOL = 1e-12
"""Weighted steps: both paths solve one QP exactly; they differ by round-off only."""

STRICT_TOL = 1e-9
"""Strict steps: level 0 with active bounds is solved to the conditioning of
``AᵀA + εI`` (about 1e7 for ε = 1e-6) by two different exact methods; level 1 inherits it."""


@pytest.fixture(scope="module")
def panda() -> redik.Robot:
    return redik.load("panda")


@pytest.fixture(scope="module")
def torso() -> redik.Robot:
    """A whole model: free base, ball-jointed head, two arms with slide fingers, a table."""
    return redik.Robot(mujoco.MjModel.from_xml_string(TORSO_XML), joints="all")


def _panda_stack(robot, strict: bool, variant: str) -> tuple[list, list]:
    lower = 1 if strict else 0
    tasks = [
        FrameTask("ee", position_cost=1.0, orientation_cost=0.5, gain=0.9),
        PostureTask(cost=0.1, priority=lower),
        JointLimitAvoidanceTask(cost=0.1, priority=lower),
    ]
    limits = [ConfigurationLimit(), VelocityLimit(2.0)]
    if variant == "position":
        tasks[0] = PositionTask("ee", cost=[1.0, 2.0, 0.5])
        tasks.append(DampingTask(0.05, priority=lower))
    elif variant == "two frames":
        tasks.append(PositionTask("link4", "body", cost=0.3, priority=lower))
        limits.append(VelocityLimit(1.0 + np.arange(7) / 3))  # boxes of one kind intersect
    return tasks, limits


def _torso_stack(robot, strict: bool, variant: str) -> tuple[list, list]:
    lower = 1 if strict else 0
    tasks = [FrameTask("left_ee"), PositionTask("right_ee", cost=0.7), FrameTask("torso", "body")]
    tasks += [PostureTask(cost=0.1, priority=lower), DampingTask(0.01, priority=lower)]
    limits = [ConfigurationLimit(), VelocityLimit(3.0)]
    if variant == "collision":
        pairs = [(["left_hand", "left_fore", "left_upper"], ["table"])]
        limits.append(CollisionAvoidanceLimit(pairs, minimum_distance=0.02, detection_distance=0.3))
    return tasks, limits


def _targets(robot, tasks, rng, near: bool):
    """New targets: the frames' poses at a configuration near ``q`` or anywhere."""
    q = robot.random_q(rng)
    for task in tasks:
        if isinstance(task, FrameTask):
            task.set_target(robot.fk(q, task.frame_name))
        elif isinstance(task, PositionTask):
            task.set_target(robot.fk(q, task.frame_name)[:3, 3] + (0.0 if near else 0.3))


def _both_paths(robot, stack, strict, variant, backend="daqp"):
    problems = []
    for compiled in (True, False):
        tasks, limits = stack(robot, strict, variant)
        problems.append(
            Problem(robot, tasks, limits, backend=backend, damping=1e-6, compiled=compiled)
        )
    return problems


def _compare(robot, fast, general, rng, states: int) -> float:
    """The largest difference of the two paths' steps over random states and targets.

    A state where the general path's back-end failed on level 1 (a skipped level: quadprog on
    a degenerate reduced QP, whose success turns on round-off) is left out; at most 2 %.
    """
    worst, skipped = 0.0, 0
    for k in range(states):
        for problem in (fast, general):
            _targets(robot, problem.tasks, np.random.default_rng(k), near=k % 3 == 0)
        q = robot.random_q(rng)
        if k % 4 == 1:  # a joint on its limit: bounds bind exactly there
            q = robot.clip(q + 10.0 * (rng.random(robot.nq) - 0.5) * robot.flat)
        dt = [0.01, 0.05, 0.2][k % 3]
        before = general.stats.get("skipped_levels", 0)
        a, b = fast.step(q, dt), general.step(q, dt)
        if general.stats.get("skipped_levels", 0) > before:
            skipped += 1
            continue
        worst = max(worst, float(np.max(np.abs(a - b))))
    assert skipped <= 0.02 * states
    return worst


@pytest.mark.parametrize("strict", [False, True])
@pytest.mark.parametrize("variant", ["pose", "position", "two frames"])
@pytest.mark.parametrize("backend", ["daqp", "quadprog"])
def test_panda_steps_are_the_general_paths(panda, strict, variant, backend):
    fast, general = _both_paths(panda, _panda_stack, strict, variant, backend)
    assert fast.compiled and not general.compiled
    worst = _compare(panda, fast, general, np.random.default_rng(7), 150)
    assert worst <= (STRICT_TOL if strict else WEIGHTED_TOL)


@pytest.mark.parametrize("strict", [False, True])
@pytest.mark.parametrize("variant", ["box", "collision"])
def test_whole_model_steps_are_the_general_paths(torso, strict, variant):
    fast, general = _both_paths(torso, _torso_stack, strict, variant)
    assert fast.compiled and not general.compiled
    worst = _compare(torso, fast, general, np.random.default_rng(3), 120)
    assert worst <= (STRICT_TOL if strict else WEIGHTED_TOL)


@pytest.mark.parametrize("strict", [False, True])
def test_static_steps_are_the_general_paths(panda, strict):
    """A driver's step: Levenberg–Marquardt damping on level 0 and a trust region."""
    fast, general = _both_paths(panda, _panda_stack, strict, "pose")
    rng = np.random.default_rng(2)
    worst = 0.0
    for k in range(100):
        for problem in (fast, general):
            _targets(panda, problem.tasks, np.random.default_rng(k), near=k % 2 == 0)
        q = panda.random_q(rng)
        damping, max_step = [(0.0, None), (1e-2, 0.3), (1.0, 0.05)][k % 3]
        a = fast.static_step(q, 0.5, lm_damping=damping, max_step=max_step)
        b = general.static_step(q, 0.5, lm_damping=damping, max_step=max_step)
        worst = max(worst, float(np.max(np.abs(a - b))))
        if max_step is not None:
            assert np.max(np.abs(a)) <= max_step
    assert worst <= (STRICT_TOL if strict else WEIGHTED_TOL)


def test_collision_rows_that_bind_are_the_general_paths(torso):
    """The hand driven into the table: the rows bind and the rows' QP solves level 0 with them."""
    fast, general = _both_paths(torso, _torso_stack, False, "collision")
    q = torso.home.copy()
    worst, binding = 0.0, 0
    for _ in range(60):
        for problem in (fast, general):
            problem.tasks[0].set_target(redik.lie.make_pose(np.eye(3), [0.4, 0.25, 0.9]))
            problem.tasks[1].set_target(torso.fk(torso.home, "right_ee")[:3, 3])
            problem.tasks[2].set_target(torso.fk(torso.home, "torso"))
        a, b = fast.step(q, 0.05), general.step(q, 0.05)
        worst = max(worst, float(np.max(np.abs(a - b))))
        limit = general.limits[2]
        binding += bool(np.any(limit.floor < limit.minimum_distance))
        q = torso.integrate(q, b)
    assert binding > 0  # the test reached the rows
    assert worst <= WEIGHTED_TOL


@pytest.mark.parametrize("distance", [0.02, 0.1, 0.3])
def test_near_pairs_keeps_every_pair_closer_than_the_distance(torso, distance):
    """The bounding spheres and boxes skip a pair only when ``mj_geomDistance`` does too."""
    limit = CollisionAvoidanceLimit(minimum_distance=0.0).bind(torso)
    model, data = torso.model, torso.state.data
    pairs = np.ascontiguousarray(limit.pairs, dtype=np.int64)
    rbound = model.geom_rbound
    radii = rbound[pairs[:, 0]] + rbound[pairs[:, 1]]
    bounded = (rbound[pairs[:, 0]] > 0.0) & (rbound[pairs[:, 1]] > 0.0)
    candidates = np.zeros(len(pairs), dtype=np.int64)
    rng, fromto, skipped = np.random.default_rng(4), np.zeros(6), 0
    for _ in range(200):
        torso.state.update(torso.random_q(rng))
        count = near_pairs(data.geom_xpos, data.geom_xmat, pairs, radii, bounded,
                           model.geom_aabb, distance, candidates)  # fmt: skip
        near = set(candidates[:count].tolist())
        for i, (a, b) in enumerate(pairs):
            d = mujoco.mj_geomDistance(model, data, a, b, distance, fromto)
            assert i in near or d >= distance
        skipped += len(pairs) - count
    assert skipped > 0  # the bounds did skip pairs


def test_changed_costs_gains_and_targets_reach_the_plan(panda):
    fast, general = _both_paths(panda, _panda_stack, False, "pose")
    rng = np.random.default_rng(5)
    q = panda.random_q(rng)
    for problem in (fast, general):
        _targets(panda, problem.tasks, np.random.default_rng(1), near=True)
    edits = [
        lambda p: p.tasks[0].set_orientation_cost(3.0),
        lambda p: setattr(p.tasks[0], "gain", 0.3),
        lambda p: p.tasks[1].set_target(panda.random_q(np.random.default_rng(2))),
        lambda p: p.tasks[2].set_cost(2.0),
        lambda p: p.tasks[0].set_target(panda.fk(panda.home)),
    ]
    for edit in edits:
        before = fast.step(q, 0.05)
        for problem in (fast, general):
            edit(problem)
        after = fast.step(q, 0.05)
        assert np.max(np.abs(after - before)) > 1e-6  # the edit changes the step
        np.testing.assert_allclose(after, general.step(q, 0.05), rtol=0, atol=WEIGHTED_TOL)


def _mink_frame_task() -> mink.FrameTask:
    task = mink.FrameTask("ee", "site", 1.0, 1.0)
    task.set_target(mink.SE3.identity())
    return task


@pytest.mark.parametrize(
    "make",
    [
        lambda r: Problem(r, [FrameTask("ee", target=np.eye(4))], compiled=False),
        lambda r: Problem(r, [FrameTask("ee", target=np.eye(4))], backend="proxsuite"),
        lambda r: Problem(r, [FrameTask("ee", target=np.eye(4))], step_damping=0.1),
        lambda r: Problem(r, [FrameTask("ee", target=np.eye(4), lm_damping=1.0)]),
        lambda r: Problem(r, [_mink_frame_task()]),
        lambda r: Problem(r, [FrameTask("ee", target=np.eye(4))], [AccelerationLimit(1.0)]),
        lambda r: Problem(r, [FrameTask("ee", target=np.eye(4))], [ConfigurationLimit(priority=0)]),
        lambda r: Problem(
            r,
            [FrameTask("ee", target=np.eye(4)), PostureTask(priority=1), DampingTask(priority=2)],
        ),
        lambda r: Problem(  # level 0 of two is not a least-squares level
            r,
            [FrameTask("ee", target=np.eye(4)), PostureTask(priority=0), DampingTask(priority=1)],
        ),
    ],
    ids=["off", "proxsuite", "step damping", "lm damping", "mink task", "acceleration",
         "ranked", "three levels", "weighted level 0"],
)  # fmt: skip
def test_what_the_plan_does_not_cover_takes_the_general_path(panda, make):
    problem = make(panda)
    assert not problem.compiled
    assert problem.step(panda.home, 0.01).shape == (panda.dof,)


def test_the_plan_raises_the_general_paths_errors(panda):
    problem = Problem(panda, [FrameTask("ee")], [ConfigurationLimit(), VelocityLimit(1.0)])
    assert problem.compiled
    with pytest.raises(TargetNotSet):
        problem.step(panda.home, 0.01)
    problem.tasks[0].set_target(panda.fk(panda.home))
    with pytest.raises(InvalidInput, match="VelocityLimit needs"):
        problem.step(panda.home)
    with pytest.raises(InvalidInput, match="dt"):
        problem.step(panda.home, dt=float("inf"))
    with pytest.raises(InvalidConfiguration, match="NaN or inf"):
        problem.step(np.full(7, np.nan), 0.01)
    with pytest.raises(InvalidConfiguration, match="7"):
        problem.step(np.zeros(3), 0.01)
    # A list and an int dt are converted as the general path converts them.
    np.testing.assert_array_equal(
        problem.step(panda.home.tolist(), 1), problem.step(panda.home, 1.0)
    )


def test_an_empty_box_is_the_general_paths_error(panda):
    limits = [ConfigurationLimit(), VelocityLimit(1.0)]
    problem = Problem(panda, [FrameTask("ee", target=np.eye(4))], limits)
    assert problem.compiled
    outside = panda.upper + 0.5  # the way back into range is longer than a tick allows
    with pytest.raises(redik.InfeasibleProblem):
        problem.step(outside, 0.01)


# ---------------------------------------------------------------------------------------------
# Kernels


def _random_box_qp(rng, n: int, degenerate: bool):
    M = rng.normal(size=(n, n))
    H = M @ M.T + 10.0 ** rng.uniform(-6, 0) * np.eye(n)
    c = rng.normal(size=n) * 3.0
    lb, ub = -rng.random(n), rng.random(n)
    if degenerate:
        fixed = rng.random(n) < 0.3
        lb[fixed] = ub[fixed] = rng.uniform(-0.5, 0.5, fixed.sum())  # zero-width bounds
        lb[rng.random(n) < 0.2] = -np.inf
        ub[rng.random(n) < 0.2] = np.inf
    return H, c, lb, ub


def _kkt_residual(H, c, lb, ub, x) -> float:
    """Largest violation of the box QP's KKT conditions, relative to the gradient's scale."""
    g = H @ x + c
    interior = (x > lb) & (x < ub)
    bad = np.abs(g[interior]).tolist()
    bad += np.maximum(-g[(x <= lb) & ~interior & (ub > lb)], 0).tolist()  # at lower: g ≥ 0
    bad += np.maximum(g[(x >= ub) & ~interior & (ub > lb)], 0).tolist()  # at upper: g ≤ 0
    return max(bad, default=0.0) / (1.0 + np.abs(c).max())


@pytest.mark.parametrize("degenerate", [False, True])
def test_box_qp_is_daqps_minimiser(degenerate):
    rng = np.random.default_rng(11)
    none = np.zeros((0, 1))
    for _ in range(400):
        n = int(rng.integers(1, 36))
        H, c, lb, ub = _random_box_qp(rng, n, degenerate)
        x = np.linalg.solve(H, -c)
        iterations = box_qp(H, c, lb, ub, none.reshape(0, n), np.zeros(0), 0, x, 4 * n + 10)
        assert iterations >= 1
        assert np.all(x >= lb) and np.all(x <= ub)
        assert _kkt_residual(H, c, lb, ub, x) < 1e-8
        reference, _, exitflag, _ = daqp.solve(
            H, c, np.zeros((0, n)), ub, lb, np.zeros(n, np.int32)
        )
        assert exitflag == 1
        scale = 1.0 + np.abs(reference).max()
        assert np.max(np.abs(x - reference)) / scale < 1e-6


@pytest.mark.parametrize("dependent", [False, True])
def test_rows_qp_is_daqps_minimiser(dependent):
    """Rows only (the box wide): the dual method's minimiser and active rows are DAQP's."""
    rng = np.random.default_rng(12)
    solved = 0
    for _ in range(400):
        n, m = int(rng.integers(2, 36)), int(rng.integers(1, 12))
        M = rng.standard_normal((n, n))
        H, c = M @ M.T + 0.1 * np.eye(n), rng.standard_normal(n)
        C, u = rng.standard_normal((m, n)), rng.uniform(-0.5, 1.0, m)
        if dependent and m > 2:  # a row that is a combination of two others: degenerate vertices
            C[2] = 0.5 * C[0] + 0.5 * C[1]
            u[2] = 0.5 * u[0] + 0.5 * u[1]
        lb, ub = np.full(n, -1e3), np.full(n, 1e3)
        x = np.zeros(n)
        active = rows_qp(np.linalg.cholesky(H), c, C, u, m, lb, ub, 1e-9, x)
        reference, _, exitflag, info = daqp.solve(
            H, c, C, np.concatenate([ub, u]), np.concatenate([lb, np.full(m, -1e30)]),
            np.zeros(n + m, np.int32),
        )  # fmt: skip
        if exitflag != 1:  # rows that cannot all hold
            assert active < 0
            continue
        assert active == np.count_nonzero(info["lam"][n:])
        assert np.all(C @ x <= u + 1e-9)
        scale = 1.0 + np.abs(reference).max()
        assert np.max(np.abs(x - reference)) / scale < 1e-9
        solved += 1
    assert solved > 300


def test_rows_qp_refuses_a_broken_box_and_rows_that_cannot_hold():
    L, c = np.eye(2), np.array([-1.0, -1.0])  # H = I
    rows, bounds = np.array([[1.0, 1.0]]), np.array([1.5])  # x₁ + x₂ ≤ 1.5: at (0.75, 0.75)
    x = np.zeros(2)
    assert rows_qp(L, c, rows, bounds, 1, np.full(2, -1.0), np.full(2, 2.0), 0.0, x) == 1
    assert np.allclose(x, [0.75, 0.75])
    assert rows_qp(L, c, rows, bounds, 1, np.full(2, -1.0), np.full(2, 0.5), 0.0, x) == -1
    opposite, apart = np.array([[1.0, 0.0], [-1.0, 0.0]]), np.array([-1.0, -1.0])  # x₁ ≤ −1, x₁ ≥ 1
    assert rows_qp(L, c, opposite, apart, 2, np.full(2, -9.0), np.full(2, 9.0), 0.0, x) == -1


def test_rotation_difference_is_mujocos(torso):
    """``q ⊖ r`` across a free joint's orientation: ``mj_differentiatePos``'s, to round-off."""
    rng, work = np.random.default_rng(6), np.zeros(11)
    for k in range(300):
        r, q = torso.random_q(rng), torso.random_q(rng)
        q[3:7] *= [1.0, 0.5, 2.0, 1e-9][k % 4]  # quaternions that are not unit
        if k % 5 == 0:
            q[3:7] = -r[3:7]  # the same rotation: the angle wraps to zero
        rotation_difference(q, r, 3, work)
        reference = torso.difference(r, q)[3:6]
        assert np.max(np.abs(work[8:11] - reference)) <= 1e-13


def test_box_qp_reports_rows_it_breaks_and_non_definite_blocks():
    H, c = np.eye(2), np.array([-1.0, -1.0])
    lb, ub = np.full(2, -1.0), np.full(2, 2.0)
    x = np.array([1.0, 1.0])
    rows, bounds = np.array([[1.0, 1.0]]), np.array([1.5])  # x₁ + x₂ ≤ 1.5 broken by (1, 1)
    assert box_qp(H, c, lb, ub, rows, bounds, 1, x, 10) == -2
    indefinite = np.array([[1.0, 0.0], [0.0, -1.0]])
    assert box_qp(indefinite, c, lb, ub, rows, bounds, 0, np.zeros(2), 10) == -1


def test_point_jacobian_is_mujocos(torso):
    model, data = torso.model, torso.state.data
    column_of = np.full(model.nv, -1, dtype=np.int64)
    column_of[torso.dof_indices] = np.arange(torso.dof)
    torso.state.update(torso.random_q(np.random.default_rng(0)))
    jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    J = np.zeros((6, torso.dof))
    for body in range(1, model.nbody):
        dofs, columns = dof_chain(model, body, column_of)
        point = data.xipos[body] + 0.1
        point_jacobian(data.cdof, data.subtree_com, model.body_rootid[body], point,
                       np.array([*dofs, 0]), np.array([*columns, 0]), len(dofs), J)  # fmt: skip
        mujoco.mj_jac(model, data, jacp, jacr, point, body)
        np.testing.assert_allclose(J[:3], jacp[:, torso.dof_indices], rtol=0, atol=1e-15)
        np.testing.assert_allclose(J[3:], jacr[:, torso.dof_indices], rtol=0, atol=1e-15)


def test_null_space_is_lapacks_basis():
    rng = np.random.default_rng(4)
    for m, n in [(6, 7), (3, 7), (12, 35), (1, 2)]:
        A = rng.normal(size=(m, n))
        N = np.zeros((n, n - m))
        assert null_space(A, N) > 1e-3
        np.testing.assert_allclose(A @ N, 0.0, atol=1e-12)
        np.testing.assert_allclose(N.T @ N, np.eye(n - m), atol=1e-12)
        # LAPACK's reflectors (dgeqrf, dormqr): the same basis, not only the same span.
        np.testing.assert_allclose(N, row_null_space(A, 1e-10), atol=1e-12)
    assert null_space(np.array([[1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]), np.zeros((3, 1))) == 0.0
