"""Back-ends: every installed one agrees on random IK QPs; failures name back-end and size."""

from __future__ import annotations

import numpy as np
import pytest

import redik
from redik.core.exceptions import BackendError, InfeasibleProblem
from redik.qp import QP, Backend, FallbackChain, available_backends, make_backend

TIGHT = 1e-6  # the agreement the older tests ask of persistent/fallback back-ends


def random_ik_qps(rng: np.random.Generator, count: int, robot_name: str = "panda") -> list[QP]:
    """Damped least-squares QPs of an arm with a position box, rows and equalities.

    The damping (1e-3) bounds the conditioning: with 1e-6, the redundant direction is so
    flat that tolerance-based solvers legitimately differ by ~1e-4 along it. Errors of
    0.05 to 2 (m, rad) against steps capped at 0.05 to 10 rad make some boxes active and
    leave others inactive.
    """
    robot = redik.load(robot_name)
    n = robot.dof
    qps = []
    for i in range(count):
        q = robot.random_q(rng)
        J = robot.jacobian(q, reference="body")
        e = rng.normal(scale=(0.05, 0.3, 2.0)[i % 3], size=6)
        H = J.T @ J + 1e-3 * np.eye(n)
        c = -J.T @ e
        cap = (10.0, 0.5, 0.05)[(i // 3) % 3]
        qp = QP(H, c, np.maximum(robot.lower - q, -cap), np.minimum(robot.upper - q, cap))
        if i % 3 == 1:
            qp.C = rng.normal(size=(3, n))
            qp.l = np.array([-0.1, -np.inf, -0.2])
            qp.u = np.array([0.1, 0.05, np.inf])
        if i % 3 == 2:
            qp.A = J[:1]
            qp.b = np.array([0.01])
        qps.append(qp)
    return qps


def kkt_residual(qp: QP, x: np.ndarray, active_tol: float = 1e-9) -> tuple[float, float]:
    """``(stationarity residual, most negative multiplier)`` of ``x``: the multipliers of
    the constraints active within ``active_tol`` by least squares on ``Hx + c + Gᵀλ + Aᵀν
    = 0``. A feasible ``x`` with both ≈ 0 is the minimiser (KKT suffices for a convex QP).
    """
    G, h = qp.one_sided(bounds=True)
    gradient = qp.H @ x + qp.c
    columns, signs = [], []
    if G is not None:
        active = G @ x >= h - active_tol
        columns.append(G[active].T)
        signs.append(np.ones(int(active.sum())))
    if qp.A is not None:
        columns.append(qp.A.T)
        signs.append(np.zeros(qp.n_eq))  # equality multipliers have no sign
    if not columns:
        return float(np.max(np.abs(gradient))), 0.0
    M = np.hstack(columns)
    multipliers = np.linalg.lstsq(M, -gradient, rcond=None)[0]
    residual = float(np.max(np.abs(gradient + M @ multipliers)))
    sign = np.concatenate(signs)
    return residual, float(np.min(multipliers * sign, initial=0.0))


@pytest.fixture(scope="module")
def certified_qps():
    """Random IK QPs (3 seeds × panda and ur5e) with their KKT-certified minimisers."""
    cases = []
    for robot_name in ("panda", "ur5e"):
        for seed in (1, 2, 3):
            for qp in random_ik_qps(np.random.default_rng(seed), 18, robot_name):
                x = make_backend("quadprog").solve(qp)
                residual, multiplier = kkt_residual(qp, x)
                assert qp.max_violation(x) <= 1e-10 and residual <= 1e-9 and multiplier >= -1e-9
                cases.append((qp, x))
    active = [np.any((x <= qp.lb + 1e-9) | (x >= qp.ub - 1e-9)) for qp, x in cases]
    assert 0.2 < np.mean(active) < 0.8  # both active and inactive boxes are exercised
    return cases


@pytest.mark.parametrize("name", available_backends())
def test_every_backend_meets_its_declared_tolerance_on_random_ik_qps(name, certified_qps):
    backend = make_backend(name)  # one instance: persistent back-ends warm-start
    worst_violation = worst_distance = 0.0
    for qp, x_ref in certified_qps:
        x = backend.solve(qp)
        worst_violation = max(worst_violation, qp.max_violation(x))
        worst_distance = max(worst_distance, float(np.max(np.abs(x - x_ref))))
    assert worst_violation <= backend.tolerance, (name, worst_violation)
    assert worst_distance <= backend.tolerance, (name, worst_distance)


def test_available_backends_lists_only_what_imports(monkeypatch):
    import sys

    import qpsolvers

    assert "cvxpy" in available_backends()
    monkeypatch.setitem(sys.modules, "cvxpy", None)  # `import cvxpy` now raises ImportError
    monkeypatch.setitem(sys.modules, "proxsuite", None)
    names = available_backends()
    assert "cvxpy" not in names and "proxsuite" not in names and "daqp" in names
    with pytest.raises(BackendError, match=r"'cvxpy' is not installed.*available: \['daqp'"):
        make_backend("cvxpy")
    monkeypatch.setattr(qpsolvers, "available_solvers", ["quadprog"])
    assert available_backends() == ["daqp", "quadprog"]


def test_unknown_backend_lists_the_available_ones():
    with pytest.raises(BackendError, match=r"available: .*daqp"):
        make_backend("gurobi-by-mistake")
    with pytest.raises(BackendError, match="a name, a list of names or a Backend"):
        make_backend(3)


def test_a_failure_names_the_backend_and_the_problem_size(rng):
    qp = random_ik_qps(rng, 1)[0]
    with pytest.raises(BackendError, match=r"'osqp'.*n=7 variables, 7 bounds"):
        make_backend("osqp", max_iterations=1, polishing=False).solve(qp)


class Failing(Backend):
    name = "failing"

    def solve(self, qp: QP) -> np.ndarray:
        raise self._error("always", qp)


def test_fallback_chain_uses_the_next_backend_and_reports_every_failure(rng):
    qp = random_ik_qps(rng, 1)[0]
    chain = FallbackChain([Failing(), make_backend("daqp")])
    np.testing.assert_allclose(chain.solve(qp), make_backend("quadprog").solve(qp), atol=1e-9)
    assert chain.tolerance == 1e-9
    assert chain.last_used == "daqp"
    with pytest.raises(BackendError, match=r"failing.*always.*failing"):
        FallbackChain([Failing(), Failing()]).solve(qp)
    assert isinstance(make_backend(["daqp", "proxsuite"]), FallbackChain)


def empty_box() -> QP:
    # x₀ ≤ −1 and x₀ ≥ 1 as rows: no point satisfies both.
    return QP(np.eye(2), np.zeros(2), C=np.array([[1.0, 0.0]] * 2), l=np.array([-np.inf, 1.0]),
              u=np.array([-1.0, np.inf]))  # fmt: skip


@pytest.mark.parametrize("name", ["daqp", "cvxpy"])  # ProxQP may just hit its iteration limit
def test_infeasible_constraints_are_reported_as_such(name):
    with pytest.raises(InfeasibleProblem, match=rf"'{name}'.*infeasible"):
        make_backend(name).solve(empty_box())


def test_a_chain_of_infeasible_reports_is_infeasible():
    with pytest.raises(InfeasibleProblem, match="every back-end"):
        make_backend(["daqp", "cvxpy"]).solve(empty_box())


def test_persistent_proxsuite_follows_changing_problems(rng):
    backend = make_backend("proxsuite")
    for qp in random_ik_qps(rng, 6):  # sizes change every call: re-initialised as needed
        np.testing.assert_allclose(
            backend.solve(qp), make_backend("quadprog").solve(qp), atol=TIGHT
        )


def test_daqp_solves_every_step_of_ik_runs_with_the_default_regularisation(rng):
    """mink's 1e-12 damping lets DAQP call valid IK QPs infeasible; redik's 1e-6 must not."""
    from redik.qp import Problem
    from redik.tasks import FrameTask, JointLimitAvoidanceTask, PostureTask

    robot = redik.load("panda")
    tasks = [FrameTask("ee", target=np.eye(4)), JointLimitAvoidanceTask(), PostureTask()]
    problem = Problem(robot, tasks, backend="daqp")
    reference = Problem(robot, tasks, backend="quadprog")
    for q_target in robot.random_q(rng, size=10):
        tasks[0].set_target(robot.fk(q_target))
        q = robot.random_q(rng)
        for _ in range(15):  # raises InfeasibleProblem/BackendError on a spurious failure
            dq = problem.step(q)
            np.testing.assert_allclose(dq, reference.step(q), atol=1e-6)
            q = q + dq
    assert problem.stats.get("skipped_levels", 0) == 0


def test_daqp_solves_an_unconstrained_qp_twice(rng):
    # The second call updates the workspace in place: with no bounds and no rows DAQP's
    # update raised IndexError (``Problem(robot, tasks, limits=[])``, second step).
    backend = make_backend("daqp")
    for qp in random_ik_qps(rng, 3)[:1] * 3:
        free = QP(qp.H, qp.c)
        np.testing.assert_allclose(backend.solve(free), np.linalg.solve(qp.H, -qp.c), atol=1e-9)


def test_daqp_set_up_and_update_failures_are_reported_not_left_in_the_workspace():
    # A zero row with a negative right-hand side (0 ≤ −1) or a crossed bound fails DAQP's
    # set-up or update, before any solve: the set-up's failure left a model whose solve
    # raised a raw RuntimeError, the update's one that returned the previous QP's x.
    backend = make_backend("daqp")
    zero_row = QP(np.eye(2), np.zeros(2), C=np.zeros((1, 2)), l=np.array([-np.inf]),
                  u=np.array([-1.0]))  # fmt: skip
    for _ in range(2):  # the workspace is forgotten: the same report the second time
        with pytest.raises(InfeasibleProblem, match=r"'daqp'.*infeasible"):
            backend.solve(zero_row)
    box = QP(np.eye(2), -np.ones(2), lb=-np.full(2, 0.5), ub=np.full(2, 0.5))
    np.testing.assert_allclose(backend.solve(box), [0.5, 0.5])
    crossed = QP(np.eye(2), -np.ones(2), lb=np.array([0.2, -0.5]), ub=np.array([0.1, 0.5]))
    with pytest.raises(InfeasibleProblem, match=r"'daqp'.*infeasible"):
        backend.solve(crossed)  # same sizes: an update of the workspace
    np.testing.assert_allclose(backend.solve(box), [0.5, 0.5])
    with pytest.raises(BackendError, match="non-convex"):
        backend.solve(QP(-np.eye(2), np.zeros(2), lb=-np.ones(2), ub=np.ones(2)))


@pytest.mark.parametrize("names", [["daqp"], ["proxsuite"], ["proxsuite", "daqp"]])
def test_reset_makes_a_persistent_backend_answer_as_a_fresh_one(names, rng):
    if not set(names) <= set(available_backends()):
        pytest.skip(f"{names} not installed")
    qps = random_ik_qps(rng, 30)[1::3]  # one size (box, rows): the workspace is updated
    fresh = [make_backend(names).solve(qp) for qp in qps]
    backend = make_backend(names)
    # proxsuite's own answers to one problem differ from run to run by ~1e-17 (its threads sum
    # in varying order): a reset answer must then be as close to the fresh one as a second
    # fresh answer is, and closer than the warm-started answers, so that reset had work to do.
    noise = max(
        np.abs(make_backend(names).solve(qp) - x).max() for qp, x in zip(qps, fresh, strict=True)
    )
    used = []  # answers after another problem: warm-started, equal to round-off only
    reset = []
    for qp, x in zip(qps, fresh, strict=True):
        backend.solve(qps[-1])
        used.append(np.abs(backend.solve(qp) - x).max())
        backend.solve(qps[-1])
        backend.reset()
        reset.append(np.abs(backend.solve(qp) - x).max())
    if names == ["daqp"]:
        assert max(reset) == 0.0  # daqp is deterministic: bit for bit
    assert max(reset) <= max(4 * noise, 1e-16)
    assert max(used) > max(reset)  # the warm start did change an answer: reset had work to do
