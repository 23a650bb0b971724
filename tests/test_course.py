"""Every worked example of the course runs as written, through the public API (issue 15).

Each test reproduces the course's numbers as the course prints them (its rounding), from its
own inputs, so a student typing the example gets the book's answer:

- Modern Robotics (Lynch & Park 2017) Example 6.1 (§6.2.2): IKinBody on the planar 2R arm,
  the book's iterate table;
- the Chapter 6 quiz: Newton–Raphson on ``f(x, y) = (x² − 9, y² − 4)`` from (1, 1), two
  iterations, and IKinBody on the planar 3R arm to a target typed with 3 decimals;
- the forward-difference Jacobian with ``δ = 0.1`` of the course notes;
- the RRP polar arm's example ``p = (1, 1, 1)``, ``d1 = 0.5`` in its bundled scene;
- the hexapod leg's servo angles as the notes define them (001), and the Stanford arm's boom
  elevation as the lecture measures it.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import redik
from redik.core.exceptions import NearRotationWarning
from redik.lie import euler_angles, inverse, se3_log, so3_exp
from redik.models.scene_library import get_scene
from redik.solvers.analytic import hexapod_leg, rrp_polar, solver_for, spherical_wrist
from redik.solvers.analytic.hexapod import LECTURE
from redik.solvers.iterative import finite_difference_jacobian, newton_raphson


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
    result = newton_raphson(lambda x: np.array([x[0] ** 2 - 9.0, x[1] ** 2 - 4.0]),
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
    result = newton_raphson(course_fd_function, x_d, x, fd_step=0.1, fd_scheme="forward", tol=0,
                            max_iterations=1)  # fmt: skip
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
