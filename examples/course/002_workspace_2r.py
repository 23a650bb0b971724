"""Notes 002 (Robotics 1, Inverse kinematics), "Workspace of planar 2R arm": the primary and the
secondary (dexterous) workspace.

Stated: for l1 ≠ l2, WS1 = {|l1 − l2| ≤ ‖p‖ ≤ l1 + l2} and WS2 = ∅; for l1 = l2 = ℓ,
WS1 = {‖p‖ ≤ 2ℓ} and WS2 = {p = 0} (every feasible orientation at the origin). WS2 counts the
orientations "feasible for the robot direct kinematics": for a planar arm, rotations about the
plane's normal, which ``redik.apps.workspace`` tries by default (``attainable_rotations``).
Arms: the bundled ``planar_2r`` (ℓ = 1) and one with l1 = 1, l2 = 0.5 (chosen).

Run: python examples/course/002_workspace_2r.py
"""

import numpy as np

import redik
from redik.apps import workspace

ARMS = [
    ("l1 = l2 = 1", redik.load("planar_2r"), 1.0, 1.0),
    ("l1 = 1, l2 = 0.5", redik.Robot.from_dh([(1.0, 0.0, 0.0), (0.5, 0.0, 0.0)]), 1.0, 0.5),
]
PROBES = np.array([[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [1.0, 0.0, 0.0], [1.5, 0.0, 0.0]])

print("002 planar 2R workspaces")
for name, robot, l1, l2 in ARMS:
    radii = np.linalg.norm(workspace.sample(robot, 2000, seed=0, resolution=4).points, axis=1)
    scores = workspace.reachability(robot, PROBES, orientations=8, seed=0).score
    ws2 = "{p = 0}" if l1 == l2 else "∅"
    print(f"  {name}: WS1 = {{{abs(l1 - l2):.1f} ≤ ‖p‖ ≤ {l1 + l2:.1f}}} (notes), sampled ‖p‖ ∈ "
          f"[{radii.min():.3f}, {radii.max():.3f}] (redik)")  # fmt: skip
    print(f"    WS2 = {ws2} (notes); fraction of 8 orientations reached at ‖p‖ = 0, 0.5, 1, 1.5: "
          f"{scores.tolist()} (redik)")  # fmt: skip
