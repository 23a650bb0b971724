"""Notes 000 (Ch7 Inverse Kinematics), "Case Study", table "IK using Jacobian transpose".

Same arm and target as the Newton table (unit links, x_d = (0.2, 1.3), step 0.75):
θ^{k+1} = θ^k + λ J_aᵀ(θ^k)(x_d − f(θ^k)), printed rows 1–5 and 26–30. ``tol=0`` runs every
iteration of the budget, so ``result.history[k]`` is iteration k.

Slips of the notes, shown rather than corrected:
- the table does not start from the stated initial guess (0.25, 0.75): its first row is one
  step from (0.30, 0.40) (from (0.25, 0.75) the first step lands at (1.5582, 1.6618));
- its rows 26–29 are iterations 27–30, and its row 30 (4 decimals) is iteration 30 again
  (iteration 31 reads 0.5651).

Run: python examples/course/000_transpose_table.py
"""

from _table import attempt, table

import redik

ROWS_1_TO_5 = [("1", "1.8362", "1.3412"), ("2", "0.4667", "1.1025"), ("3", "1.1215", "1.6233"),
               ("4", "0.45264", "1.415"), ("5", "0.83519", "1.7273")]  # fmt: skip
ROWS_26_TO_30 = [("26", "0.56522", "1.7063"), ("27", "0.56492", "1.7061"),
                 ("28", "0.56514", "1.7063"), ("29", "0.56498", "1.7062"),
                 ("30", "0.5650", "1.7062")]  # fmt: skip

arm = redik.load("planar_2r")


def tip(q):
    """x = f(θ): the (x, y) of the tip."""
    return arm.fk(q)[:2, 3]


def jacobian(q):
    """J_a(θ) = ∂(x, y)/∂θ."""
    return arm.jacobian(q, reference="world")[:2]


def transpose_run(name, q0):
    return attempt(name, lambda: redik.solve_equations(
        tip, [0.2, 1.3], q0, "transpose", jacobian, step=0.75, tol=0, max_iterations=31
    ))  # fmt: skip


stated = transpose_run("from the stated (0.25, 0.75)", [0.25, 0.75])
used = transpose_run("from (0.30, 0.40)", [0.30, 0.40])
if stated is not None and used is not None:
    stated, used = stated.history, used.history
    table(
        "000 Case Study — IK using Jacobian transpose, rows 1–5, from the stated θ⁰ = (0.25, 0.75)",
        ["θ1", "θ2"],
        [(k, (a, b), stated[int(k)]) for k, a, b in ROWS_1_TO_5],
    )
    table(
        "rows 1–5 from θ⁰ = (0.30, 0.40), the start the notes' table was made from",
        ["θ1", "θ2"],
        [(k, (a, b), used[int(k)]) for k, a, b in ROWS_1_TO_5],
    )
    table(
        "rows 26–30 against the iterations they are labelled with",
        ["θ1", "θ2"],
        [(k, (a, b), used[int(k)]) for k, a, b in ROWS_26_TO_30],
    )
    table(
        "rows 26–29 against iterations 27–30, row 30 against iteration 30",
        ["θ1", "θ2"],
        [(f"{k}→{min(int(k) + 1, 30)}", (a, b), used[min(int(k) + 1, 30)])
         for k, a, b in ROWS_26_TO_30],
    )  # fmt: skip
    print(f"iteration 31 = ({used[31][0]:.4f}, {used[31][1]:.4f}): not the printed row 30")
