"""Notes 002 (Robotics 1, Inverse kinematics), "A planar 3R arm": workspace and number/type of
inverse solutions for the tip position, l1 = l2 = l3 = ℓ (the bundled ``planar_3r``, ℓ = 1).

Stated: WS1 = {‖p‖ ≤ 3ℓ}, WS2 = {‖p‖ ≤ ℓ} (every planar orientation φ); in WS1 ∞¹ regular
solutions; at ‖p‖ = 3ℓ only 1 solution, singular; at ‖p‖ = ℓ ∞¹ solutions, 3 of them singular;
at ‖p‖ < ℓ ∞¹ solutions, never singular. ``planar_3r_family`` gives the orientations φ reachable
at p and, for each, the solutions; singular = the 2 × 3 position Jacobian loses rank. The
solutions are sampled along φ (and along θ1 where it is free, at the origin of the last two
links), so the singular ones are found among samples that include φ = 0 and φ = π.

Run: python examples/course/002_planar_3r_workspace.py
"""

import math

import numpy as np

import redik
from redik.lie import wrap_angle
from redik.solvers.analytic import planar_3r_family

robot = redik.load("planar_3r")
ELL = 1.0


def sigma_min(q):
    return np.linalg.svd(robot.jacobian(q, reference="world")[:2], compute_uv=False)[-1]


def sampled_solutions(r):
    """Solutions of the tip at (r, 0), sampled along φ (and θ1 where it is free)."""
    family = planar_3r_family(r, 0.0, ELL, ELL, ELL)
    qs = []
    for start, end in family.phi_intervals:
        for phi in np.unique(np.r_[np.linspace(start, end, 181), 0.0, math.pi]):
            if family.contains(phi):
                for q in family(phi):
                    members = (
                        [q]
                        if q.family is None
                        else [q.family.at(t) for t in np.linspace(-math.pi, math.pi, 181)]
                    )
                    qs += [np.asarray(m) for m in members]  # fmt: skip
    return family, qs


print("002 planar 3R, ℓ = 1: notes | redik")
STATED = {0.5: "∞¹, never singular", 1.0: "∞¹, 3 singular", 2.0: "∞¹ regular",
          3.0: "1, singular", 3.001: "none (outside WS1)"}  # fmt: skip
for r, stated in STATED.items():
    family, qs = sampled_solutions(r)
    distinct = {tuple(np.round(wrap_angle(q), 4).tolist()) for q in qs}
    singular = sorted(
        {tuple(np.round(wrap_angle(q), 4).tolist()) for q in qs if sigma_min(q) < 1e-9}
    )
    every_phi = family.phi_intervals == ((-math.pi, math.pi),)
    count = "none" if not distinct else ("1" if len(distinct) == 1 else "∞¹")
    print(f"  ‖p‖ = {r:5.3f}: {stated:20s} | in WS1 {family.reachable!s:5s} in WS2 "
          f"{every_phi!s:5s} solutions {count:4s} singular {len(singular)} {singular}")  # fmt: skip
