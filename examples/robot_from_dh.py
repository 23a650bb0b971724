"""Build a robot from a Denavit–Hartenberg table and check it against the table's own FK.

A datasheet table becomes a MuJoCo model (bodies, hinge joints, an ``ee`` site, servos); the
table travels inside the model, so it can be read back from the generated file.

Run: python examples/robot_from_dh.py
"""

import itertools
import math

import mujoco
import numpy as np

import redik
from redik.models import dh
from redik.models.builder import dh_to_mjcf, read_dh

# UR5e, standard DH (a, d, alpha) in metres and radians, as Universal Robots publish it.
rows = [
    (0.0, 0.1625, math.pi / 2),
    (-0.425, 0.0, 0.0),
    (-0.3922, 0.0, 0.0),
    (0.0, 0.1333, math.pi / 2),
    (0.0, 0.0997, -math.pi / 2),
    (0.0, 0.0996, 0.0),
]
limits = (
    [(-2 * math.pi, 2 * math.pi)] * 2 + [(-math.pi, math.pi)] + [(-2 * math.pi, 2 * math.pi)] * 3
)
home = [0.0, -1.2, 1.5, -1.9, -1.571, 0.0]

robot = redik.Robot.from_dh(rows, "standard", limits, name="my_ur5e", home=home)
print(robot, "joints:", robot.joint_names)

rng = np.random.default_rng(0)
worst = max(
    np.abs(robot.fk(q) - dh.forward(rows, q)).max()
    for q in rng.uniform(robot.lower, robot.upper, (100, robot.dof))
)
print(f"max |T_mujoco − T_dh| over 100 random q: {worst:.1e}")
print("ee position at home [m]:", np.round(robot.fk(np.array(home))[:3, 3], 4))

# The same table in Craig's modified convention (row i holds a_{i-1}, alpha_{i-1}), with
# the last (a_n, alpha_n) as the tool, is the same arm.
modified = [(0.0, rows[0][1], 0.0)] + [
    (previous[0], row[1], previous[2]) for previous, row in itertools.pairwise(rows)
]
tool = (rows[-1][0], 0.0, rows[-1][2])
q = np.array(home)
difference = np.abs(dh.forward(modified, q, "modified", tool) - dh.forward(rows, q)).max()
print(f"modified-DH table of the same arm differs by {difference:.1e}")

# The MJCF string carries the table: read it back from the compiled model.
model = mujoco.MjModel.from_xml_string(dh_to_mjcf(rows, limits=limits, home=home))
read_rows, convention, _ = read_dh(model)
print(f"table read back from the model ({convention}): a =", [row.a for row in read_rows])
