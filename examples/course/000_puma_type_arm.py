"""Notes 000 (Ch7 Inverse Kinematics), "Example 1: 6R PUMA-Type Arms": four arm solutions
(θ1, θ2, θ3) of the wrist centre, then the ZYX wrist — eight solutions in all.

The notes' arm: p_W = (c1 r, s1 r, a2 s2 + a3 s23) with r = a2 c2 + a3 c23, the wrist axes
along (ẑ_s, ŷ_s, x̂_s) at the zero configuration (ZYX Euler angles) and the tool at
p = p_W + d ŷ_b. The notes give formulas and no numbers: a2 = 1, a3 = 0.8, d = 0.1 and the
target are chosen here. Their recipe (c3, s3 = ±√(1 − c3²), c2 and s2 with ±r, θ1,I and θ1,II,
then the ZYX angles of R') is evaluated below and compared with redik's closed form of the
same arm built from its screws (``redik.Robot.from_screws``, which takes Modern Robotics'
(ω, v) columns; ``redik.lie`` twists are (v, ω)).

Run: python examples/course/000_puma_type_arm.py
"""

import math

import numpy as np

import redik
from redik.lie import euler_angles, inverse, se3_exp, wrap_angle
from redik.solvers.analytic import solver_for

A2, A3, D = 1.0, 0.8, 0.1
L = A2 + A3
POINTS = np.array([[0, 0, 0], [0, 0, 0], [A2, 0, 0], [L, 0, 0], [L, 0, 0], [L, 0, 0]], float)
AXES = np.array([[0, 0, 1], [0, -1, 0], [0, -1, 0], [0, 0, 1], [0, 1, 0], [1, 0, 0]], float)
S = np.vstack([AXES.T, np.cross(-AXES, POINTS).T])  # columns S_i = (ω_i, v_i), MR's order
M = np.eye(4)
M[:3, 3] = (L, D, 0.0)
robot = redik.Robot.from_screws(S, M)


def exp_screw(i, theta):
    """e^{[S_i]θ}; redik.lie's twists are (v, ω)."""
    return se3_exp(np.r_[S[3:, i], S[:3, i]] * theta)


def notes_solutions(T):
    """The notes' recipe: the four (θ1, θ2, θ3), each with its two ZYX wrists."""
    p_w = T[:3, 3] - D * T[:3, 1]  # p_W = p − d ŷ_b
    c3 = (p_w @ p_w - A2**2 - A3**2) / (2 * A2 * A3)
    r, den = math.hypot(p_w[0], p_w[1]), p_w @ p_w
    arms = []
    for s3 in (math.sqrt(1 - c3**2), -math.sqrt(1 - c3**2)):  # θ3,I and θ3,II
        for sign in (1.0, -1.0):  # +r → θ1,I ; −r → θ1,II
            c2 = (sign * r * (A2 + A3 * c3) + p_w[2] * A3 * s3) / den
            s2 = (p_w[2] * (A2 + A3 * c3) - sign * r * A3 * s3) / den
            theta1 = math.atan2(sign * p_w[1], sign * p_w[0])
            arms.append((theta1, math.atan2(s2, c2), math.atan2(s3, c3)))
    solutions = []
    for t1, t2, t3 in arms:
        R = (exp_screw(2, -t3) @ exp_screw(1, -t2) @ exp_screw(0, -t1) @ T @ inverse(M))[:3, :3]
        t4, t5, t6 = euler_angles(R, "zyx")  # Rot(z, θ4) Rot(y, θ5) Rot(x, θ6) = R'
        solutions += [
            (t1, t2, t3, t4, t5, t6),
            (t1, t2, t3, t4 + math.pi, math.pi - t5, t6 + math.pi),
        ]
    return arms, np.array(solutions)


def key(q):
    return tuple(np.round(wrap_angle(np.asarray(q)), 6).tolist())


T = robot.fk([0.4, 0.6, -1.1, 0.3, -0.7, 1.2])
arms, notes = notes_solutions(T)
ours = solver_for(robot)(T).as_array()
print("000 Example 1, PUMA-type arm (a2 = 1, a3 = 0.8, d = 0.1): the notes' 4 arm solutions")
for arm in arms:
    print(f"  (θ1, θ2, θ3) = {np.round(arm, 4)}")
shared = {key(q) for q in notes} & {key(q) for q in ours}
print(f"  distinct arm solutions by the notes' recipe: {len({key(a) for a in arms})} (notes: four)")
print(
    f"  pose solutions: the notes' recipe {len(notes)}, redik {len(ours)}, the same: {len(shared)}"
)
worst = max(float(np.abs(robot.fk(q) - T).max()) for q in notes)
print(f"  largest |FK(q) − T| over the notes' eight: {worst:.1e}")
