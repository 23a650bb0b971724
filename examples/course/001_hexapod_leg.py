"""Notes 001 (Inverse Kinematics), "Example: Analytical IK" (leg of a hexapod): the three servo
angles from the foot position.

The notes give the formulas and no numbers:
    γ = atan(x / y)  (coxa, from the leg's outward y axis),
    α = acos(Z_offset / L) + acos((tibia² − femur² − L²) / (−2 femur L))  (femur, from the
        downward vertical),
    β = acos((L² − tibia² − femur²) / (−2 tibia femur))  (knee, between femur and tibia),
with L = √(Z_offset² + (L1 − coxa)²), L1 = √(x² + y²) and Z_offset the height of the femur axis
above the foot. The bundled ``hexapod_leg`` scene's lengths and a foot at x = 0.05, y = 0.15,
Z_offset = 0.105 are chosen here. redik's leg frame has x outward (the notes' y) and its
``z_offset`` is the femur axis' height above the leg origin, so the notes' foot is
p = (y, x, z_offset − Z_offset); ``convention="lecture"`` returns (γ, α, β).

Run: python examples/course/001_hexapod_leg.py
"""

import math

from _table import table

from redik.solvers.analytic import hexapod_leg

COXA, FEMUR, TIBIA, Z_OFFSET = 0.052, 0.082, 0.142, -0.015  # the bundled scene
x, y, Z_offset = 0.05, 0.15, 0.105  # the notes' inputs, chosen

L1 = math.hypot(x, y)
L = math.hypot(Z_offset, L1 - COXA)
gamma = math.atan(x / y)
alpha = math.acos(Z_offset / L) + math.acos((TIBIA**2 - FEMUR**2 - L**2) / (-2 * FEMUR * L))
beta = math.acos((L**2 - TIBIA**2 - FEMUR**2) / (-2 * TIBIA * FEMUR))
notes = [f"{math.degrees(angle):.3f}" for angle in (gamma, alpha, beta)]

foot = [y, x, Z_OFFSET - Z_offset]
lecture = hexapod_leg(foot, COXA, FEMUR, TIBIA, Z_OFFSET, convention="lecture")
ours = [math.degrees(angle) for angle in lecture.by_label("knee-up")]
table(
    "001 hexapod leg — the notes' formulas against hexapod_leg(convention='lecture'), degrees",
    ["γ", "α", "β"],
    [("knee-up", notes, ours)],
)
joint = hexapod_leg(foot, COXA, FEMUR, TIBIA, Z_OFFSET).by_label("knee-up")
print(
    "the same solution in joint angles (θ1, θ2, θ3) = "
    f"({', '.join(f'{math.degrees(angle):.3f}°' for angle in joint)}): γ = θ1, α = θ2 + 90°, "
    "β = θ3 + 180°"
)
