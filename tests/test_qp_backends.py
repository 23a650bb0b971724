"""Back-ends: every installed one agrees on random IK QPs; failures name back-end and size."""

from __future__ import annotations

import numpy as np
import pytest

import redik
from redik.exceptions import BackendError, InfeasibleProblem
from redik.qp import QP, Backend, FallbackChain, available_backends, make_backend

# First-order solvers (osqp, scs) are held to 1e-5: their accuracy depends on the
# conditioning; the others agree to 1e-6 (in practice ~1e-8).
LOOSE = {"osqp": 1e-5, "scs": 1e-5}
TIGHT = 1e-6


def random_ik_qps(rng: np.random.Generator, count: int) -> list[QP]:
    """Damped least-squares QPs of a 7-joint arm with a position box, rows and equalities.

    The damping (1e-3) bounds the conditioning: with 1e-6, the redundant direction is so
    flat that tolerance-based solvers (ProxQP) legitimately differ by ~1e-4 along it.
    """
    robot = redik.load("panda")
    qps = []
    for i in range(count):
        q = robot.random_q(rng)
        J = robot.jacobian(q, reference="body")
        e = rng.normal(scale=0.3, size=6)
        H = J.T @ J + 1e-3 * np.eye(7)
        c = -J.T @ e
        qp = QP(H, c, robot.lower - q, robot.upper - q)
        if i % 3 == 1:
            qp.C = rng.normal(size=(3, 7))
            qp.l = np.array([-0.1, -np.inf, -0.2])
            qp.u = np.array([0.1, 0.05, np.inf])
        if i % 3 == 2:
            qp.A = J[:1]
            qp.b = np.array([0.01])
        qps.append(qp)
    return qps


def test_every_backend_agrees_on_random_ik_qps(rng):
    qps = random_ik_qps(rng, 9)
    reference = [make_backend("quadprog").solve(qp) for qp in qps]
    for name in available_backends():
        backend = make_backend(name)  # one instance: persistent back-ends warm-start
        tolerance = LOOSE.get(name, TIGHT)
        for qp, x_ref in zip(qps, reference, strict=True):
            x = backend.solve(qp)
            np.testing.assert_allclose(x, x_ref, atol=tolerance, err_msg=name)
            assert qp.max_violation(x) <= max(backend.tolerance, 1e-9) * 10, name


def test_unknown_backend_lists_the_available_ones():
    with pytest.raises(BackendError, match=r"available: .*daqp"):
        make_backend("gurobi-by-mistake")


def test_a_failure_names_the_backend_and_the_problem_size(rng):
    qp = random_ik_qps(rng, 1)[0]
    with pytest.raises(BackendError, match=r"'osqp'.*n=7 variables, 7 bounds"):
        make_backend("osqp", max_iter=1, polishing=False).solve(qp)


class Failing(Backend):
    name = "failing"

    def solve(self, qp: QP) -> np.ndarray:
        raise self._error("always", qp)


def test_fallback_chain_uses_the_next_backend_and_reports_every_failure(rng):
    qp = random_ik_qps(rng, 1)[0]
    chain = FallbackChain([Failing(), make_backend("daqp")])
    np.testing.assert_allclose(chain.solve(qp), make_backend("quadprog").solve(qp), atol=1e-9)
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
    from redik.problem import Problem
    from redik.tasks import JointLimitAvoidanceTask, PoseTask, PostureTask

    robot = redik.load("panda")
    tasks = [PoseTask(np.eye(4)), JointLimitAvoidanceTask(), PostureTask()]
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
