"""Every worked example of the course runs as written, through the public API.

The lecture notes are five documents (000 the IK chapter, 001 a hexapod leg and Newton's
method, 002 De Luca's *Robotics 1* inverse kinematics, 003 and 004 Modern Robotics Chapter 6);
``examples/course/`` holds one script per worked example and its README the index. Each test
here reproduces the notes' numbers as the notes print them (their rounding), from their own
inputs, with the expected values quoted from the notes — never read from redik. Where the
notes slip (a typo, a table started from another guess), the test pins the slip: the printed
number and the corrected one. Beside them, Modern Robotics (Lynch & Park 2017) Example 6.1
(§6.2.2), the IKinBody iterate table the course's quiz refers to.
"""

from __future__ import annotations

import ast
import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import redik
from redik.core.exceptions import NearRotationWarning
from redik.lie import euler_angles, inverse, se3_log, so3_exp
from redik.models.scene_library import get_scene
from redik.solvers.analytic import hexapod_leg, rrp_polar, solver_for, spherical_wrist
from redik.solvers.analytic.hexapod import LECTURE
from redik.solvers.iterative import finite_difference_jacobian, solve_equations


def scene_robot(name: str) -> redik.Robot:
    return redik.Robot.from_file(redik.models.scene_path(name))


# --------------------------------------------------------------------------------------
# Modern Robotics Chapter 6


QUIZ_TARGET = np.array(
    [[-0.585, -0.811, 0, 0.076], [0.811, -0.585, 0, 2.608], [0, 0, 1, 0], [0, 0, 0, 1]]
)
"""The Chapter 6 quiz's ``T_sd``, typed from the book (3 decimals: not exactly a rotation)."""


@pytest.mark.parametrize("stop", ["twist", "pose"])
def test_ikinbody_quiz_gives_the_books_answer(stop):
    """Planar 3R with unit links (the book's ``M = [[1,0,0,3], …]``, ``B_i = (0,0,1, 0,3−i+1,0)``
    is the bundled ``planar_3r``), θ0 = (π/4, π/4, π/4), ε_ω = 0.001, ε_v = 0.0001."""
    robot = scene_robot("planar_3r")
    np.testing.assert_allclose(robot.fk(np.zeros(3)), [[1, 0, 0, 3], [0, 1, 0, 0], [0, 0, 1, 0],
                                                       [0, 0, 0, 1]], atol=1e-12)  # fmt: skip
    with pytest.warns(NearRotationWarning, match="closest rotation"):
        result = redik.solve_pose(
            robot, QUIZ_TARGET, [math.pi / 4] * 3, method="newton", pos_tol=1e-4, rot_tol=1e-3,
            restarts=0, stop=stop,
        )  # fmt: skip
    assert result.success and result.restarts == 0
    assert tuple(np.round(result.q, 3)) == (0.925, 0.586, 0.684)


def test_ikinbody_example_6_1_iterate_table():
    """MR Example 6.1: 2R, θ_d = (30°, 90°), θ0 = (0°, 30°); the book's table of θ^i (deg)
    and, at i = 0, ‖ω_b‖ = 1.571 and ‖v_b‖ = 1.924."""
    robot = scene_robot("planar_2r")
    T_d = robot.fk(np.radians([30.0, 90.0]))
    result = redik.solve_pose(
        robot, T_d, np.radians([0.0, 30.0]), method="newton", pos_tol=1e-4, rot_tol=1e-3,
        restarts=0, stop="twist",
    )  # fmt: skip
    table = np.round(np.degrees(result.history), 2)
    np.testing.assert_array_equal(
        table, [[0.00, 30.00], [34.23, 79.18], [29.98, 90.22], [30.00, 90.00]]
    )
    positions = np.round([robot.fk(q)[:2, 3] for q in result.history], 3)
    np.testing.assert_array_equal(positions[[0, 3]], [[1.866, 0.500], [0.366, 1.366]])
    V_b = se3_log(inverse(robot.fk(result.history[0])) @ T_d)  # (v, ω)
    assert (round(float(np.linalg.norm(V_b[3:])), 3), round(float(np.linalg.norm(V_b[:3])), 3)) == (
        1.571,
        1.924,
    )


def test_newton_root_quiz_two_iterations_with_tol_zero():
    """Newton–Raphson on f(x, y) = (x² − 9, y² − 4) from (1, 1): (5, 2.5), then (3.4, 2.05).
    ``tol=0`` runs exactly ``max_iterations`` iterations, the table the quiz asks for."""
    result = solve_equations(lambda x: np.array([x[0] ** 2 - 9.0, x[1] ** 2 - 4.0]),
                             [0.0, 0.0], [1.0, 1.0], tol=0, max_iterations=2)  # fmt: skip
    assert result.iterations == 2 and result.status == "max_iterations"
    np.testing.assert_allclose(result.history, [[1.0, 1.0], [5.0, 2.5], [3.4, 2.05]], atol=1e-12)


def course_fd_function(x: np.ndarray) -> np.ndarray:
    """The course's forward-difference example, ``f(x) = (x1² + x2², 5x1² + 2x2²)`` at
    (1, 2): derived from its printed ``[[2.1, 4.1], [10.5, 8.2]]`` — a forward difference of
    ``a x²`` at ``x`` is ``a (2x + δ)``, so 2.1, 4.1, 10.5, 8.2 are ``1·(2·1 + 0.1)``,
    ``1·(2·2 + 0.1)``, ``5·(2·1 + 0.1)``, ``2·(2·2 + 0.1)`` (exact J = [[2, 4], [10, 8]])."""
    return np.array([x[0] ** 2 + x[1] ** 2, 5.0 * x[0] ** 2 + 2.0 * x[1] ** 2])


def test_forward_difference_jacobian_with_the_courses_delta():
    x = np.array([1.0, 2.0])
    J = finite_difference_jacobian(course_fd_function, x, step=0.1, scheme="forward")
    np.testing.assert_allclose(J, [[2.1, 4.1], [10.5, 8.2]], atol=1e-12)
    # The same Jacobian drives a Newton step when the course picks δ = 0.1 in the solver.
    x_d = np.array([6.0, 20.0])
    result = solve_equations(course_fd_function, x_d, x, fd_step=0.1, fd_scheme="forward",
                             tol=0, max_iterations=1)  # fmt: skip
    np.testing.assert_allclose(
        result.history[1], x + np.linalg.solve(J, x_d - course_fd_function(x)), atol=1e-12
    )
    central = finite_difference_jacobian(course_fd_function, x, step=0.1)
    np.testing.assert_allclose(central, [[2.0, 4.0], [10.0, 8.0]], atol=1e-12)  # exact for x²


# --------------------------------------------------------------------------------------
# The closed-form examples, in their bundled scenes


def test_rrp_example_is_reachable_in_its_scene():
    """p = (1, 1, 1), d1 = 0.5: θ1 = 45°, θ2 = atan2(0.5, √2) = 19.47°, d3 = 1.5 m."""
    scene = get_scene("rrp_polar")
    assert scene.parameters["d1"] == 0.5
    limits = tuple(np.array(bounds) for bounds in zip(*scene.limits, strict=True))
    result = rrp_polar([1.0, 1.0, 1.0], 0.5, limits=limits)
    front = result.by_label("front")
    assert tuple(np.round([math.degrees(front[0]), math.degrees(front[1]), front[2]], 2)) == (
        45.0,
        19.47,
        1.5,
    )
    robot = scene_robot("rrp_polar")
    T = np.eye(4)
    T[:3, 3] = 1.0
    T[:3, :3] = robot.fk(front.q)[:3, :3]
    assert redik.solve_pose(robot, T, seed=0).success


def test_rrp_scene_holds_both_of_the_courses_solutions():
    """002, RRP analytic solutions: q* = (0.7854, 0.3398, 1.5), q** = (−2.3562, 2.8018, 1.5)."""
    robot = scene_robot("rrp_polar")
    T = np.eye(4)
    T[:3, 3] = 1.0
    solutions = redik.solve_all(robot, T, method="analytic")
    found = sorted(tuple(np.round(solution.q, 4)) for solution in solutions)
    assert found == [(-2.3562, 2.8018, 1.5), (0.7854, 0.3398, 1.5)]


@pytest.mark.parametrize(
    ("scene", "q"),
    [
        ("planar_2r", np.radians([30.0, 90.0])),  # MR Example 6.1, target
        ("planar_2r", np.radians([0.0, 30.0])),  # and initial guess
        ("planar_3r", np.array([0.925, 0.586, 0.684])),  # the IKinBody quiz
        ("planar_3r", np.full(3, math.pi / 4)),
        ("rrp_polar", np.array([math.pi / 4, math.atan2(0.5, math.sqrt(2.0)), 1.5])),  # q*
        ("rrp_polar", np.array([-3 * math.pi / 4, math.pi - math.atan2(0.5, math.sqrt(2.0)), 1.5])),
        # The standing foot (0.15, 0, −0.12) of tests/test_analytic_planar.py, knee-up.
        ("hexapod_leg", hexapod_leg([0.15, 0.0, -0.12], 0.052, 0.082, 0.142, -0.015)[1].q),
    ],
)
def test_every_worked_example_lies_inside_its_scene(scene, q):
    assert scene_robot(scene).within_limits(q)


# --------------------------------------------------------------------------------------
# Conventions of the lectures


def test_hexapod_servo_angles_are_the_lectures():
    """001 "Example: Analytical IK": the notes' three formulas (α from the downward vertical,
    β the interior knee angle, γ = atan(x/y) from the outward y axis), evaluated on the
    bundled leg with a foot at x = 0.05, y = 0.15, Z_offset = 0.105 m below the femur axis,
    give (114.123°, 78.601°, 18.435°)."""
    coxa, femur, tibia, z_offset = 0.052, 0.082, 0.142, -0.015
    x, y, Z_offset = 0.05, 0.15, 0.105
    L = math.hypot(Z_offset, math.hypot(x, y) - coxa)
    notes = {
        "α": math.acos(Z_offset / L) + math.acos((tibia**2 - femur**2 - L**2) / (-2 * femur * L)),
        "β": math.acos((L**2 - tibia**2 - femur**2) / (-2 * tibia * femur)),
        "γ": math.atan(x / y),
    }
    assert [round(math.degrees(notes[k]), 3) for k in "αβγ"] == [114.123, 78.601, 18.435]
    foot = np.array([y, x, z_offset - Z_offset])  # the notes' y is the leg's outward axis
    lecture = hexapod_leg(foot, coxa, femur, tibia, z_offset, convention="lecture")
    angles = dict(zip(LECTURE.symbols, lecture.by_label("knee-up"), strict=True))
    for symbol, value in notes.items():
        assert angles[symbol] == pytest.approx(value, abs=1e-12), symbol
    joint = hexapod_leg(foot, coxa, femur, tibia, z_offset)
    assert lecture.labels == joint.labels
    np.testing.assert_allclose(LECTURE.to_joints(lecture.as_array()), joint.as_array(), atol=1e-15)
    assert lecture.by_label("knee-down")[2] > math.pi  # the other bend
    # Limits in lecture angles: a knee that may only close to 100° keeps no knee-up solution
    # bent further than that.
    limited = hexapod_leg(foot, coxa, femur, tibia, z_offset, convention="lecture",
                          limits=([-1, 0, math.radians(100)], [1, 3, math.pi]))  # fmt: skip
    assert all(math.radians(100) <= s[2] <= math.pi for s in limited)
    assert (notes["β"] >= math.radians(100)) == ("knee-up" in limited.labels)


def test_hexapod_lecture_family_members_are_in_lecture_angles():
    dims = (0.052, 0.082, 0.142, -0.015)
    under = hexapod_leg([0.0, 0.0, -0.1], *dims, convention="lecture")
    member = under[0].family.at(0.7)  # γ = 0.7
    assert member[0] == pytest.approx(0.7)
    np.testing.assert_allclose(member[1:], under[0][1:], atol=1e-12)


def test_stanford_type_rrp_takes_the_boom_offset():
    """000 "Example 2: Stanford-Type Arms (RRP)": p_W = (θ3 + a2)(c2 c1, c2 s1, s2) + d1 ẑ, so
    θ3 = √(p_Wx² + p_Wy² + (p_Wz − d1)²) − a2 and θ2 = atan2(p_Wz − d1, ±√(p_Wx² + p_Wy²)):
    two solutions. The notes give no numbers; d1 = 0.5, a2 = 0.25, p_W = (1, 1, 1)."""
    d1, a2, p_w = 0.5, 0.25, np.array([1.0, 1.0, 1.0])
    notes = []
    for sign in (1.0, -1.0):
        theta2 = math.atan2(p_w[2] - d1, sign * math.hypot(p_w[0], p_w[1]))
        theta1 = math.atan2(p_w[1] / math.cos(theta2), p_w[0] / math.cos(theta2))
        theta3 = math.sqrt(p_w[0] ** 2 + p_w[1] ** 2 + (p_w[2] - d1) ** 2) - a2
        notes.append((theta1, theta2, theta3))
    assert np.round(notes, 4).tolist() == [[0.7854, 0.3398, 1.25], [-2.3562, 2.8018, 1.25]]
    result = rrp_polar(p_w, d1, a2=a2)
    np.testing.assert_allclose(result.as_array(), notes, atol=1e-12)
    # The whole Stanford-type arm, its boom a2 long at θ3 = 0 and a ZYZ wrist ("similar to
    # PUMA"): its closed form returns the notes' θ3 for the wrist centre p_W, no offset by hand.
    rows = [
        redik.models.dh.DHRow(0.0, d1, math.pi / 2),
        redik.models.dh.DHRow(0.0, 0.0, math.pi / 2, math.pi / 2),
        redik.models.dh.DHRow(0.0, a2, 0.0, 0.0, "prismatic"),
        redik.models.dh.DHRow(0.0, 0.0, -math.pi / 2),
        redik.models.dh.DHRow(0.0, 0.0, math.pi / 2),
        redik.models.dh.DHRow(0.0, 0.0, 0.0),
    ]
    limits = [(-math.pi, math.pi), (-math.pi, math.pi), (-1.0, 2.0)] + [(-math.pi, math.pi)] * 3
    robot = redik.Robot.from_dh(rows, limits=limits, name="stanford_type")
    T = robot.fk(np.zeros(6))
    T[:3, 3] = p_w
    arm = {tuple(np.round(q[:3], 12)) for q in solver_for(robot)(T, limits=None)}
    assert len(arm) == 4  # the notes' two, and the boom pointing back (θ3 + a2 < 0)
    for row in notes:
        assert min(np.abs(np.subtract(row, q)).max() for q in arm) < 1e-9


@pytest.mark.parametrize("convention", ["ZYZ", "ZXZ"])
def test_spherical_wrist_takes_both_conventions_the_notes_name(convention):
    """002 "Inverse kinematics for robots with spherical wrist": ³R₆ is "Euler ZYZ or ZXZ";
    out of the singularity there are two solutions. The notes give no rotation; this one is
    chosen, and the noflip solution is redik.lie's Euler angles (middle angle in [0, π])."""
    R = so3_exp(np.array([0.3, -0.5, 0.9]))
    axes = {"X": np.array([1.0, 0.0, 0.0]), "Y": np.array([0.0, 1.0, 0.0]),
            "Z": np.array([0.0, 0.0, 1.0])}  # fmt: skip
    result = spherical_wrist(R, convention)
    assert result.labels == ("noflip", "flip")
    for q in result:
        rebuilt = np.eye(3)
        for letter, angle in zip(convention, q, strict=True):
            rebuilt = rebuilt @ so3_exp(axes[letter] * angle)
        np.testing.assert_allclose(rebuilt, R, atol=1e-12)
    np.testing.assert_allclose(
        result.by_label("noflip"), euler_angles(R, convention.lower()), atol=1e-12
    )


def test_unknown_convention_is_refused():
    with pytest.raises(redik.InvalidInput, match="convention must be one of"):
        hexapod_leg([0.15, 0.0, -0.12], 0.052, 0.082, 0.142, convention="servo")
    with pytest.raises(redik.InvalidInput, match="must end in 3 values"):
        LECTURE.to_joints([0.1, 0.2])
    # Neither text, complex numbers nor NaN become angles (no raw numpy error, no silent NaN).
    for bad, match in [(["a", "b", "c"], "real numbers"), ([1j, 0, 0], "real numbers"),
                       ([np.nan, 0.0, 0.0], "NaN")]:  # fmt: skip
        with pytest.raises(redik.InvalidInput, match=match):
            LECTURE.from_joints(bad)


def test_the_quiz_with_strict_input_is_refused_not_projected():
    robot = scene_robot("planar_3r")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(redik.InvalidPose):
            redik.solve_pose(robot, QUIZ_TARGET, method="newton", strict=True)


def test_ikinbody_stopping_rules_differ_where_the_rotation_error_is_large():
    """stop="twist" (‖v_b‖ ≤ ε_v, ‖ω_b‖ ≤ ε_ω) is stricter than the pose rule: with a loose
    orientation tolerance (1 rad) and a start 0.98 mm / 0.99 rad from the target, the pose
    rule accepts the start, while ‖v_b‖ = ‖(G(θ)/θ)⁻¹ Rᵀ(p_d − p)‖ ≈ 1.02 mm > ε_v."""
    robot = scene_robot("planar_3r")
    T_d = robot.fk(redik.solvers.analytic.planar_3r(1.5, 1.0, 0.5, 1, 1, 1)[0].q)
    offset = 0.98e-3 * np.array([math.cos(2.0), math.sin(2.0)])
    q0 = redik.solvers.analytic.planar_3r(1.5 + offset[0], 1.0 + offset[1], 1.49, 1, 1, 1)[0].q
    V_b = se3_log(inverse(robot.fk(q0)) @ T_d)
    assert np.linalg.norm(V_b[:3]) > 1e-3 > np.linalg.norm(robot.fk(q0)[:3, 3] - T_d[:3, 3])
    options = {"method": "newton", "pos_tol": 1e-3, "rot_tol": 1.0, "restarts": 0}
    pose = redik.solve_pose(robot, T_d, q0, stop="pose", **options)
    twist = redik.solve_pose(robot, T_d, q0, stop="twist", **options)
    assert pose.success and pose.iterations == 0
    assert twist.success and twist.iterations > 0
    V_end = se3_log(inverse(robot.fk(twist.q)) @ T_d)
    assert np.linalg.norm(V_end[:3]) <= 1e-3 and np.linalg.norm(V_end[3:]) <= 1.0
    with pytest.raises(redik.InvalidInput, match="stop must be"):
        redik.solve_pose(robot, T_d, q0, method="newton", stop="residual")


# --------------------------------------------------------------------------------------
# The worked examples of the notes, one test each (examples/course/<doc>_<name>.py)


def planar_2r_tip_and_jacobian(robot: redik.Robot):
    """x = f(θ), the (x, y) of the tip, and J = ∂f/∂θ (the world Jacobian's ṗ rows)."""
    return (lambda q: robot.fk(q)[:2, 3]), (lambda q: robot.jacobian(q, reference="world")[:2])


def as_printed(values, printed: list[str]) -> list[str]:
    """``values`` written with as many decimals as each printed number has."""
    return [
        f"{float(value):.{len(text.split('.')[1]) if '.' in text else 0}f}"
        for value, text in zip(values, printed, strict=True)
    ]


def test_000_case_study_solution_and_its_slip():
    """000 "Case Study": x_d = (0.2, 1.3), unit links; printed "θ1 = 0.5650 and θ2 = 0.7062".
    θ2 is 1.7062 (both iterate tables end there): the printed 0.7062 drops the leading 1."""
    q = redik.solvers.analytic.planar_2r(0.2, 1.3, 1.0, 1.0).by_label("elbow-down")
    assert as_printed(q, ["0.5650", "0.7062"]) == ["0.5650", "1.7062"]
    tip = scene_robot("planar_2r").fk([0.5650, 0.7062])[:2, 3]  # the printed pair
    assert np.linalg.norm(tip - [0.2, 1.3]) > 0.1


CASE_STUDY_NEWTON = [
    ("-0.33284", "2.6711"), ("0.80552", "2.1025"), ("0.46906", "1.9316"), ("0.53554", "1.7697"),
    ("0.55729", "1.7227"), ("0.56308", "1.7104"), ("0.56455", "1.7073"), ("0.56492", "1.7065"),
    ("0.56501", "1.7063"), ("0.56503", "1.7062"),
]  # fmt: skip
"""000 "Case Study", table "IK using Jacobian inverse": iterations 1–10 as printed."""


def test_000_case_study_newton_table():
    """θ⁰ = (0.25, 0.75), step 0.75, ten iterations: every printed digit."""
    tip, jacobian = planar_2r_tip_and_jacobian(scene_robot("planar_2r"))
    run = redik.solve_equations(
        tip, [0.2, 1.3], [0.25, 0.75], "newton", jacobian, step=0.75, tol=0, max_iterations=10
    )
    assert run.iterations == 10
    for k, printed in enumerate(CASE_STUDY_NEWTON, start=1):
        assert as_printed(run.history[k], list(printed)) == list(printed), k


def test_000_puma_type_arm_has_four_arm_and_eight_pose_solutions():
    """000 "Example 1: 6R PUMA-Type Arms": "in total, there exist four solutions" for
    (θ1, θ2, θ3), each with two ZYX wrists. The notes give no dimensions: a2 = 1, a3 = 0.8,
    d = 0.1 (p_W = p − d ŷ_b), the wrist axes along ẑ, ŷ, x̂ at zero."""
    a2, a3, d = 1.0, 0.8, 0.1
    points = np.array([[0, 0, 0], [0, 0, 0], [a2, 0, 0]] + [[a2 + a3, 0, 0]] * 3, float)
    axes = np.array([[0, 0, 1], [0, -1, 0], [0, -1, 0], [0, 0, 1], [0, 1, 0], [1, 0, 0]], float)
    M = np.eye(4)
    M[:3, 3] = (a2 + a3, d, 0.0)
    robot = redik.Robot.from_screws(np.vstack([axes.T, np.cross(-axes, points).T]), M)
    T = robot.fk([0.4, 0.6, -1.1, 0.3, -0.7, 1.2])
    solutions = solver_for(robot)(T)
    assert len(solutions) == 8
    assert len({tuple(np.round(q[:3], 9)) for q in solutions}) == 4
    for q in solutions:
        np.testing.assert_allclose(robot.fk(q), T, atol=1e-9)
        # Step 2: Rot(z, θ4) Rot(y, θ5) Rot(x, θ6) = R', the ZYX Euler angles of R'.
        R_wrist = so3_exp([0, 0, q[3]]) @ so3_exp([0, q[4], 0]) @ so3_exp([q[5], 0, 0])
        R_arm = so3_exp([0, 0, q[0]]) @ so3_exp([0, -(q[1] + q[2]), 0])
        np.testing.assert_allclose(R_arm @ R_wrist, T[:3, :3], atol=1e-9)


def test_000_orientation_metrics_are_the_notes_formulas():
    """000 "Position and Orientation Error…": the geodesic 2 arccos|q1·q2| ∈ [0, π], the
    chordal min(‖q1 − q2‖, ‖q1 + q2‖) ∈ [0, √2], ‖r1 − r2‖ of exponential coordinates and
    arccos((tr R_rel − 1)/2) = ‖log R_rel‖ (poses chosen: the notes give none)."""
    rng = np.random.default_rng(7)
    for _ in range(20):
        r1, r2 = rng.uniform(-1.5, 1.5, (2, 3))
        R1, R2 = so3_exp(r1), so3_exp(r2)
        q1, q2 = redik.lie.quat_from_matrix(R1), redik.lie.quat_from_matrix(R2)
        geodesic = redik.lie.quaternion_geodesic_distance(q1, q2)
        chordal = redik.lie.quaternion_chordal_distance(q1, q2)
        assert geodesic == pytest.approx(2 * math.acos(min(1.0, abs(q1 @ q2))), abs=1e-9)
        assert chordal == pytest.approx(min(np.linalg.norm(q1 - q2), np.linalg.norm(q1 + q2)))
        assert 0 <= geodesic <= math.pi and 0 <= chordal <= math.sqrt(2)
        assert redik.lie.exp_coordinate_distance(R1, R2) == pytest.approx(
            np.linalg.norm(redik.lie.so3_log(R1) - redik.lie.so3_log(R2)), abs=1e-12
        )
        trace = math.acos(np.clip((np.trace(R1.T @ R2) - 1) / 2, -1, 1))
        assert redik.lie.rotation_angle(R1, R2) == pytest.approx(trace, abs=1e-7)
        assert redik.lie.rotation_angle(R1, R2) == pytest.approx(geodesic, abs=1e-7)


def test_000_joint_limit_cost_is_the_notes_sum():
    """000 "Optimization-based Inverse Kinematics": φ(θ) = Σ ((θ_i − θ_i,mid)/(θ_i,max −
    θ_i,min))², on the PUMA's ranges (002's Table I) at a θ chosen here."""
    robot = scene_robot("puma560")
    theta = np.radians([30.0, -60.0, 120.0, 40.0, 50.0, 60.0])
    notes = np.sum(((theta - (robot.lower + robot.upper) / 2) / (robot.upper - robot.lower)) ** 2)
    scale, middle = redik.criteria.joint_limit_scaling(robot.lower, robot.upper)
    assert redik.criteria.joint_limit_potential(theta - middle, scale) == pytest.approx(notes)


def test_001_jacobian_of_the_notes_function():
    """001 "Jacobian: Approximation": F = (x1² + x2² − 1, 5x1² + 2x2² + 4) at x = (1, 2):
    "proper Jacobian" [[2, 4], [10, 8]], "approx. Jacobian (delta = 0.1)" [[2.1, 4.1],
    [10.5, 8.2]]."""

    def F(x):
        return np.array([x[0] ** 2 + x[1] ** 2 - 1.0, 5.0 * x[0] ** 2 + 2.0 * x[1] ** 2 + 4.0])

    x = np.array([1.0, 2.0])
    forward = finite_difference_jacobian(F, x, step=0.1, scheme="forward")
    central = finite_difference_jacobian(F, x, step=0.1, scheme="central")
    assert np.round(forward, 1).tolist() == [[2.1, 4.1], [10.5, 8.2]]
    assert np.round(central, 9).tolist() == [[2, 4], [10, 8]]


def test_002_planar_2r_workspaces():
    """002 "Workspace of planar 2R arm": l1 = l2 = ℓ: WS1 = {‖p‖ ≤ 2ℓ}, WS2 = {p = 0};
    l1 ≠ l2: WS1 = {|l1 − l2| ≤ ‖p‖ ≤ l1 + l2}, WS2 = ∅ (the orientations tried are those the
    planar arm can take)."""
    probes = np.array([[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [1.0, 0.0, 0.0], [1.5, 0.0, 0.0]])
    equal = redik.apps.workspace.reachability(scene_robot("planar_2r"), probes, seed=0)
    assert equal.score[0] == 1.0 and np.all(equal.score[1:] < 1.0)
    unequal_robot = redik.Robot.from_dh([(1.0, 0.0, 0.0), (0.5, 0.0, 0.0)])
    unequal = redik.apps.workspace.reachability(unequal_robot, probes, seed=0)
    assert np.all(unequal.score < 1.0)
    radii = np.linalg.norm(redik.apps.workspace.sample(unequal_robot, 500, seed=0).points, axis=1)
    assert 0.5 - 1e-9 <= radii.min() and radii.max() <= 1.5 + 1e-9


def test_002_planar_2r_multiplicity():
    """002 "Multiplicity of solutions": 2 regular solutions in WS1 (q2', q2'' of opposite
    signs), 1 on ∂WS1, ∞ in WS2 for l1 = l2 (q1 undefined: det = l1² + l2² + 2l1l2c2 = 0)."""
    inside = redik.solvers.analytic.planar_2r(1.2, 0.7, 1.0, 1.0)
    assert len(inside) == 2 and inside[0][1] == pytest.approx(-inside[1][1])
    assert len(redik.solvers.analytic.planar_2r(2.0, 0.0, 1.0, 1.0)) == 1
    origin = redik.solvers.analytic.planar_2r(0.0, 0.0, 1.0, 1.0)
    assert origin[0].family is not None and math.cos(origin[0][1]) == pytest.approx(-1.0)


@pytest.mark.parametrize(
    ("radius", "reachable", "every_phi", "singular"),
    [(0.5, True, True, 0), (1.0, True, True, 3), (2.0, True, False, 0), (3.0, True, False, 1),
     (3.001, False, False, 0)],
)  # fmt: skip
def test_002_planar_3r_workspace(radius, reachable, every_phi, singular):
    """002 "A planar 3R arm", l1 = l2 = l3 = ℓ = 1: WS1 = {‖p‖ ≤ 3ℓ}, WS2 = {‖p‖ ≤ ℓ};
    ‖p‖ = 3ℓ: "only 1 solution, singular"; ‖p‖ = ℓ: "∞¹ solutions, 3 of which singular";
    ‖p‖ < ℓ: "never singular". Singular: the 2 × 3 position Jacobian loses rank."""
    robot = scene_robot("planar_3r")
    family = redik.solvers.analytic.planar_3r_family(radius, 0.0, 1.0, 1.0, 1.0)
    assert family.reachable == reachable
    assert (family.phi_intervals == ((-math.pi, math.pi),)) == every_phi
    found = set()
    for start, end in family.phi_intervals:
        for phi in np.unique(np.r_[np.linspace(start, end, 91), 0.0, math.pi]):
            if not family.contains(phi):
                continue
            for q in family(phi):
                members = [q] if q.family is None else [
                    q.family.at(t) for t in np.linspace(-math.pi, math.pi, 91)]  # fmt: skip
                for member in members:
                    J = robot.jacobian(np.asarray(member), reference="world")[:2]
                    if np.linalg.svd(J, compute_uv=False)[-1] < 1e-9:
                        found.add(tuple(np.round(redik.lie.wrap_angle(member), 4)))
    assert len(found) == singular


def test_002_dexter_8r_has_two_degrees_of_redundancy():
    """002 "Dexter robot (8R arm)": m = 6, n = 8, "∞² inverse kinematic solutions
    (redundancy degree = n − m = 2)"."""
    robot = scene_robot("dexter8r")
    J = robot.jacobian(robot.home)
    assert J.shape == (6, 8) and np.linalg.matrix_rank(J) == 6
    motion = redik.explore_self_motion(
        robot, robot.fk(robot.home), seed=0, n_starts=8, max_samples=2000
    )
    assert motion.dimension == 2


def test_002_rrp_polar_closed_form():
    """002 "Numerical tests on RRP robot": "q* = (0.7854, 0.3398, 1.5)",
    "q** = (q1* − π, π − q2*, q3*) = (−2.3562, 2.8018, 1.5)" for p_d = (1, 1, 1), d1 = 0.5."""
    solutions = rrp_polar([1.0, 1.0, 1.0], 0.5)
    printed = {"front": ["0.7854", "0.3398", "1.5"], "back": ["-2.3562", "2.8018", "1.5"]}
    for label, numbers in printed.items():
        assert as_printed(solutions.by_label(label), numbers) == numbers


PUMA_600_TABLE = [(0, 0, -math.pi / 2), (17.000, 0, 0), (0.75, 4.937, math.pi / 2),
                  (0, 17.000, -math.pi / 2), (0, 0, math.pi / 2), (0, 0, 0)]  # fmt: skip
"""002 "6R example: Unimation PUMA 600", Table I as (a, d, α): a2 = 17.000 (printed "a1"),
a3 = 0.75, d3 = 4.937, d4 = 17.000 inches."""


def puma_600_printed_p(q, a2=17.000, a3=0.75, d3=4.937, d4=17.000):
    """The printed p_x, p_y, p_z of the PUMA 600."""
    c1, s1, c2, s2 = math.cos(q[0]), math.sin(q[0]), math.cos(q[1]), math.sin(q[1])
    c23, s23 = math.cos(q[1] + q[2]), math.sin(q[1] + q[2])
    reach = d4 * s23 + a3 * c23 + a2 * c2
    return np.array([c1 * reach - s1 * d3, s1 * reach + c1 * d3, -(-d4 * c23 + a3 * s23 + a2 * s2)])


def test_002_puma_600_table_and_its_eight_solutions():
    """Table I's direct kinematics is the printed p (and a = ⁰z₆: a_z = −S23 C4 S5 + C23 C5);
    "8 different inverse solutions that can be found in closed form". The printed
    "a1 = 17.000" is a2: with a1 = 17 (and a2 = 0) the printed p does not hold."""
    ranges = np.radians([(-160, 160), (-225, 45), (-45, 225), (-170, 170), (-135, 135),
                         (-170, 170)])  # fmt: skip
    robot = redik.Robot.from_dh(PUMA_600_TABLE, limits=ranges)
    as_printed_a1 = redik.Robot.from_dh([(17.000, 0, -math.pi / 2), (0, 0, 0), *PUMA_600_TABLE[2:]])
    rng = np.random.default_rng(3)
    for q in (robot.random_q(rng) for _ in range(10)):
        np.testing.assert_allclose(robot.fk(q)[:3, 3], puma_600_printed_p(q), atol=1e-9)
        a_z = -math.sin(q[1] + q[2]) * math.cos(q[3]) * math.sin(q[4]) + math.cos(
            q[1] + q[2]
        ) * math.cos(q[4])
        assert robot.fk(q)[2, 2] == pytest.approx(a_z, abs=1e-12)
        assert np.abs(as_printed_a1.fk(q)[:3, 3] - puma_600_printed_p(q)).max() > 1.0
    q = np.radians([30.0, -60.0, 120.0, 40.0, 50.0, 60.0])
    solutions = solver_for(robot)(robot.fk(q), limits=None)
    assert len(solutions) == 8
    scene = scene_robot("puma560")
    np.testing.assert_allclose([scene.lower, scene.upper], ranges.T, atol=1e-9)


@pytest.mark.parametrize(
    ("A", "b", "by_hand"),
    [(np.array([[1.0, 2.0]]), [3.0], ["0.6", "1.2"]), (np.array([[1.0], [2.0]]), [0.0, 3.0],
                                                        ["1.2"])],
)  # fmt: skip
def test_003_pseudoinverse_exercises(A, b, by_hand):
    """003: "Graphically find a 'good' solution to Ax = b, e.g., x = A†b": 1) A = [1 2],
    b = 3; 2) A = [1 2]ᵀ, b = [0 3]ᵀ. No printed answer; by hand (0.6, 1.2) and 6/5 = 1.2.
    One Newton step from 0 is Δθ* = J†(x_d − f(θ⁰)) = A†b."""
    step = redik.solve_equations(
        lambda x: A @ x, b, np.zeros(A.shape[1]), "newton", lambda x: A, tol=0, max_iterations=1
    )
    assert as_printed(step.q, by_hand) == by_hand


def test_004_quiz_question_2_with_the_quizs_screws():
    """004 "Python Solution for Course Quiz", question 2, with Blist, M and T as the code
    writes them (MR's (ω, v) screws): the code prints θ to 2 decimals, [0.93, 0.59, 0.68]."""
    B_list = np.array([[0, 0, 1, 0, 3, 0], [0, 0, 1, 0, 2, 0], [0, 0, 1, 0, 1, 0]]).T
    M = np.array([[1, 0, 0, 3], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    robot = redik.Robot.from_screws(B_list, M, frame="body")
    with pytest.warns(NearRotationWarning):
        run = redik.solve_pose(
            robot, QUIZ_TARGET, [math.pi / 4] * 3, method="newton", stop="twist",
            rot_tol=0.001, pos_tol=0.0001, max_iterations=20, restarts=0, respect_limits=False,
        )  # fmt: skip
    assert run.success
    assert as_printed(run.q, ["0.93", "0.59", "0.68"]) == ["0.93", "0.59", "0.68"]


CASE_STUDY_TRANSPOSE = {
    1: ("1.8362", "1.3412"), 2: ("0.4667", "1.1025"), 3: ("1.1215", "1.6233"),
    4: ("0.45264", "1.415"), 5: ("0.83519", "1.7273"), 26: ("0.56522", "1.7063"),
    27: ("0.56492", "1.7061"), 28: ("0.56514", "1.7063"), 29: ("0.56498", "1.7062"),
    30: ("0.5650", "1.7062"),
}  # fmt: skip
"""000 "Case Study", table "IK using Jacobian transpose": the printed rows, by their label."""


def test_000_case_study_transpose_table_and_its_slips():
    """Step 0.75. The table starts from (0.30, 0.40), not from the stated initial guess
    (0.25, 0.75); rows 26–29 are iterations 27–30 and row 30 is iteration 30 again."""
    tip, jacobian = planar_2r_tip_and_jacobian(scene_robot("planar_2r"))

    def history(q0):
        return redik.solve_equations(
            tip, [0.2, 1.3], q0, "transpose", jacobian, step=0.75, tol=0, max_iterations=31
        ).history

    stated, used = history([0.25, 0.75]), history([0.30, 0.40])
    row_1 = list(CASE_STUDY_TRANSPOSE[1])
    assert as_printed(stated[1], row_1) != row_1
    for k in range(1, 6):
        assert as_printed(used[k], list(CASE_STUDY_TRANSPOSE[k])) == list(CASE_STUDY_TRANSPOSE[k])
    for label in range(26, 30):
        printed = list(CASE_STUDY_TRANSPOSE[label])
        assert as_printed(used[label + 1], printed) == printed, label
        assert as_printed(used[label], printed) != printed, label
    row_30 = list(CASE_STUDY_TRANSPOSE[30])
    assert as_printed(used[30], row_30) == row_30 and as_printed(used[31], row_30) != row_30


def planar_3r_pose_and_jacobian(robot: redik.Robot):
    """x = f(θ) = (x, y, φ), the planar pose of the tip, and ∂x/∂θ (rows ẋ, ẏ, ω_z)."""

    def pose(q):
        T = robot.fk(q)
        return np.array([T[0, 3], T[1, 3], math.atan2(T[1, 0], T[0, 0])])

    return pose, (lambda q: robot.jacobian(q, reference="world")[[0, 1, 5]])


def test_000_minimum_coordinate_algorithm_with_separate_tolerances():
    """000 "Algorithm for Minimum-Coordinate Representation": while e_p > ε_p or e_R > ε_R:
    θ ← θ + λJ⁺e, and its listing (λ = 1, max_iterations = 20, ‖e‖ > ε). No numbers in the
    notes: the planar 3R pose (x, y, φ), ε_p = 1e-6, ε_R = 1e-4 and the target are chosen."""
    pose, jacobian = planar_3r_pose_and_jacobian(scene_robot("planar_3r"))
    x_d, theta = pose([0.3, 0.9, -0.4]), np.array([0.1, 0.5, 0.1])
    k, e = 0, x_d - pose(theta)
    while np.linalg.norm(e) > 1e-6 and k < 20:  # the listing, as written
        theta = theta + np.linalg.pinv(jacobian(theta)) @ e
        k, e = k + 1, x_d - pose(theta)
    options = {"step": 1.0, "max_iterations": 20}
    listing = redik.solve_equations(pose, x_d, [0.1, 0.5, 0.1], "newton", jacobian, tol=1e-6,
                                    **options)  # fmt: skip
    assert listing.iterations == k and np.allclose(listing.q, theta, atol=1e-12)
    split = redik.solve_equations(pose, x_d, [0.1, 0.5, 0.1], "newton", jacobian,
                                  tol=(1e-6, 1e-4), **options)  # fmt: skip
    e = x_d - pose(split.q)
    assert split.success and np.linalg.norm(e[:2]) <= 1e-6 and abs(e[2]) <= 1e-4
    assert split.position_error == pytest.approx(np.linalg.norm(e[:2]))
    assert split.rotation_error == pytest.approx(abs(e[2]))


def test_000_stopping_rules_each_alone():
    """000 and 002's stopping rules on the Case Study (λ = 0.75), each alone (tol=None):
    the relative change ‖f(x^{k+1}) − f(x^k)‖/‖f(x^k)‖ ≤ ε and the increment
    ‖θ^{k+1} − θ^k‖ < ε_q stop the run, converged, at the iteration where the notes' rule
    first holds. As written for the root's function e = x_d − f(θ), the ratio tends to λ:
    it cannot stop a converging run (the notes' slip)."""
    tip, jacobian = planar_2r_tip_and_jacobian(scene_robot("planar_2r"))
    x_d, theta0, options = [0.2, 1.3], [0.25, 0.75], {"step": 0.75, "max_iterations": 30}
    table = redik.solve_equations(tip, x_d, theta0, "newton", jacobian, tol=0, **options).history
    x = np.array([tip(q) for q in table])
    change = np.linalg.norm(np.diff(x, axis=0), axis=1) / np.linalg.norm(x[:-1], axis=1)
    increment = np.linalg.norm(np.diff(table, axis=0), axis=1)
    e = x_d - x
    as_written = np.linalg.norm(np.diff(e, axis=0), axis=1) / np.linalg.norm(e[:-1], axis=1)
    assert as_written[10:20] == pytest.approx(0.75, abs=1e-3)
    for rule, fired in [({"rel_tol": 1e-6}, change <= 1e-6), ({"q_tol": 1e-6}, increment < 1e-6)]:
        run = redik.solve_equations(tip, x_d, theta0, "newton", jacobian, tol=None, **rule,
                                    **options)  # fmt: skip
        assert run.status == "converged" and run.iterations == 1 + int(np.argmax(fired)), rule
        np.testing.assert_array_equal(run.q, table[run.iterations])


def test_002_puma560_solve_all_finds_the_eight():
    """002 "Wrist position and E-E pose inverse solutions" (PUMA 560): "4 inverse solutions
    … for the position of the wrist center", "8 inverse solutions considering the complete
    E-E pose"; solve_all without the limits finds the same 8, angles modulo 2π."""
    robot = scene_robot("puma560")
    T = robot.fk(np.radians([30.0, -60.0, 120.0, 40.0, 50.0, 60.0]))
    closed = redik.solve_all(robot, T, method="analytic", respect_limits=False)
    assert len({tuple(np.round(redik.lie.wrap_angle(r.q[:3]), 6)) for r in closed}) == 4
    assert len(closed) == 8
    searched = redik.solve_all(robot, T, n_starts=200, seed=0, respect_limits=False)
    assert len(searched) == 8
    wrapped = {tuple(np.round(redik.lie.wrap_angle(r.q), 4)) for r in searched}
    assert wrapped == {tuple(np.round(redik.lie.wrap_angle(r.q), 4)) for r in closed}


def test_002_case_study_gain_rotates_the_error_out_of_the_kernel():
    """002 "A case study" (2R, l1 = l2 = 1, r_d = (1, 1)): J_r = [[−(s1 + s12), −s12],
    [c1 + c12, c12]], det J_r = s2; "(q1, q2)' = (0, π/2)", "(q1, q2)'' = (π/2, −π/2)"; at the
    saddle (π/4, 0) "e ∈ Ker(J_rᵀ)" and the gradient is stuck; "K can be used also to
    'escape' … by rotating the error e out of the kernel of J_rᵀ" (K chosen: Rot(45°))."""
    tip, jacobian = planar_2r_tip_and_jacobian(scene_robot("planar_2r"))
    for q in np.random.default_rng(0).uniform(-math.pi, math.pi, (5, 2)):
        s1, c1, s12, c12 = math.sin(q[0]), math.cos(q[0]), math.sin(q.sum()), math.cos(q.sum())
        np.testing.assert_allclose(jacobian(q), [[-(s1 + s12), -s12], [c1 + c12, c12]], atol=1e-12)
        assert np.linalg.det(jacobian(q)) == pytest.approx(math.sin(q[1]), abs=1e-12)
    solutions = redik.solvers.analytic.planar_2r(1.0, 1.0, 1.0, 1.0)
    assert {tuple(np.round(q, 9)) for q in solutions} == {
        (0.0, round(math.pi / 2, 9)), (round(math.pi / 2, 9), round(-math.pi / 2, 9))}  # fmt: skip
    saddle, r_d = [math.pi / 4, 0.0], [1.0, 1.0]
    assert np.linalg.norm(jacobian(saddle).T @ (r_d - tip(saddle))) < 1e-12
    options = {"step": 0.5, "tol": 1e-6, "max_iterations": 100}
    stuck = redik.solve_equations(tip, r_d, saddle, "transpose", jacobian, **options)
    assert not stuck.success and np.allclose(stuck.q, saddle)
    K = np.array([[1.0, -1.0], [1.0, 1.0]]) / math.sqrt(2.0)
    escaped = redik.solve_equations(tip, r_d, saddle, "transpose", jacobian, gain=K, **options)
    assert escaped.success
    assert min(np.abs(redik.lie.wrap_angle(escaped.q - s)).max() for s in solutions) < 1e-5


def rrp_position_and_jacobian():
    """002's RRP tests: f_r(q) = p of the bundled rrp_polar (d1 = 0.5), J_r = ∂f_r/∂q."""
    robot = scene_robot("rrp_polar")
    return (lambda q: robot.fk(q)[:3, 3]), (lambda q: robot.jacobian(q, reference="world")[:3])


RRP_SETTINGS = {"tol": 1e-5, "q_tol": 1e-6, "max_iterations": 15}
"""002 "Numerical tests on RRP robot": "ε = 10⁻⁵ (max Cartesian error), ε_q = 10⁻⁶ (min joint
increment)", "k_max = 15 (max iterations)"."""

RRP_Q_STAR = ["0.7854", "0.3398", "1.5"]
"""002: "q* = (0.7854, 0.3398, 1.5)"."""


def test_002_rrp_numerical_test_1():
    """q⁰ = (0, 0, 1): "Gradient: α = 1 not converging", "α = 0.7 converges in 11
    iterations" with the final error "0.57·10⁻⁵", "Newton converges in 5 iterations", "both
    to solution q*"."""
    position, jacobian = rrp_position_and_jacobian()

    def run(method, **options):
        return redik.solve_equations(position, [1.0, 1.0, 1.0], [0.0, 0.0, 1.0], method,
                                     jacobian, **RRP_SETTINGS, **options)  # fmt: skip

    assert not run("transpose", step=1.0).success
    gradient = run("transpose", step=0.7)
    newton = run("newton", singular_tol=1e-4, singular_test="det")
    assert gradient.success and gradient.iterations == 11
    assert f"{gradient.error * 1e5:.2f}" == "0.57"
    assert newton.success and newton.iterations == 5
    for result in (gradient, newton):
        assert as_printed(result.q, RRP_Q_STAR) == RRP_Q_STAR


def test_002_rrp_numerical_test_2():
    """q⁰ = (−π/4, π/2, 1), "singular start, since c2 = 0": Newton "with check of singularity
    (|det J_r| ≤ 10⁻⁴): blocked at start", "without check: it diverges"; the gradient "starts
    toward solution, but slowly stops (in singularity): when … e ∈ Ker(J_rᵀ)"."""
    position, jacobian = rrp_position_and_jacobian()
    q0, p_d = [-math.pi / 4, math.pi / 2, 1.0], np.array([1.0, 1.0, 1.0])

    def run(method, **options):
        return redik.solve_equations(position, p_d, q0, method, jacobian, **RRP_SETTINGS,
                                     **options)  # fmt: skip

    checked = run("newton", singular_tol=1e-4, singular_test="det")
    assert checked.status == "singular" and checked.iterations == 0
    assert run("newton").status == "diverged"
    gradient = run("transpose", step=0.7)
    e = p_d - position(gradient.q)
    assert not gradient.success and gradient.error < gradient.error_history[0]
    assert np.linalg.norm(jacobian(gradient.q).T @ e) < 1e-5 < np.linalg.norm(e)


def test_002_rrp_numerical_test_3_and_its_slip():
    """q⁰ = (0, π/2, 0), "double singular": the gradient with α = 0.7 "slowly converges in 19
    iterations to the solution q*"; "Newton is either blocked at start or (w/o check)
    explodes". The 19 iterations exceed the tests' own k_max = 15: held to it, the run stops
    at 15 with the error above ε."""
    position, jacobian = rrp_position_and_jacobian()
    q0 = [0.0, math.pi / 2, 0.0]

    def run(method, max_iterations=15, **options):
        return redik.solve_equations(position, [1.0, 1.0, 1.0], q0, method, jacobian,
                                     tol=1e-5, q_tol=1e-6, max_iterations=max_iterations,
                                     **options)  # fmt: skip

    gradient = run("transpose", step=0.7, max_iterations=19)
    assert gradient.success and gradient.iterations == 19
    assert as_printed(gradient.q, RRP_Q_STAR) == RRP_Q_STAR
    held = run("transpose", step=0.7)
    assert held.status == "max_iterations" and held.iterations == 15 and held.error > 1e-5
    assert run("newton", singular_tol=1e-4, singular_test="det").status == "singular"
    assert run("newton").status == "diverged"


def test_the_course_readme_indexes_every_example():
    """examples/course/README.md lists each script once, and each script's docstring names
    the document of the notes it reproduces (``Notes 000`` … ``Notes 004``)."""
    folder = Path(__file__).resolve().parent.parent / "examples" / "course"
    scripts = sorted(path.name for path in folder.glob("0*.py"))
    readme = (folder / "README.md").read_text(encoding="utf-8")
    listed = sorted(set(re.findall(r"^\| `(0\d\d_\w+\.py)` \|", readme, flags=re.MULTILINE)))
    assert listed == scripts
    for name in scripts:
        docstring = ast.get_docstring(ast.parse((folder / name).read_text(encoding="utf-8")))
        assert docstring is not None and docstring.startswith(f"Notes {name[:3]} "), name
