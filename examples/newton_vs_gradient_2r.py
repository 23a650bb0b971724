"""Newton–Raphson versus gradient descent on a planar 2R arm: the classic convergence plot.

Run: python examples/newton_vs_gradient_2r.py [out.png]
"""

import sys

import numpy as np

from redik.apps import plot
from redik.solvers.iterative import solve_equations

L1, L2 = 1.0, 0.8


def tip(q: np.ndarray) -> np.ndarray:
    """Tip position (x, y) of the 2R arm."""
    return np.array(
        [L1 * np.cos(q[0]) + L2 * np.cos(q[0] + q[1]), L1 * np.sin(q[0]) + L2 * np.sin(q[0] + q[1])]
    )


x_d = tip(np.array([0.4, 1.1]))
q0 = np.array([0.2, 1.6])
results = [
    solve_equations(tip, x_d, q0, "newton", tol=1e-10),
    solve_equations(tip, x_d, q0, "transpose", step="armijo", tol=1e-10, max_iterations=500),
    solve_equations(tip, x_d, q0, "transpose", step=0.3, tol=1e-10, max_iterations=500),
]
labels = ["Newton (J⁻¹)", "gradient, Armijo", "gradient, α = 0.3"]
for label, result in zip(labels, results, strict=True):
    print(f"{label:18s} {result.summary()}  q = {np.round(result.q, 6)}")
path = sys.argv[1] if len(sys.argv) > 1 else "newton_vs_gradient_2r.png"
plot.convergence(results, labels, path=path)
print(f"saved {path}")
