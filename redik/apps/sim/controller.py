r"""The joint-level controller: a joint reference in, actuator controls out.

Given the reference ``(q̂, \dot{\hat q}, \ddot{\hat q})`` of the chain joints and the measured
state ``(q, q̇)``, the feed-forward is the computed torque (Siciliano et al., *Robotics:
Modelling, Planning and Control*, §8.5)

.. math::

    τ_{ff} = M(q)\, \ddot{\hat q} + c(q, \dot q) + g(q) − τ_{passive}(q, \dot q),

MuJoCo's inverse dynamics (``mj_inverse`` at the measured state with ``qacc = \ddot{\hat q}``
on the chain joints, 0 elsewhere: inertia, Coriolis, gravity, joint damping and springs).

- A **position servo** (``biasprm = [0, −k_p, −k_v]``, :mod:`~redik.apps.sim.drives`) applies
  ``k_p (u − q) − k_v q̇`` (per unit gear); it gets
  ``u = q̂ + \frac{k_v}{k_p} \dot{\hat q} + \frac{1}{k_p} τ_{ff}``, so that its torque is
  ``k_p (q̂ − q) + k_v (\dot{\hat q} − q̇) + τ_{ff}``: its own PD on the tracking error plus
  the torque the motion needs. Without the feed-forward a servo sags under gravity by
  ``g(q) / k_p`` and lags a moving reference by about ``k_v / k_p`` seconds.
- A **motor** (torque actuator) gets the computed-torque law ``τ = τ_{ff}`` evaluated with
  ``qacc = \ddot{\hat q} + K_d (\dot{\hat q} − q̇) + K_p (q̂ − q)``, ``K_p = ω²``, ``K_d = 2ω``
  (critically damped error dynamics of bandwidth ``ω``), and
  ``u = τ / (\text{gear} · \text{gain})``.

MuJoCo clips ``u`` to ``ctrlrange`` and the actuator force to ``forcerange``; the controller
reports either (saturation), and cuts the inertial part of a servo's feed-forward to what the
actuator can give (:meth:`Controller.controls`).
"""

from __future__ import annotations

import mujoco
import numpy as np

from redik.apps.sim.drives import JointDrives
from redik.kinematics.robot import Robot

SATURATION_TOLERANCE = 1e-9
"""How close to its range an actuator force counts as saturated (N or N·m)."""


class Controller:
    r"""Turns a joint reference ``(q̂, \dot{\hat q}, \ddot{\hat q})`` into actuator controls.

    Args:
        robot: The robot whose chain joints are driven.
        drives: Their actuators (:func:`~redik.apps.sim.drives.joint_drives`).
        feedforward: Add ``τ_ff`` to the servos' commands (motors always use it).
        motor_bandwidth: ``ω`` (rad/s) of the motors' computed-torque law.
    """

    def __init__(
        self, robot: Robot, drives: JointDrives, feedforward: bool, motor_bandwidth: float
    ):
        model = robot.model
        self.model, self.drives, self.feedforward = model, drives, feedforward
        self.dofs = np.asarray(robot.dof_indices)
        self.qpos_adr = np.asarray(robot.qpos_indices)
        self.scratch = mujoco.MjData(model)
        self.servo = drives.servo
        self.any_servo, self.all_servo = bool(self.servo.any()), bool(self.servo.all())
        self.lead = drives.lead
        self.accel_full, self.inertial_full = np.zeros(model.nv), np.zeros(model.nv)
        self.kp_motor, self.kd_motor = motor_bandwidth**2, 2.0 * motor_bandwidth
        self._ranges(model, drives)

    def _ranges(self, model: mujoco.MjModel, drives: JointDrives) -> None:
        """Control, actuator-force and joint-torque ranges (±inf where unlimited)."""
        a = drives.actuators
        ctrl_limited = model.actuator_ctrllimited[a].astype(bool)
        self.ctrl_low = np.where(ctrl_limited, model.actuator_ctrlrange[a, 0], -np.inf)
        self.ctrl_high = np.where(ctrl_limited, model.actuator_ctrlrange[a, 1], np.inf)
        limited = model.actuator_forcelimited[a].astype(bool)
        self.force_low = np.where(limited, model.actuator_forcerange[a, 0], -np.inf)
        self.force_high = np.where(limited, model.actuator_forcerange[a, 1], np.inf)
        joints = model.dof_jntid[self.dofs]
        joint_limited = model.jnt_actfrclimited[joints].astype(bool)
        self.joint_low = np.where(joint_limited, model.jnt_actfrcrange[joints, 0], -np.inf)
        self.joint_high = np.where(joint_limited, model.jnt_actfrcrange[joints, 1], np.inf)
        gear = drives.gear
        bounds = np.sort(np.stack([gear * self.force_low, gear * self.force_high]), axis=0)
        self.torque_low = np.maximum(np.nan_to_num(bounds[0], nan=-np.inf), self.joint_low)
        self.torque_high = np.minimum(np.nan_to_num(bounds[1], nan=np.inf), self.joint_high)

    def inverse_dynamics(self, data: mujoco.MjData, qacc: np.ndarray) -> np.ndarray:
        """``M(q) q̈ + c(q, q̇) + g(q) − τ_passive`` on the chain joints at the measured state.

        Computed by ``mj_inverse`` on a scratch copy of ``data``, the other joints'
        accelerations taken as 0.

        Args:
            data: The simulation's state.
            qacc: ``(n,)`` accelerations of the chain joints.

        Returns:
            ``(n,)`` generalised forces on the chain joints.
        """
        scratch = self.scratch
        scratch.qpos[:], scratch.qvel[:] = data.qpos, data.qvel
        if self.model.na:
            scratch.act[:] = data.act
        scratch.qacc[:] = 0.0
        scratch.qacc[self.dofs] = qacc
        mujoco.mj_inverse(self.model, scratch)
        return scratch.qfrc_inverse[self.dofs].copy()

    def _unreachable_inertia(self, torque: np.ndarray, accel: np.ndarray) -> np.ndarray:
        """The part of ``M q̈`` that would push a joint's torque past its actuator's range.

        A reference that chatters (near a singularity the QP's joint velocities flip from
        tick to tick) asks for accelerations no actuator can give; sent anyway, they saturate
        the actuator and take away the feedback and gravity terms that keep the arm on the
        path. So the inertial term is scaled down first, per joint, to fit the range. Reads
        the mass matrix :meth:`inverse_dynamics` just computed.
        """
        self.accel_full[self.dofs] = accel
        mujoco.mj_mulM(self.model, self.scratch, self.inertial_full, self.accel_full)
        inertial = self.inertial_full[self.dofs]
        excess = np.maximum(torque - self.torque_high, 0.0) + np.minimum(
            torque - self.torque_low, 0.0
        )
        ratio = np.divide(excess, inertial, out=np.zeros_like(excess), where=inertial != 0.0)
        return np.clip(ratio, 0.0, 1.0) * inertial

    def controls(
        self,
        data: mujoco.MjData,
        q_ref: np.ndarray,
        velocity_ref: np.ndarray,
        accel_ref: np.ndarray,
    ) -> tuple[np.ndarray, bool]:
        r"""The controls of the chain's actuators by the laws of the module docstring.

        Args:
            data: The simulation's state (the measured ``q``, ``q̇``).
            q_ref: ``q̂``.
            velocity_ref: ``\dot{\hat q}``.
            accel_ref: ``\ddot{\hat q}``.

        Returns:
            The controls (clipped to ``ctrlrange``), and whether the clipping changed any.
        """
        drives, servo = self.drives, self.servo
        q, qdot = data.qpos[self.qpos_adr], data.qvel[self.dofs]
        g = drives.gear
        u = np.empty(len(g))
        if self.any_servo:
            # servo torque g·kp·u − g²kp·q − g²kv·q̇ = g²kp (q̂ − q) + g²kv (q̂' − q̇) + τ_ff
            kp, kv = drives.gain, drives.kv
            servo_u = g * (q_ref + self.lead * velocity_ref)
            if self.feedforward:
                tau = self.inverse_dynamics(data, accel_ref)
                feedback = g * g * (kp * (q_ref - q) + kv * (velocity_ref - qdot))
                tau -= self._unreachable_inertia(feedback + tau, accel_ref)
                servo_u += tau / (g * kp)
            u[servo] = servo_u[servo]
        if not self.all_servo:
            qacc = accel_ref + self.kd_motor * (velocity_ref - qdot) + self.kp_motor * (q_ref - q)
            motor_u = self.inverse_dynamics(data, qacc) / (g * drives.gain)
            u[~servo] = motor_u[~servo]
        clipped = bool(np.any((u < self.ctrl_low) | (u > self.ctrl_high)))
        return np.clip(u, self.ctrl_low, self.ctrl_high), clipped

    def force_saturated(self, data: mujoco.MjData) -> bool:
        """True when an actuator force (or a joint's actuator torque) sits at its range."""
        force = data.actuator_force[self.drives.actuators]
        torque = data.qfrc_actuator[self.dofs]
        tol = SATURATION_TOLERANCE
        return bool(
            np.any((force <= self.force_low + tol) | (force >= self.force_high - tol))
            or np.any((torque <= self.joint_low + tol) | (torque >= self.joint_high - tol))
        )
