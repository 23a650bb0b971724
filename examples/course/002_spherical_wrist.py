"""Notes 002 (Robotics 1, Inverse kinematics), "Inverse kinematics for robots with spherical
wrist": R = ⁰R₃(q1, q2, q3) ³R₆(q4, q5, q6), with ³R₆ an "Euler ZYZ or ZXZ rotation matrix" →
q4, q5, q6, two solutions out of the wrist singularity.

The notes give no numbers: the wrist rotation is chosen here, and both named conventions are
solved by ``spherical_wrist``; each solution's Euler product is rebuilt to show it is R.

Run: python examples/course/002_spherical_wrist.py
"""

import numpy as np

from redik.lie import so3_exp
from redik.solvers.analytic import spherical_wrist

AXIS = {"X": np.array([1.0, 0, 0]), "Y": np.array([0, 1.0, 0]), "Z": np.array([0, 0, 1.0])}


def euler_matrix(convention, angles):
    """R = Rot(a, q4) Rot(b, q5) Rot(c, q6) for the convention "abc"."""
    R = np.eye(3)
    for letter, angle in zip(convention, angles, strict=True):
        R = R @ so3_exp(AXIS[letter] * angle)
    return R


R = so3_exp(np.array([0.3, -0.5, 0.9]))
for convention in ("ZYZ", "ZXZ"):
    solutions = spherical_wrist(R, convention)
    print(f"002 spherical wrist, Euler {convention}: {len(solutions)} solutions (the notes: two)")
    for q in solutions:
        error = np.abs(euler_matrix(convention, q) - R).max()
        print(f"  {q.label:7s} (q4, q5, q6) = {np.round(q, 4)}   |Euler(q) − R| = {error:.1e}")
