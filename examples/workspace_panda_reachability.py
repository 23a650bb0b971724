"""Where can the Panda reach, and with how many orientations? Workspace samples and a map.

Writes workspace_3d.png, workspace_slices.png and reachability_z.png into $REDIK_OUT
(default: the current folder).

Run: python examples/workspace_panda_reachability.py
"""

import os
from pathlib import Path

import numpy as np

import redik
from redik.apps import workspace

out = Path(os.environ.get("REDIK_OUT", "."))
robot = redik.load("panda")

sample = workspace.sample(robot, 4000, seed=0, orientations=6, resolution=8)
print(
    f"{len(sample.points)} FK samples, {len(sample.cells.points)} occupied cells "
    f"of {sample.cell_size:.3f} m, {len(sample.dexterous)} dexterous (all 6 orientations)"
)
for path in sample.plot(out):
    print("wrote", path)

xs = np.linspace(-1.0, 1.0, 15)
grid = np.stack(np.meshgrid(xs, xs, [0.5], indexing="ij"), axis=-1)  # the plane z = 0.5 m
reach = workspace.reachability(robot, grid, orientations=6, seed=0)
print(
    f"plane z = 0.5 m: mean score {reach.score.mean():.2f}, "
    f"{(reach.score > 0).sum()} of {reach.score.size} points reachable with some orientation"
)
print("wrote", reach.plot_slice(out / "reachability_z.png", axis="z"))
