r"""The closed loop: :func:`simulate` steps the IK problem and MuJoCo's physics tick by tick.

At every control tick ``k`` (period ``dt = 1 / control_rate``) :func:`simulate`

1. reads the measured joint values ``q_k`` and velocities ``q̇_k`` from the simulation,
2. moves the tracked task's target to the reference pose ``T_d(t_k)``,
3. asks the problem for a step ``Δq = problem.step(q, dt)`` and turns it into a joint
   reference, by ``command``:

   * ``"integrate"`` (default): the reference is the integral of the IK velocity,
     ``q̂_{k+1} = q̂_k + Δq(q̂_k)``; over the tick the actuators track ``q̂_k`` with velocity
     ``\dot{\hat q} = Δq / dt`` and acceleration ``\ddot{\hat q}`` its backward difference —
     all three at the same instant, the start of the tick;
   * ``"position"``: ``q̂ = q_k + Δq(q_k)`` from the *measured* state — feedback through the
     IK itself — with zero reference velocity and acceleration (a servo then only sees the
     small offset ``Δq`` and lags more);

4. drives each chain joint's actuator toward the reference
   (:class:`~redik.apps.sim.controller.Controller`: servo PD or computed torque, with the
   inverse-dynamics feed-forward),
5. advances the physics by ``mj_step`` until the next tick, then reads MuJoCo's warnings and
   contacts (:mod:`~redik.apps.sim.monitor`): a warning stops the run with status
   ``"unstable"``.

Tracking error is the pose error (:mod:`redik.core.conventions`) of the simulated frame
against the reference at the same instant. It has two recorded parts: the IK's own error (the
FK of ``q̂`` against the reference: a path the QP cannot follow, near a singularity or a joint
or velocity limit) and the servo error (the joints lagging ``q̂``). No window is opened:
pictures come afterwards from the recorded states (:func:`~redik.apps.sim.plot_tracking`;
videos by :func:`redik.apps.render.render_states`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import mujoco
import numpy as np

from redik.apps.sim.base import BaseHold, check_base
from redik.apps.sim.controller import Controller
from redik.apps.sim.drives import joint_drives
from redik.apps.sim.monitor import ContactLog, InstabilityWatch
from redik.apps.sim.result import SimulationResult, SimulationStatus, tracking_diagnosis
from redik.apps.trajectory import PosePath
from redik.core.exceptions import InstabilityWarning, InvalidInput, TrackingWarning, warn
from redik.core.validate import flag, positive
from redik.kinematics.robot import Robot
from redik.lie import pose_errors

COMMANDS = ("position", "integrate")

DEFAULT_ERROR_BOUND = (5e-3, 5e-2)
"""Tracking error (m, rad) above which :func:`simulate` warns, unless told otherwise."""


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
    feedforward: bool = True,
    motor_bandwidth: float = 30.0,
    error_bound: tuple[float, float] | None = DEFAULT_ERROR_BOUND,
    hold_base: bool = False,
    on_tick: Callable[[int, int], None] | None = None,
) -> SimulationResult:
    """Track a reference pose path in closed loop on MuJoCo's physics (module docstring).

    Args:
        robot: The robot; its model needs a position servo or a torque motor on every chain
            joint (:func:`~redik.apps.sim.drives.joint_drives`).
        problem: A :class:`redik.Problem` whose ``step(q, dt)`` returns ``Δq``. It is reset
            (:meth:`redik.Problem.reset`) at the start: the run starts at rest and does not
            continue the motion of an earlier run, so the same problem simulated twice gives
            the same result.
        task: The task of ``problem`` that tracks the reference (it must have
            ``set_target(T)``, like :class:`redik.FrameTask`); its frame is the one measured.
        reference: A path (:class:`~redik.apps.trajectory.CartesianPath`,
            :class:`~redik.apps.trajectory.CircularPath`) or a function ``t -> T_d``.
        duration: Seconds to simulate; default the path's duration.
        q0: Initial joint values (default ``robot.home``); the robot starts at rest there.
        control_rate: Control ticks per second; the physics step must divide the period.
        command: ``"integrate"`` or ``"position"`` (module docstring).
        feedforward: Add the inverse-dynamics torque to the position servos' commands
            (gravity, Coriolis, inertia, joint damping). Motors always use it: a torque
            actuator has no other way to hold the arm up.
        motor_bandwidth: ``ω`` (rad/s) of the motors' computed-torque law
            (``K_p = ω²``, ``K_d = 2ω``); keep ``ω · dt`` well below 1.
        error_bound: ``(position m, rotation rad)``: warn (:class:`TrackingWarning`) when the
            tracking error exceeds either; None for no check.
        hold_base: Hold a floating base (a free joint above the chain) at its initial pose
            (:mod:`~redik.apps.sim.base`). Without it, a floating base that nothing supports
            under gravity is refused.
        on_tick: Called as ``on_tick(k, total)`` after every tick (e.g. a progress bar).

    Returns:
        The recorded run. Its ``status`` is ``"completed"``, or ``"unstable"`` when MuJoCo
        reported the physics unsound: the run then stops, keeps the ticks before, and warns
        (:class:`~redik.core.exceptions.InstabilityWarning`) with the result's summary.
        Contacts of the robot (with itself and with the world) are in ``contacts`` and in
        the summary.

    Raises:
        InvalidInput: bad duration, rate, command, bandwidth, bound or flag; a control period
            that is not a whole number of physics steps.
        ModelError: a chain joint without an actuator :func:`simulate` can drive; a floating
            base the robot moves itself, or one that nothing supports without ``hold_base``.
    """
    run = _Run.checked(
        robot, reference, duration, control_rate, command, feedforward, motor_bandwidth,
        error_bound, hold_base, on_tick,
    )  # fmt: skip
    q = robot.home.copy() if q0 is None else robot.check_q(q0, "q0").copy()
    qpos = robot.full_qpos(q)
    base = check_base(robot, run.hold_base, qpos)
    drives = joint_drives(robot)
    hold = None if base is None else BaseHold(robot.model, base)
    model = robot.model if hold is None else hold.model
    data = mujoco.MjData(model)
    data.qpos[:] = qpos
    if hold is not None:
        hold.start(data)
    mujoco.mj_forward(model, data)
    loop = _Loop(robot, model, data, drives, run, hold, task)
    problem.reset()  # the robot starts at rest: no motion of an earlier run to continue
    result = loop.run(problem, task, q)
    if result.status is not SimulationStatus.COMPLETED:
        warn(f"{robot.name}: {result.summary()}", InstabilityWarning)
    elif not result.within_bound:
        warn(tracking_diagnosis(robot.name, result), TrackingWarning)
    return result


@dataclasses.dataclass(frozen=True)
class _Run:
    """The checked options of one :func:`simulate` call."""

    pose_at: Callable[[float], np.ndarray]
    times: np.ndarray
    control_rate: float
    dt: float
    substeps: int
    command: str
    feedforward: bool
    motor_bandwidth: float
    error_bound: tuple[float, float] | None
    hold_base: bool
    on_tick: Callable[[int, int], None] | None

    @classmethod
    def checked(
        cls, robot, reference, duration, control_rate, command, feedforward, motor_bandwidth,
        error_bound, hold_base, on_tick,
    ) -> _Run:  # fmt: skip
        """The options of :func:`simulate`, checked; raises :class:`InvalidInput` by name."""
        if command not in COMMANDS:
            raise InvalidInput(f"command must be one of {COMMANDS}, got {command!r}")
        pose_at, start, duration = _reference(reference, duration)
        duration = positive(duration, "duration", unit="s")
        control_rate = positive(control_rate, "control_rate", unit="Hz")
        if on_tick is not None and not callable(on_tick):
            raise InvalidInput(f"on_tick must be callable or None, got {on_tick!r}")
        dt = 1.0 / control_rate
        ticks = round(duration * control_rate)
        if ticks < 1:
            raise InvalidInput(
                f"duration {duration:g} s is shorter than one control tick ({dt:g} s)"
            )
        return cls(
            pose_at=pose_at,
            times=start + np.arange(1, ticks + 1) * dt,
            control_rate=control_rate,
            dt=dt,
            substeps=_substeps(dt, robot.model.opt.timestep),
            command=command,
            feedforward=flag(feedforward, "feedforward"),
            motor_bandwidth=positive(motor_bandwidth, "motor_bandwidth", unit="rad/s"),
            error_bound=_error_bound(error_bound),
            hold_base=flag(hold_base, "hold_base"),
            on_tick=on_tick,
        )


def _reference(reference, duration) -> tuple[Callable[[float], np.ndarray], float, object]:
    """``(t -> T_d, start time, duration)`` of a path or a function of time."""
    if isinstance(reference, PosePath):
        duration = reference.duration if duration is None else duration
        return reference.pose, reference.start_time, duration
    if callable(reference):
        return reference, 0.0, duration
    raise InvalidInput(f"reference must be a trajectory.PosePath or t -> T, got {reference!r}")


def _error_bound(error_bound) -> tuple[float, float] | None:
    """``(position m, rotation rad)``, both positive (inf allowed), or None."""
    if error_bound is None:
        return None
    if not isinstance(error_bound, (tuple, list)) or len(error_bound) != 2:
        raise InvalidInput(
            f"error_bound must be (position m, rotation rad), both positive, or None; "
            f"got {error_bound!r}"
        )
    return (
        positive(error_bound[0], "error_bound[0]", allow_inf=True, unit="m"),
        positive(error_bound[1], "error_bound[1]", allow_inf=True, unit="rad"),
    )


def _substeps(dt: float, timestep: float) -> int:
    """Physics steps per control period; :class:`InvalidInput` unless a whole number."""
    substeps = dt / timestep
    if abs(substeps - round(substeps)) > 1e-6 or round(substeps) < 1:
        raise InvalidInput(
            f"the control period {dt:g} s must be a whole number of physics steps ({timestep:g} s)"
        )
    return round(substeps)


class _Loop:
    """One run's state: the physics, the controller, the monitors and the recorded rows."""

    def __init__(self, robot, model, data, drives, run: _Run, hold: BaseHold | None, task):
        self.robot, self.model, self.data, self.run_options = robot, model, data, run
        self.drives, self.hold = drives, hold
        self.controller = Controller(robot, drives, run.feedforward, run.motor_bandwidth)
        self.watch = InstabilityWatch(model, data)
        self.contacts = ContactLog(model, robot.joint_ids)
        self.frame = robot.frame(getattr(task, "frame_name", None))
        ticks, n = len(run.times), robot.dof
        self.q, self.q_command = np.empty((ticks, n)), np.empty((ticks, n))
        self.qpos = np.empty((ticks, model.nq))
        self.targets = np.empty((ticks, 4, 4))
        self.errors, self.reference_errors = np.empty((ticks, 2)), np.empty((ticks, 2))
        self.saturated = np.zeros(ticks, dtype=bool)
        self.T = np.eye(4)

    def run(self, problem, task, q: np.ndarray) -> SimulationResult:
        """Every tick until the end or a MuJoCo warning; the recorded result."""
        run, data = self.run_options, self.data
        q_command, velocity = q.copy(), np.zeros(self.robot.dof)
        for k, t in enumerate(run.times):
            T_d = run.pose_at(t)  # once a tick: a user's t -> T may be costly
            task.set_target(T_d)
            self.targets[k] = T_d
            q_command, velocity, clipped = self._command(problem, q_command, velocity)
            mujoco.mj_step(self.model, data, nstep=run.substeps)
            message = self.watch.check(data, t)
            if message:
                return self._result(k, SimulationStatus.UNSTABLE, message)
            self._record(k, t, q_command, clipped)
            if run.on_tick is not None:
                run.on_tick(k, len(run.times))
        return self._result(len(run.times), SimulationStatus.COMPLETED, "")

    def _command(
        self, problem, q_command: np.ndarray, velocity: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, bool]:
        """Step the problem, set the controls; the next reference, its velocity, clipping."""
        dt, data = self.run_options.dt, self.data
        if self.run_options.command == "position":
            q_measured = data.qpos[self.robot.qpos_indices].copy()
            q_command = q_measured + problem.step(q_measured.copy(), dt)
            still = np.zeros(self.robot.dof)
            ctrl, clipped = self.controller.controls(data, q_command, still, still)
        else:
            # The reference over this tick runs from q̂_k (now) to q̂_{k+1}: track it with
            # position, velocity and acceleration taken at the same instant.
            dq = problem.step(q_command, dt)
            previous, velocity = velocity, dq / dt
            accel = (velocity - previous) / dt
            ctrl, clipped = self.controller.controls(data, q_command, velocity, accel)
            q_command = q_command + dq
        data.ctrl[self.drives.actuators] = ctrl
        return q_command, velocity, clipped

    def _record(self, k: int, t: float, q_command: np.ndarray, clipped: bool) -> None:
        """Row ``k``: the measured state and pose, the errors, saturation, contacts."""
        model, data, robot = self.model, self.data, self.robot
        self.saturated[k] = clipped or self.controller.force_saturated(data)
        self.contacts.record(data, t)
        if self.hold is not None:
            self.hold.pin(data)
        mujoco.mj_kinematics(model, data)  # mj_step leaves poses of the previous state
        frame_pose(data, self.frame, self.T)
        self.errors[k] = pose_errors(self.T, self.targets[k])
        self.reference_errors[k] = pose_errors(robot.fk(q_command, self.frame), self.targets[k])
        self.q[k] = data.qpos[robot.qpos_indices]
        self.q_command[k] = q_command
        self.qpos[k] = data.qpos

    def _result(self, ticks: int, status: SimulationStatus, message: str) -> SimulationResult:
        """The first ``ticks`` rows as a :class:`SimulationResult`."""
        run = self.run_options
        return SimulationResult(
            times=run.times[:ticks],
            q=self.q[:ticks],
            q_command=self.q_command[:ticks],
            qpos=self.qpos[:ticks],
            targets=self.targets[:ticks],
            position_error=self.errors[:ticks, 0],
            rotation_error=self.errors[:ticks, 1],
            control_rate=run.control_rate,
            reference_position_error=self.reference_errors[:ticks, 0],
            reference_rotation_error=self.reference_errors[:ticks, 1],
            saturated=self.saturated[:ticks],
            drives=self.drives.kinds,
            error_bound=run.error_bound,
            status=status,
            message=message,
            contacts=self.contacts.contacts(),
            held_base="" if self.hold is None else self.hold.name,
        )


def frame_pose(data: mujoco.MjData, frame, T: np.ndarray) -> np.ndarray:
    """Write the pose of a resolved frame (site, body or geom) in ``data`` into ``T``.

    Args:
        data: A state whose poses are current (after ``mj_kinematics``).
        frame: A frame of the robot (:meth:`redik.Robot.frame`).
        T: The 4 × 4 output.

    Returns:
        ``T``.
    """
    rotation, position = {
        "site": (data.site_xmat, data.site_xpos),
        "geom": (data.geom_xmat, data.geom_xpos),
    }.get(frame.kind, (data.xmat, data.xpos))
    T[:3, :3] = rotation[frame.id].reshape(3, 3)
    T[:3, 3] = position[frame.id]
    return T
