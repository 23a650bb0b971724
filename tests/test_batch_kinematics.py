"""Batched FK and Jacobians of the compiled chain against MuJoCo's own (robot.fk/jacobian)."""

from __future__ import annotations

import pickle

import mujoco
import numpy as np
import pytest

import redik
from redik.solvers.batch import Chain, forward_kinematics, jacobian

from .conftest import ARM_XML

# Joint references (qpos0 ≠ 0), anchors off the body origin, skew axes, a slide after a hinge
# in one body, and a ball joint on the chain held at its home quaternion (fixed=["ball"]:
# a chain moves hinges and slides only, and never freezes a ball joint silently).
REF_ARM_XML = """
<mujoco model="ref_arm">
  <worldbody>
    <body name="root" pos="0 0.1 0.2" euler="0.2 -0.1 0.4">
      <joint name="ball" type="ball" pos="0.01 0 0.02"/>
      <geom type="sphere" size="0.05"/>
      <body name="a" pos="0.1 0 0.2" quat="0.8 0.2 0.5 0.2">
        <joint name="h1" type="hinge" axis="0.3 0.4 0.5" pos="0.05 0.02 0" ref="0.4"
               range="-2 2"/>
        <joint name="s1" type="slide" axis="1 1 0" pos="0.1 0 0" ref="0.1" range="-0.3 0.3"/>
        <geom type="sphere" size="0.05"/>
        <body name="b" pos="0.2 0 0">
          <joint name="h2" type="hinge" axis="0 0 1" pos="0 0.1 0.05" ref="-0.7"/>
          <geom type="sphere" size="0.05"/>
          <site name="ee" pos="0.1 0 0.03" euler="0.5 0.1 -0.2"/>
        </body>
      </body>
    </body>
  </worldbody>
  <keyframe>
    <key name="home" qpos="0.8660254 0.5 0 0  0.3 0.05 0.2"/>
  </keyframe>
</mujoco>
"""

# A floating base frozen at its home pose, with the chain hanging below it.
FREE_BASE_XML = """
<mujoco model="free_base">
  <worldbody>
    <body name="base" pos="0 0 1">
      <freejoint/>
      <geom type="box" size="0.1 0.1 0.1"/>
      <body name="l1" pos="0 0 0.1">
        <joint name="j1" type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
        <body name="l2" pos="0.3 0 0">
          <joint name="j2" type="hinge" axis="0 0 1" range="-1 1"/>
          <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
          <site name="ee" pos="0.3 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
  <keyframe>
    <key name="home" qpos="0.2 -0.3 1.1  0.9238795 0 0.3826834 0  0.5 0.2"/>
  </keyframe>
</mujoco>
"""


def _robots() -> dict[str, redik.Robot]:
    robots = {name: redik.load(name) for name in redik.list_scenes()}
    robots["test_arm"] = redik.Robot.from_xml_string(ARM_XML)
    robots["test_arm_fingertip"] = redik.Robot.from_xml_string(ARM_XML, ee="fingertip")
    robots["test_arm_body_ee"] = redik.Robot.from_xml_string(ARM_XML, ee="l7")
    robots["ref_arm"] = redik.Robot(mujoco.MjModel.from_xml_string(REF_ARM_XML), fixed=["ball"])
    # A hinge and a slide on the chain held at their home values (q − qpos0 ≠ 0), skew axes.
    robots["ref_arm_held"] = redik.Robot(
        mujoco.MjModel.from_xml_string(REF_ARM_XML), fixed=["ball", "h1", "s1"]
    )
    robots["free_base"] = redik.Robot.from_xml_string(FREE_BASE_XML)
    return robots


ROBOTS = _robots()


@pytest.fixture(params=sorted(ROBOTS), ids=str)
def robot(request) -> redik.Robot:
    return ROBOTS[request.param]


def test_there_are_scenes_to_check():
    assert len(redik.list_scenes()) >= 3


def test_forward_kinematics_matches_mujoco(robot, rng):
    chain = Chain.from_robot(robot)
    q = robot.random_q(rng, size=16)
    T = forward_kinematics(chain, q)
    assert T.shape == (16, 4, 4)
    for i in range(len(q)):
        np.testing.assert_allclose(T[i], robot.fk(q[i]), rtol=0, atol=1e-12)


@pytest.mark.parametrize("reference", ["world", "space", "body"])
def test_jacobian_matches_mujoco(robot, reference, rng):
    chain = Chain.from_robot(robot)
    q = robot.random_q(rng, size=16)
    J = jacobian(chain, q, reference=reference)
    assert J.shape == (16, 6, robot.dof)
    for i in range(len(q)):
        expected = robot.jacobian(q[i], reference=reference)
        np.testing.assert_allclose(J[i], expected, rtol=0, atol=1e-12)


def test_jacobian_is_the_derivative_of_forward_kinematics(rng):
    # Independent of MuJoCo: finite differences of the batched FK itself (world reference).
    robot = ROBOTS["ref_arm"]
    chain = Chain.from_robot(robot)
    q = robot.random_q(rng)
    J = jacobian(chain, q, reference="world")[0]
    T = forward_kinematics(chain, q)[0]
    h = 1e-6
    for k in range(robot.dof):
        dq = np.zeros(robot.dof)
        dq[k] = h
        plus, minus = forward_kinematics(chain, q + dq)[0], forward_kinematics(chain, q - dq)[0]
        np.testing.assert_allclose((plus[:3, 3] - minus[:3, 3]) / (2 * h), J[:3, k], atol=1e-8)
        dR = (plus[:3, :3] - minus[:3, :3]) / (2 * h) @ T[:3, :3].T
        omega = np.array([dR[2, 1], dR[0, 2], dR[1, 0]])
        np.testing.assert_allclose(omega, J[3:, k], atol=1e-8)


def test_single_configuration_gives_a_batch_of_one():
    robot = ROBOTS["test_arm"]
    chain = Chain.from_robot(robot)
    np.testing.assert_allclose(forward_kinematics(chain, robot.home)[0], robot.fk(robot.home))


def test_chain_carries_limits_and_pickles():
    robot = ROBOTS["test_arm"]
    chain = pickle.loads(pickle.dumps(Chain.from_robot(robot)))
    assert chain.dof == robot.dof
    np.testing.assert_array_equal(chain.lower, robot.lower)
    np.testing.assert_array_equal(chain.upper, robot.upper)
    np.testing.assert_array_equal(chain.revolute, robot.revolute)
    assert not np.isfinite(chain.upper).all()  # j4 has no range


@pytest.mark.parametrize("q", [np.zeros(3), np.zeros((2, 8)), np.full(7, np.nan)])
def test_bad_configurations_raise(q):
    chain = Chain.from_robot(ROBOTS["test_arm"])
    with pytest.raises(redik.InvalidConfiguration):
        forward_kinematics(chain, q)


def test_unknown_reference_raises():
    chain = Chain.from_robot(ROBOTS["test_arm"])
    with pytest.raises(redik.InvalidInput, match="reference"):
        jacobian(chain, np.zeros(7), reference="hybrid")
