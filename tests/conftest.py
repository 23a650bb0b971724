"""Shared fixtures: small models and seeded random generators."""

from __future__ import annotations

import numpy as np
import pytest

import redik

# A 7-joint arm with mixed hinge axes, a slide joint, a joint without range, a free-floating
# distractor body and a gripper joint off the chain: enough to exercise chain extraction.
ARM_XML = """
<mujoco model="test_arm">
  <compiler angle="radian"/>
  <worldbody>
    <body name="base" pos="0.1 -0.2 0.3" quat="0.9238795 0 0 0.3826834">
      <joint name="j1" type="hinge" axis="0 0 1" range="-2.8 2.8"/>
      <geom type="capsule" fromto="0 0 0 0 0 0.3" size="0.04"/>
      <body name="l2" pos="0 0 0.3">
        <joint name="j2" type="hinge" axis="0 1 0" range="-1.7 1.7"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.035"/>
        <body name="l3" pos="0.3 0 0" euler="0.3 0 0">
          <joint name="j3" type="slide" axis="1 0 0" range="0 0.2"/>
          <geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.03"/>
          <body name="l4" pos="0.2 0 0">
            <joint name="j4" type="hinge" axis="0 1 0"/>
            <geom type="capsule" fromto="0 0 0 0.25 0 0" size="0.03"/>
            <body name="l5" pos="0.25 0 0">
              <joint name="j5" type="hinge" axis="1 0 0" range="-2.9 2.9"/>
              <joint name="j6" type="hinge" axis="0 1 0" range="-2 2"/>
              <geom type="sphere" size="0.03"/>
              <body name="l7" pos="0.05 0 0.02">
                <joint name="j7" type="hinge" axis="0.6 0 0.8" range="-3 3"/>
                <geom type="box" size="0.02 0.02 0.02"/>
                <site name="ee" pos="0.1 0.01 0.02" euler="0.1 0.2 0.3"/>
                <body name="finger" pos="0.1 0 0">
                  <joint name="grip" type="slide" axis="0 1 0" range="0 0.04"/>
                  <geom type="box" size="0.01 0.01 0.01"/>
                  <site name="fingertip" pos="0 0.02 0"/>
                </body>
              </body>
            </body>
          </body>
        </body>
      </body>
    </body>
    <body name="floating" pos="1 1 1">
      <freejoint/>
      <geom type="sphere" size="0.1"/>
    </body>
  </worldbody>
  <keyframe>
    <key name="home" qpos="0.1 0.2 0.05 -0.3 0.4 0.5 0.6 0.02 1 1 1 1 0 0 0"/>
  </keyframe>
</mujoco>
"""


@pytest.fixture
def arm() -> redik.Robot:
    return redik.Robot.from_xml_string(ARM_XML)


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(12345)
