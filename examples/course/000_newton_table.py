"""Notes 000 (Ch7 Inverse Kinematics), "Case Study", table "IK using Jacobian inverse".

The unit-link 2R arm, x_d = (0.2, 1.3), θ⁰ = (0.25, 0.75), step λ = 0.75:
θ^{k+1} = θ^k + λ J⁻¹(θ^k)(x_d − f(θ^k)), ten iterations printed. ``tol=0`` runs every
iteration of the budget, so ``result.history[k]`` is the table's row k (row 0 is θ⁰).

Run: python examples/course/000_newton_table.py
"""

from _table import table

import redik

NOTES = [  # iteration, θ1, θ2 as printed
    ("1", "-0.33284", "2.6711"), ("2", "0.80552", "2.1025"), ("3", "0.46906", "1.9316"),
    ("4", "0.53554", "1.7697"), ("5", "0.55729", "1.7227"), ("6", "0.56308", "1.7104"),
    ("7", "0.56455", "1.7073"), ("8", "0.56492", "1.7065"), ("9", "0.56501", "1.7063"),
    ("10", "0.56503", "1.7062"),
]  # fmt: skip

arm = redik.load("planar_2r")


def tip(q):
    """x = f(θ): the (x, y) of the tip."""
    return arm.fk(q)[:2, 3]


def jacobian(q):
    """J(θ) = ∂(x, y)/∂θ: the first two rows of the world Jacobian (ṗ)."""
    return arm.jacobian(q, reference="world")[:2]


run = redik.solve_equations(
    tip, [0.2, 1.3], [0.25, 0.75], "newton", jacobian, step=0.75, tol=0, max_iterations=10
)
table(
    "000 Case Study — IK using Jacobian inverse (λ = 0.75)",
    ["θ1", "θ2"],
    [(k, (t1, t2), run.history[int(k)]) for k, t1, t2 in NOTES],
)
print(run.summary())
