r"""Headless closed-loop simulation: the IK problem as a controller, MuJoCo as the plant.

At every control tick ``k`` (period ``dt = 1 / control_rate``) :func:`simulate`

1. reads the measured joint values ``q_k`` from the simulation,
2. moves the tracked task's target to the reference pose ``T_d(t_k)``,
3. asks the QP for a step ``Δq = problem.step(q, dt)`` (at which ``q``: see 4),
4. commands the scene's position actuators, either

   * ``command="integrate"`` (default): the joint reference is the integral of the IK
     velocity, ``q̂_{k+1} = q̂_k + Δq(q̂_k)``, and the servo gets it with feed-forward,

     .. math::

         u = q̂ + \frac{k_v}{k_p} \dot{\hat q} + \frac{1}{k_p} M(q)\, \ddot{\hat q},

     so that the servo torque ``k_p (u − q) − k_v q̇`` equals the PD law on the tracking
     error plus the inertial torque the reference motion needs (computed-torque
     feed-forward; Siciliano et al., *Robotics*, §8.5). Without the two terms a servo of
     bandwidth ω lags a moving reference by about ``2/ω`` seconds;
   * ``command="position"``: ``u = q_k + Δq(q_k)`` from the *measured* state — feedback
     through the IK itself, no feed-forward; simple, but the servo only sees the small
     offset ``Δq`` and lags more (and a velocity limit caps that offset at ``v_max dt``),

5. advances the physics by ``mj_step`` until the next tick.

No window is opened: the loop is pure computation, and pictures come afterwards from the
recorded states (:func:`plot_tracking`; videos by :func:`redik.render.render_states` —
set ``MUJOCO_GL=egl`` before MuJoCo is first imported).

Gravity is left to the scene (the bundled scenes compensate it with ``gravcomp``).

Tracking error is the pose error (:mod:`redik.conventions`) of the simulated end-effector
against the reference at the same instant. A position servo with stiffness ``k_p`` lags a
moving reference, so the error grows with the path's speed and shrinks with the control rate
and servo bandwidth; the bounds stated in the tests (and the ``iiwa14_tracking`` task spec)
are measured on the bundled scenes, whose servos run at about 4 Hz bandwidth. Measured
(``redik run tasks/iiwa14_tracking.py --fast``, recorded in
``tasks/baselines/iiwa14_tracking.json``; ``tests/test_sim.py`` asserts the bound):
iiwa14 tracing a 10 cm circle in 4 s (quintic timing, peak speed 0.3 m/s) at 100 Hz with
``"integrate"`` stays within 2.1 mm and 6.4e-3 rad of the reference and ends within
0.023 mm; the stated bound is 3 mm, 0.01 rad and 0.05 mm at the end.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from pathlib import Path

import mujoco
import numpy as np

from .exceptions import InvalidInput, ModelError
from .lie import pose_errors
from .plot import new_figure, save_figure
from .robot import Robot
from .trajectory import Path as PosePath

COMMANDS = ("position", "integrate")


@dataclasses.dataclass
class SimulationResult:
    """What a closed-loop run recorded, one row per control tick.

    Attributes:
        times: (N,) tick times in seconds (each row is the state once the physics reached it).
        q: (N, n) measured chain joint values.
        q_command: (N, n) position commands sent to the actuators.
        qpos: (N, nq) full simulation state, for rendering the run afterwards.
        targets: (N, 4, 4) reference poses.
        position_error: (N,) ``‖p_d − p‖`` of the simulated end-effector, metres.
        rotation_error: (N,) angle of ``Rᵀ R_d``, radians.
        control_rate: Control ticks per second.
    """

    times: np.ndarray
    q: np.ndarray
    q_command: np.ndarray
    qpos: np.ndarray
    targets: np.ndarray
    position_error: np.ndarray
    rotation_error: np.ndarray
    control_rate: float

    @property
    def max_position_error(self) -> float:
        return float(self.position_error.max())

    @property
    def max_rotation_error(self) -> float:
        return float(self.rotation_error.max())

    @property
    def rms_position_error(self) -> float:
        return float(np.sqrt(np.mean(self.position_error**2)))

    @property
    def final_position_error(self) -> float:
        return float(self.position_error[-1])

    @property
    def final_rotation_error(self) -> float:
        return float(self.rotation_error[-1])

    def summary(self) -> str:
        return (
            f"{len(self.times)} ticks at {self.control_rate:g} Hz over {self.times[-1]:.2f} s: "
            f"tracking error max {self.max_position_error * 1e3:.3f} mm / "
            f"{self.max_rotation_error:.2e} rad, rms {self.rms_position_error * 1e3:.3f} mm, "
            f"final {self.final_position_error * 1e3:.4f} mm / {self.final_rotation_error:.2e} rad"
        )


def actuator_indices(robot: Robot) -> np.ndarray:
    """The actuator driving each chain joint (one per joint, in ``robot.joint_names`` order).

    Raises:
        ModelError: a chain joint has no actuator acting on it directly.
    """
    model = robot.model
    by_joint = {}
    for a in range(model.nu):
        if int(model.actuator_trntype[a]) == int(mujoco.mjtTrn.mjTRN_JOINT):
            by_joint.setdefault(int(model.actuator_trnid[a, 0]), a)
    indices = []
    for name in robot.joint_names:
        joint = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
        if joint not in by_joint:
            raise ModelError(
                f"joint {name!r} of {robot.name!r} has no actuator; simulate() needs one "
                f"position actuator per chain joint"
            )
        indices.append(by_joint[joint])
    return np.array(indices, dtype=int)


def servo_lead(model: mujoco.MjModel, actuators: np.ndarray) -> np.ndarray:
    """``kv / kp`` of each position servo (seconds): how far it lags a ramp at steady state.

    A MuJoCo position actuator applies ``kp (ctrl − q) − kv q̇`` (``gainprm[0] = kp``,
    ``biasprm[1] = −kp``, ``biasprm[2] = −kv``); following ``q_ref(t) = v t`` it settles
    ``(kv / kp) v`` behind. Actuators of another form get 0 (no feed-forward).
    """
    kp = model.actuator_gainprm[actuators, 0]
    kv = -model.actuator_biasprm[actuators, 2]
    is_servo = (kp > 0.0) & np.isclose(model.actuator_biasprm[actuators, 1], -kp) & (kv >= 0.0)
    return np.where(is_servo, kv / np.where(kp > 0.0, kp, 1.0), 0.0)


def simulate(
    robot: Robot,
    problem,
    task,
    reference: PosePath | Callable[[float], np.ndarray],
    duration: float | None = None,
    *,
    q0: np.ndarray | None = None,
    control_rate: float = 100.0,
    command: str = "integrate",
    on_tick: Callable[[int, int], None] | None = None,
) -> SimulationResult:
    """Run the closed loop described in the module docstring.

    Args:
        robot: The robot; its model must have a position actuator on every chain joint.
        problem: A :class:`redik.Problem` whose ``step(q, dt)`` returns ``Δq``.
        task: The task of ``problem`` that tracks the reference (it must have
            ``set_target(T)``, like :class:`redik.PoseTask`).
        reference: A path (:class:`~redik.trajectory.CartesianPath`,
            :class:`~redik.trajectory.CircularPath`) or a function ``t -> T_d``.
        duration: Seconds to simulate; default the path's duration.
        q0: Initial joint values (default ``robot.home``); the arm starts at rest there.
        control_rate: Control ticks per second; the physics step must divide the period.
        command: ``"position"`` or ``"integrate"`` (module docstring).
        on_tick: Called as ``on_tick(k, total)`` after every tick (e.g. a progress bar).

    Raises:
        InvalidInput: bad duration, rate or command; a control period that is not a whole
            number of physics steps.
        ModelError: a chain joint without an actuator.
    """
    if command not in COMMANDS:
        raise InvalidInput(f"command must be one of {COMMANDS}, got {command!r}")
    if isinstance(reference, PosePath):
        pose_at, start = reference.pose, reference.start_time
        duration = reference.duration if duration is None else duration
    elif callable(reference):
        pose_at, start = reference, 0.0
    else:
        raise InvalidInput(f"reference must be a trajectory.Path or t -> T, got {reference!r}")
    if duration is None or not duration > 0.0:
        raise InvalidInput(f"duration must be a positive number of seconds, got {duration!r}")
    if not control_rate > 0.0:
        raise InvalidInput(f"control_rate must be positive (Hz), got {control_rate!r}")
    dt = 1.0 / control_rate
    substeps = dt / robot.model.opt.timestep
    if abs(substeps - round(substeps)) > 1e-6 or round(substeps) < 1:
        raise InvalidInput(
            f"the control period {dt:g} s must be a whole number of physics steps "
            f"({robot.model.opt.timestep:g} s)"
        )
    substeps = round(substeps)
    q = robot.home.copy() if q0 is None else robot.check_q(q0, "q0").copy()
    actuators = actuator_indices(robot)
    lead = servo_lead(robot.model, actuators)
    qpos_adr = robot.qpos_indices

    data = mujoco.MjData(robot.model)
    data.qpos[:] = robot.full_qpos(q)
    data.ctrl[actuators] = q
    mujoco.mj_forward(robot.model, data)
    T = np.eye(4)
    ee = robot.frame(getattr(task, "frame_name", None))

    ticks = round(duration * control_rate)
    times = start + np.arange(1, ticks + 1) * dt
    q_log, command_log = np.empty((ticks, robot.dof)), np.empty((ticks, robot.dof))
    qpos_log = np.empty((ticks, robot.model.nq))
    targets = np.empty((ticks, 4, 4))
    position_error, rotation_error = np.empty(ticks), np.empty(ticks)
    q_command = q.copy()
    previous_velocity = np.zeros(robot.dof)
    accel_full = np.zeros(robot.model.nv)
    torque_full = np.zeros(robot.model.nv)
    kp = robot.model.actuator_gainprm[actuators, 0]
    if command == "integrate" and np.any(kp <= 0.0):
        raise ModelError("command='integrate' needs position servos (kp > 0) on every joint")
    for k, t in enumerate(times):
        q_measured = data.qpos[qpos_adr]
        # Aim at where the reference will be when this command has been applied.
        task.set_target(pose_at(t))
        if command == "position":
            q_command = q_measured + problem.step(q_measured.copy(), dt)
            data.ctrl[actuators] = q_command
        else:
            dq = problem.step(q_command, dt)
            q_command = q_command + dq
            velocity = dq / dt
            accel_full[robot.dof_indices] = (velocity - previous_velocity) / dt
            previous_velocity = velocity
            mujoco.mj_mulM(robot.model, data, torque_full, accel_full)
            # The servo's damping pulls against motion: kp (ctrl − q) − kv q̇. Leading the
            # setpoint by (kv / kp) q̇_ref cancels that pull on the reference velocity.
            inertial = torque_full[robot.dof_indices]
            data.ctrl[actuators] = q_command + lead * velocity + inertial / kp
        mujoco.mj_step(robot.model, data, nstep=substeps)
        mujoco.mj_kinematics(robot.model, data)  # mj_step leaves poses of the previous state

        targets[k] = pose_at(t)
        _site_pose(data, ee, T)
        position_error[k], rotation_error[k] = pose_errors(T, targets[k])
        q_log[k] = data.qpos[qpos_adr]
        command_log[k] = q_command
        qpos_log[k] = data.qpos
        if on_tick is not None:
            on_tick(k, ticks)
    return SimulationResult(
        times=times,
        q=q_log,
        q_command=command_log,
        qpos=qpos_log,
        targets=targets,
        position_error=position_error,
        rotation_error=rotation_error,
        control_rate=control_rate,
    )


def _site_pose(data: mujoco.MjData, frame, T: np.ndarray) -> None:
    """The pose of a resolved frame in a simulation's data (after ``mj_step``)."""
    if frame.kind == "site":
        T[:3, :3] = data.site_xmat[frame.id].reshape(3, 3)
        T[:3, 3] = data.site_xpos[frame.id]
    else:
        T[:3, :3] = data.xmat[frame.id].reshape(3, 3)
        T[:3, 3] = data.xpos[frame.id]


def plot_tracking(result: SimulationResult, path: str | Path, title: str = "") -> Path:
    """Save a PNG: tracking errors over time, and each joint's command against its value."""
    fig, (ax_err, ax_q) = new_figure(2, 1, figsize=(8, 6.5), sharex=True)
    ax_err.plot(result.times, result.position_error * 1e3, label="position (mm)")
    ax_rot = ax_err.twinx()
    ax_rot.plot(result.times, result.rotation_error, color="tab:orange", label="rotation (rad)")
    ax_err.set_ylabel("position error [mm]")
    ax_rot.set_ylabel("rotation error [rad]", color="tab:orange")
    ax_err.set_title(title or "closed-loop tracking error")
    ax_err.grid(True, alpha=0.3)
    for j in range(result.q.shape[1]):
        (line,) = ax_q.plot(result.times, result.q[:, j], label=f"q{j + 1}")
        ax_q.plot(result.times, result.q_command[:, j], "--", color=line.get_color(), lw=0.8)
    ax_q.set_xlabel("time [s]")
    ax_q.set_ylabel("joint value (solid) / command (dashed)")
    ax_q.legend(ncol=4, fontsize=7)
    ax_q.grid(True, alpha=0.3)
    return save_figure(fig, path, dpi=110)
