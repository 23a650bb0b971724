"""One status vocabulary: every solver reports a redik.Status, and every Status is reported.

Each solver is driven to each status it can produce (where a small case provokes it), and the
union of what they returned must be the whole enum: a member that no solver produces would
be a declared status nothing means.
"""

from __future__ import annotations

import json

import mujoco
import numpy as np
import pytest

import redik
from redik import Status, lie
from redik.core.result import IKResult
from redik.solvers.analytic import planar_2r
from redik.solvers.redundancy import Manipulability, gradient_projection_ik

DRIVEN: dict[str, set[Status]] = {
    "test_root_finders_report_every_status_of_theirs": {
        Status.CONVERGED, Status.MAX_ITERATIONS, Status.SINGULAR, Status.STALLED, Status.DIVERGED
    },
    "test_solve_pose_reports_converged_unreachable_max_iterations_and_limits": {
        Status.CONVERGED, Status.UNREACHABLE, Status.MAX_ITERATIONS, Status.LIMITS
    },
    "test_solve_problem_reports_every_status_of_its": {
        Status.CONVERGED, Status.SUBOPTIMAL, Status.UNREACHABLE, Status.MAX_ITERATIONS,
        Status.STALLED,
    },
    "test_solve_batch_reports_converged_stalled_unreachable_and_invalid_per_target": {
        Status.CONVERGED, Status.STALLED, Status.UNREACHABLE, Status.INVALID
    },
    "test_self_motion_reports_converged_max_iterations_unreachable_and_limits": {
        Status.CONVERGED, Status.MAX_ITERATIONS, Status.UNREACHABLE, Status.LIMITS
    },
    "test_gradient_projection_reports_converged_and_max_iterations": {
        Status.CONVERGED, Status.MAX_ITERATIONS
    },
    "test_closed_form_results_report_converged_unreachable_and_limits": {
        Status.CONVERGED, Status.UNREACHABLE, Status.LIMITS
    },
}  # fmt: skip
"""The statuses each test below drives its solver to: every test checks it produced exactly
its set (so the table stays true), and the union must be the whole enum. Declared rather than
gathered across tests, so that the check holds however pytest-xdist spreads the tests."""

PRODUCED: set[Status] = set()


@pytest.fixture(autouse=True)
def statuses_of_this_test(request):
    PRODUCED.clear()
    yield
    expected = DRIVEN.get(request.node.name)
    if expected is not None:
        assert PRODUCED == expected, f"produced {PRODUCED}, declared {expected}"


def produced(result, expected: str) -> None:
    """Check ``result.status`` is the member ``expected`` and record it."""
    assert isinstance(result.status, Status), type(result.status)
    assert result.status is Status(expected), (result.status, getattr(result, "message", ""))
    PRODUCED.add(result.status)


@pytest.fixture(scope="module")
def planar():
    return redik.load("planar_2r")


@pytest.fixture(scope="module")
def narrow():
    """A planar 2R arm whose joints may bend only ±1 rad."""
    spec = mujoco.MjSpec.from_file(str(redik.models.scene_path("planar_2r")))
    for joint in spec.joints:
        joint.range = [-1.0, 1.0]
        joint.limited = mujoco.mjtLimited.mjLIMITED_TRUE
    return redik.Robot(spec.compile(), name="planar_2r_narrow")


def out_of_reach(robot: redik.Robot) -> np.ndarray:
    T = robot.fk(robot.home)
    T[:3, 3] *= 10.0
    return T


def test_status_is_a_str_enum_equal_to_its_value():
    assert Status.CONVERGED == "converged" and "converged" == Status.CONVERGED
    assert f"{Status.MAX_ITERATIONS}" == "max_iterations" == str(Status.MAX_ITERATIONS)
    assert f"{Status.STALLED:>9}" == "  stalled"
    assert {"diverged": 1}[Status.DIVERGED] == 1
    assert json.dumps({"status": Status.LIMITS}) == '{"status": "limits"}'
    assert np.asarray([Status.INVALID]).tolist() == ["invalid"]
    assert Status("unreachable") is Status.UNREACHABLE


def test_results_store_the_member_and_refuse_unknown_statuses():
    result = IKResult(np.zeros(2), False, "stalled", 3, 0.5)
    assert result.status is Status.STALLED
    assert result.summary().startswith("ik: stalled, 3 it")
    with pytest.raises(redik.InvalidInput, match=r"status must be one of .*'converged'"):
        IKResult(np.zeros(2), False, "failed", 3, 0.5)


def test_root_finders_report_every_status_of_theirs():
    def tip(q):  # planar 2R, unit links
        return np.array([np.cos(q[0]) + np.cos(q[0] + q[1]), np.sin(q[0]) + np.sin(q[0] + q[1])])

    produced(redik.solve_equations(tip, [1.2, 0.5], [0.2, 1.4]), "converged")
    produced(redik.solve_equations(tip, [1.2, 0.5], [0.2, 1.4], max_iterations=1), "max_iterations")
    # Outstretched (q2 = 0): J is singular.
    produced(redik.solve_equations(tip, [1.2, 0.5], [0.3, 0.0], singular_tol=1e-6), "singular")
    # Beyond reach: the transpose settles at the closest point, no root.
    far = redik.solve_equations(tip, [3.0, 0.5], [0.2, 0.4], "transpose", step="armijo",
                                rel_tol=1e-6, max_iterations=1000)  # fmt: skip
    produced(far, "stalled")
    # Newton on arctan from |x0| > 1.39 overshoots further every step (a classic).
    produced(redik.solve_equations(lambda q: np.arctan(q), [0.0], [3.0]), "diverged")
    hybrid = redik.solve_equations(tip, [1.2, 0.5], [0.2, 1.4], "hybrid", switch_error=0.1)
    produced(hybrid, "converged")


def test_solve_pose_reports_converged_unreachable_max_iterations_and_limits(planar, narrow):
    T = planar.fk(np.array([0.4, 1.1]))
    produced(redik.solve_pose(planar, T, seed=0), "converged")
    produced(redik.solve_pose(planar, out_of_reach(planar), seed=0), "unreachable")
    tight = redik.solve_pose(planar, T, planar.home, method="newton", max_iterations=1, restarts=0)
    produced(tight, "max_iterations")
    for solution in redik.solve_all(planar, T, n_starts=4, seed=0):
        produced(solution, "converged")
    # Each pose of a 2R arm has one q up to the elbow's sign: θ2 = ±2.9 rad, both beyond ±1.
    for method in redik.solvers.pose.METHODS:
        limited = redik.solve_pose(narrow, narrow.fk(np.array([0.3, 2.9])), seed=0, method=method)
        produced(limited, "limits")
        assert not limited.success and narrow.within_limits(limited.q)
        assert "joint2 = 2.9 outside [-1, 1]" in limited.message
        assert "joint2 at its upper limit" in limited.message
    produced(redik.solve_pose(narrow, out_of_reach(narrow), seed=0), "unreachable")
    produced(redik.solve_pose(narrow, narrow.fk(np.array([0.3, 0.9])), seed=0), "converged")


def test_solve_problem_reports_every_status_of_its(planar, narrow):
    T = planar.fk(np.array([0.4, 1.1]))
    near = redik.Problem(planar, [redik.FrameTask("ee", orientation_cost=0.0, target=T)])
    produced(redik.solve_problem(near, planar.home), "converged")
    one_step = redik.SolveOptions(max_iterations=1, restarts=0)
    produced(redik.solve_problem(near, planar.home, one_step), "max_iterations")
    far = redik.Problem(
        planar, [redik.FrameTask("ee", target=out_of_reach(planar), orientation_cost=0.0)]
    )
    produced(redik.solve_problem(far, planar.home), "unreachable")
    # The narrow elbow stops at its limit short of a pose that needs 2.9 rad: one attempt.
    blocked = redik.Problem(
        narrow, [redik.PositionTask("ee", target=narrow.fk(np.array([0.3, 2.9]))[:3, 3])]
    )
    produced(redik.solve_problem(blocked, narrow.home, redik.SolveOptions(restarts=0)), "stalled")
    # On the pose from the first iteration; one iteration cannot finish the posture below it.
    panda = redik.load("panda")
    stack = redik.Problem(
        panda,
        [
            redik.FrameTask("ee", target=panda.fk(panda.home)),
            redik.PostureTask(panda.midrange, priority=1),
        ],
    )
    produced(redik.solve_problem(stack, panda.home, one_step), "suboptimal")


def test_solve_batch_reports_converged_stalled_unreachable_and_invalid_per_target(planar):
    tilted = planar.fk(np.array([0.4, 1.1]))
    tilted[:3, :3] = tilted[:3, :3] @ lie.so3_exp(np.array([0.5, 0.0, 0.0]))  # out of its plane
    reached = planar.fk(np.array([0.4, 1.1]))
    T = np.stack([reached, tilted, out_of_reach(planar), np.full((4, 4), np.nan)])
    result = redik.solve_batch(planar, T, restarts=0, seed=0, engine="local")
    assert all(isinstance(status, Status) for status in result.statuses)
    assert result.statuses[0] is Status.CONVERGED and result.statuses[3] is Status.INVALID
    assert result.statuses[1] is Status.STALLED  # within reach: the orientation is not
    assert result.statuses[2] is Status.UNREACHABLE  # beyond the reach of the chain
    assert result.status_names.tolist() == [status.value for status in result.statuses]
    PRODUCED.update(result.statuses)


def test_self_motion_reports_converged_max_iterations_unreachable_and_limits(narrow):
    panda = redik.load("panda")
    T = panda.fk(panda.home)
    options = {"seed": 0, "n_starts": 4, "initial": panda.home, "spacing": 0.3}
    produced(redik.explore_self_motion(panda, T, **options), "converged")
    produced(redik.explore_self_motion(panda, T, **options, max_samples=5), "max_iterations")
    produced(redik.explore_self_motion(panda, out_of_reach(panda), **options), "unreachable")
    # A planar 2R arm whose elbow may bend only 1 rad, asked for a pose that needs 2.9 rad.
    q = np.array([0.3, 2.9])
    motion = redik.explore_self_motion(narrow, narrow.fk(q), seed=0, n_starts=8, initial=q)
    produced(motion, "limits")
    assert type(motion.summary()["status"]) is str  # a plain string for JSON and YAML


def test_gradient_projection_reports_converged_and_max_iterations():
    panda = redik.load("panda")
    T = panda.fk(panda.home)
    climbed = gradient_projection_ik(panda, T, panda.home, Manipulability(), max_iterations=500)
    produced(climbed, "converged")
    # The budget spent away from the pose (the pose settled on afterwards is out of reach).
    cut = gradient_projection_ik(panda, out_of_reach(panda), panda.home, Manipulability(),
                                 max_iterations=3)  # fmt: skip
    produced(cut, "max_iterations")


def test_closed_form_results_report_converged_unreachable_and_limits():
    produced(planar_2r(1.2, 0.3, 1.0, 1.0), "converged")
    produced(planar_2r(2.3, 0.0, 1.0, 1.0), "unreachable")
    # Both elbows need |θ2| ≈ 1.4 rad: a range of ±1 rad excludes them.
    limited = planar_2r(1.2, 0.3, 1.0, 1.0, limits=(np.array([-4.0, -1.0]), np.array([4.0, 1.0])))
    produced(limited, "limits")
    assert not limited.success and "joint limits" in limited.reason


def test_every_status_is_produced_by_some_solver():
    driven = set().union(*DRIVEN.values())
    assert driven == set(Status), f"declared but not produced: {set(Status) - driven}"
    assert set(DRIVEN) <= {name for name in globals() if name.startswith("test_")}
