"""Notes 000 (Ch7 Inverse Kinematics), "Algorithm for Minimum-Coordinate Representation" and its
"Example of the Algorithm in Python".

The algorithm: e = x_d − f(θ^k); while e_p > ε_p or e_R > ε_R: θ^{k+1} = θ^k + λ J⁺(θ^k) e.
The listing: λ = 1, max_iterations = 20, one threshold ε on ‖e‖. The notes give no numbers:
the bundled ``planar_3r`` (unit links) with the planar pose x = (x, y, φ), the target, θ⁰ and
ε = 1e-6, ε_p = 1e-6 m, ε_R = 1e-4 rad are chosen here. redik's ``tol=(ε_p, ε_R)`` tests the
position part (x, y) and the orientation part φ of a length-3 residual separately.

Run: python examples/course/000_minimum_coordinate_algorithm.py
"""

import math

import numpy as np
from _table import attempt

import redik

arm = redik.load("planar_3r")


def pose(q):
    """x = f(θ) = (x, y, φ), the planar pose of the tip."""
    T = arm.fk(q)
    return np.array([T[0, 3], T[1, 3], math.atan2(T[1, 0], T[0, 0])])


def jacobian(q):
    """∂(x, y, φ)/∂θ: rows ẋ, ẏ and ω_z of the world Jacobian."""
    return arm.jacobian(q, reference="world")[[0, 1, 5]]


x_d, theta0 = pose([0.3, 0.9, -0.4]), np.array([0.1, 0.5, 0.1])

# The listing, as written.
theta, k, epsilon = theta0.copy(), 0, 1e-6
e = x_d - pose(theta)
while np.linalg.norm(e) > epsilon and k < 20:
    theta = theta + 1.0 * np.linalg.pinv(jacobian(theta)) @ e
    k += 1
    e = x_d - pose(theta)
listing = redik.solve_equations(
    pose, x_d, theta0, "newton", jacobian, step=1.0, tol=epsilon, max_iterations=20
)
print("000 minimum-coordinate algorithm, planar 3R, x = (x, y, φ)")
print(f"  the listing:  {k} iterations, θ = {np.round(theta, 6)}")
print(f"  redik (tol=ε): {listing.iterations} iterations, θ = {np.round(listing.q, 6)}, "
      f"difference {np.abs(listing.q - theta).max():.1e}")  # fmt: skip
attempt("the algorithm, e_p ≤ ε_p = 1e-6 and e_R ≤ ε_R = 1e-4", lambda: redik.solve_equations(
    pose, x_d, theta0, "newton", jacobian, step=1.0, tol=(1e-6, 1e-4), max_iterations=20
))  # fmt: skip
