r"""Headless closed-loop simulation: the IK problem as a controller, MuJoCo as the plant.

At every control tick ``k`` (period ``dt = 1 / control_rate``) :func:`simulate`

1. reads the measured joint values ``q_k`` and velocities ``q̇_k`` from the simulation,
2. moves the tracked task's target to the reference pose ``T_d(t_k)``,
3. asks the QP for a step ``Δq = problem.step(q, dt)`` (at which ``q``: see 4),
4. drives each chain joint's actuator (:func:`joint_drives` reads which kind it is), either

   * ``command="integrate"`` (default): the joint reference is the integral of the IK
     velocity, ``q̂_{k+1} = q̂_k + Δq(q̂_k)``; over the tick the actuators track ``q̂_k``
     with velocity ``\dot{\hat q} = Δq / dt`` and acceleration ``\ddot{\hat q}`` its
     backward difference — all three at the same instant, the start of the tick — with
     computed-torque feed-forward (Siciliano et al., *Robotics*, §8.5),

     .. math::

         τ_{ff} = M(q)\, \ddot{\hat q} + c(q, \dot q) + g(q) − τ_{passive}(q, \dot q),

     MuJoCo's inverse dynamics (``mj_inverse`` at the measured state with
     ``qacc = \ddot{\hat q}``: inertia, Coriolis, gravity, joint damping and springs).

     - a **position servo** (MuJoCo ``position``/``general`` with
       ``biasprm = [0, −k_p, −k_v]``) applies ``k_p (u − q) − k_v q̇``; it gets
       ``u = q̂ + \frac{k_v}{k_p} \dot{\hat q} + \frac{1}{k_p} τ_{ff}``, so its torque is
       ``k_p (q̂ − q) + k_v (\dot{\hat q} − q̇) + τ_{ff}``: its own PD on the tracking error
       plus the torque the motion needs. Without the feed-forward a servo sags under
       gravity by ``g(q) / k_p`` (Menagerie's arms have no ``gravcomp``) and lags a moving
       reference by about ``k_v / k_p`` seconds;
     - a **motor** (torque actuator, ``gaintype`` fixed, no bias) gets the computed-torque
       law ``τ = τ_{ff}`` evaluated with
       ``qacc = \ddot{\hat q} + K_d (\dot{\hat q} − q̇) + K_p (q̂ − q)``, ``K_p = ω²``,
       ``K_d = 2ω`` (critically damped error dynamics of bandwidth ``ω = motor_bandwidth``),
       and ``u = τ / (\text{gear} · \text{gain})``;

   * ``command="position"``: ``q̂ = q_k + Δq(q_k)`` from the *measured* state — feedback
     through the IK itself — and the same laws with zero reference velocity and
     acceleration (the servo then only sees the small offset ``Δq`` and lags more);

5. advances the physics by ``mj_step`` until the next tick.

MuJoCo clips ``u`` to ``ctrlrange`` and the actuator force to ``forcerange``: a tick at which
either happened is recorded as saturated (:attr:`SimulationResult.saturated`), and the
feed-forward is then only partly applied. Actuators :func:`simulate` cannot drive — velocity
servos, integrated or filtered activation, tendon or site transmissions, two actuators on
one joint — are refused by name (:class:`~redik.core.exceptions.ModelError`).

No window is opened: the loop is pure computation, and pictures come afterwards from the
recorded states (:func:`plot_tracking`; videos by :func:`redik.apps.render.render_states` —
set ``MUJOCO_GL=egl`` before MuJoCo is first imported).

Tracking error is the pose error (:mod:`redik.core.conventions`) of the simulated end-effector
against the reference at the same instant. It has two parts, both recorded: the IK's own
error (the FK of the joint reference ``q̂`` against the reference pose: a path the QP cannot
follow, near a singularity or a joint or velocity limit) and the servo error (the joints
lagging ``q̂``). When the tracking error exceeds ``error_bound`` :func:`simulate` warns
(:class:`TrackingWarning`) with that split and the saturation count.

Measured (``redik run specs/iiwa14_tracking.py --fast``, recorded in
``specs/baselines/iiwa14_tracking.json``; ``tests/test_sim.py`` asserts the bound):
iiwa14 tracing a 10 cm circle in 4 s (quintic timing, peak speed 0.3 m/s) at 100 Hz with
``"integrate"`` stays within 1.3 mm and 3.4e-4 rad of the reference and ends within
0.001 mm; the stated bound is 3 mm, 0.01 rad and 0.05 mm at the end. The same circle on
MuJoCo Menagerie's arms (servos with ``k_p`` = 500–4500, ``k_v = k_p / 10`` or ``/ 20``, no
``gravcomp``, ``forcerange`` down to ±12 N·m), from a non-singular start, with the
inverse-dynamics feed-forward (without it): iiwa14 1.1 mm (24 mm), Panda 1.1 mm (3.6 mm),
Gen3 1.2 mm (6.7 mm). Started at Menagerie's Panda ``home`` (``q₂ = 0``: axes 1 and 3
collinear) the circle's top, with the orientation held, is out of the arm's reach: the best
of 40 ``solve`` starts misses it by 39 mm (elbow stretched, ``q₄ ≈ −0.47``), and the IK
reference misses it by that much. At that fold the undamped step jumped across the
singularity every tick at the 2 rad/s box and the arm missed by 49 mm; a single-level
problem with ``Problem(..., step_damping=10)`` (:meth:`redik.Problem.step`) gives a smooth
reference and a 38.8 mm miss, the unavoidable one (with the posture task at priority 1 it
does not: the posture reverses in the turning null space, see :meth:`redik.Problem.step`).
From Gen3's ``home`` the circle is reachable but passes near a wrist singularity
(``σ_min`` = 0.04) where the QP's joint speeds reach 4.2 rad/s: at 5 rad/s the reference
follows it within 0.04 mm, at 2 rad/s it misses by 26 mm and the arm by 84 mm (23 and
24 mm single-level, damped). The warning blames the IK in both.
``tests/test_sim.py`` runs Menagerie-like servos built from the bundled iiwa14, the iiwa14
on torque motors and gymnasium's Pusher arm (torque motors).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from pathlib import Path

import mujoco
import numpy as np

from redik.apps.plot import new_figure, save_figure
from redik.apps.trajectory import PosePath
from redik.core.exceptions import InvalidInput, ModelError, TrackingWarning, warn
from redik.core.validate import flag, positive
from redik.kinematics.robot import Robot
from redik.lie import pose_errors

COMMANDS = ("position", "integrate")

DEFAULT_ERROR_BOUND = (5e-3, 5e-2)
"""Tracking error (m, rad) above which :func:`simulate` warns, unless told otherwise."""


@dataclasses.dataclass
class SimulationResult:
    """What a closed-loop run recorded, one row per control tick.

    Attributes:
        times: (N,) tick times in seconds (each row is the state once the physics reached it).
        q: (N, n) measured chain joint values.
        q_command: (N, n) joint references ``q̂`` the actuators tracked.
        qpos: (N, nq) full simulation state, for rendering the run afterwards.
        targets: (N, 4, 4) reference poses.
        position_error: (N,) ``‖p_d − p‖`` of the simulated end-effector, metres.
        rotation_error: (N,) angle of ``Rᵀ R_d``, radians.
        reference_position_error: (N,) the same for the FK of ``q̂``: the IK's own share.
        reference_rotation_error: (N,) likewise, radians.
        saturated: (N,) True where a control was clipped to its ``ctrlrange`` or an
            actuator force to its ``forcerange`` during the tick.
        drives: The kind of actuator driving each chain joint (``"position"``/``"motor"``).
        control_rate: Control ticks per second.
        error_bound: ``(position m, rotation rad)`` the run was checked against, or None.
    """

    times: np.ndarray
    q: np.ndarray
    q_command: np.ndarray
    qpos: np.ndarray
    targets: np.ndarray
    position_error: np.ndarray
    rotation_error: np.ndarray
    control_rate: float
    reference_position_error: np.ndarray | None = None
    reference_rotation_error: np.ndarray | None = None
    saturated: np.ndarray | None = None
    drives: tuple[str, ...] = ()
    error_bound: tuple[float, float] | None = None

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
    def rms_rotation_error(self) -> float:
        return float(np.sqrt(np.mean(self.rotation_error**2)))

    @property
    def final_position_error(self) -> float:
        return float(self.position_error[-1])

    @property
    def final_rotation_error(self) -> float:
        return float(self.rotation_error[-1])

    @property
    def saturation_fraction(self) -> float:
        """Fraction of ticks during which an actuator saturated."""
        return 0.0 if self.saturated is None else float(np.mean(self.saturated))

    @property
    def within_bound(self) -> bool:
        """True when no tick left the reference by more than :attr:`error_bound` (or none)."""
        if self.error_bound is None:
            return True
        position, rotation = self.error_bound
        return self.max_position_error <= position and self.max_rotation_error <= rotation

    def summary(self) -> str:
        line = (
            f"{len(self.times)} ticks at {self.control_rate:g} Hz over {self.times[-1]:.2f} s: "
            f"tracking error max {self.max_position_error * 1e3:.3f} mm / "
            f"{self.max_rotation_error:.2e} rad, rms {self.rms_position_error * 1e3:.3f} mm / "
            f"{self.rms_rotation_error:.2e} rad, final {self.final_position_error * 1e3:.4f} mm"
            f" / {self.final_rotation_error:.2e} rad"
        )
        if self.reference_position_error is not None:
            line += (
                f"; IK reference alone max {self.reference_position_error.max() * 1e3:.3f} mm"
                f" / {self.reference_rotation_error.max():.2e} rad"
            )
        if self.saturation_fraction > 0.0:
            line += f"; actuators saturated in {100 * self.saturation_fraction:.1f} % of ticks"
        return line


@dataclasses.dataclass(frozen=True)
class JointDrives:
    """How :func:`simulate` drives each chain joint: one actuator per joint, by kind.

    Attributes:
        actuators: Actuator index of each chain joint (``robot.joint_names`` order).
        kinds: ``"position"`` (a servo ``k_p (u − l) − k_v \\dot l``) or ``"motor"``
            (force ``gain · u``) per joint.
        gear: Transmission gear of each actuator (joint torque = gear × actuator force).
        gain: ``gainprm[0]``: ``k_p`` of a servo, the force per unit control of a motor.
        kv: ``−biasprm[2]`` of a servo (0 for a motor).
    """

    actuators: np.ndarray
    kinds: tuple[str, ...]
    gear: np.ndarray
    gain: np.ndarray
    kv: np.ndarray

    @property
    def servo(self) -> np.ndarray:
        return np.array([kind == "position" for kind in self.kinds], dtype=bool)

    @property
    def lead(self) -> np.ndarray:
        """``k_v / k_p`` of each servo (seconds; 0 for a motor): a servo following a ramp
        ``q̂ = v t`` settles ``(k_v / k_p) v`` behind, so its setpoint is led by that much."""
        return self.kv / self.gain


def _actuator_name(model: mujoco.MjModel, a: int) -> str:
    return mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_ACTUATOR, a) or f"#{a}"


def _actuator_kind(model: mujoco.MjModel, a: int) -> str:
    """``"position"`` or ``"motor"``; raises :class:`ModelError` for any other actuator."""
    name = _actuator_name(model, a)
    dyn, gain, bias = (
        model.actuator_dyntype[a],
        model.actuator_gaintype[a],
        model.actuator_biastype[a],
    )
    gainprm, biasprm = model.actuator_gainprm[a], model.actuator_biasprm[a]
    if dyn != mujoco.mjtDyn.mjDYN_NONE:
        raise ModelError(
            f"actuator {name!r} has activation dynamics ({mujoco.mjtDyn(dyn).name}: an "
            f"integrated velocity servo, a filtered or a muscle actuator); simulate() drives "
            f"position servos and torque motors without activation state"
        )
    if gain != mujoco.mjtGain.mjGAIN_FIXED or gainprm[0] == 0.0:
        raise ModelError(f"actuator {name!r} has no fixed gain; simulate() cannot drive it")
    if model.actuator_gear[a, 0] == 0.0:
        raise ModelError(f"actuator {name!r} has gear 0: it applies no torque to its joint")
    if bias == mujoco.mjtBias.mjBIAS_NONE:
        return "motor"
    kp, kv = gainprm[0], -biasprm[2]
    if bias == mujoco.mjtBias.mjBIAS_AFFINE and biasprm[0] == 0.0:
        if kp > 0.0 and np.isclose(biasprm[1], -kp) and kv >= 0.0:
            return "position"
        if biasprm[1] == 0.0 and np.isclose(kv, kp):
            raise ModelError(
                f"actuator {name!r} is a velocity servo (kv = {kv:g}, no position gain); "
                f"simulate() drives position servos and torque motors"
            )
    raise ModelError(
        f"actuator {name!r} has an affine bias {biasprm[:3].tolist()} that is neither a "
        f"position servo [0, -kp, -kv] nor none (a motor); simulate() cannot drive it"
    )


def joint_drives(robot: Robot) -> JointDrives:
    """The actuator driving each chain joint, and whether it is a position servo or a motor.

    A MuJoCo actuator's force is ``gain · u + b₀ + b₁ l + b₂ \\dot l`` on the transmission
    length ``l = gear · q`` (MuJoCo documentation, *Actuation model*): a ``<position>``
    servo has ``gain = k_p``, ``b = [0, −k_p, −k_v]``; a ``<motor>`` has no bias.

    Raises:
        ModelError: a chain joint has no actuator acting on it directly (only through a
            tendon or site, or none), more than one, or one of a kind :func:`simulate`
            cannot drive; the message names it.
    """
    model = robot.model
    by_joint: dict[int, list[int]] = {}
    indirect = []
    for a in range(model.nu):
        if model.actuator_trntype[a] == mujoco.mjtTrn.mjTRN_JOINT:
            by_joint.setdefault(int(model.actuator_trnid[a, 0]), []).append(a)
        else:
            trn = mujoco.mjtTrn(model.actuator_trntype[a]).name.removeprefix("mjTRN_").lower()
            indirect.append(f"{_actuator_name(model, a)!r} ({trn})")
    indices = []
    for name in robot.joint_names:
        joint = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
        acting = by_joint.get(joint, [])
        if not acting:
            through = f"; actuators without a joint transmission: {', '.join(indirect)}"
            raise ModelError(
                f"joint {name!r} of {robot.name!r} has no actuator; simulate() needs one "
                f"position servo or motor per chain joint{through if indirect else ''}"
            )
        if len(acting) > 1:
            names = ", ".join(repr(_actuator_name(model, a)) for a in acting)
            raise ModelError(
                f"joint {name!r} of {robot.name!r} is driven by {len(acting)} actuators "
                f"({names}); simulate() drives one per joint"
            )
        indices.append(acting[0])
    actuators = np.array(indices, dtype=int)
    kinds = tuple(_actuator_kind(model, a) for a in actuators)
    servo = np.array([kind == "position" for kind in kinds])
    return JointDrives(
        actuators=actuators,
        kinds=kinds,
        gear=model.actuator_gear[actuators, 0].copy(),
        gain=model.actuator_gainprm[actuators, 0].copy(),
        kv=np.where(servo, -model.actuator_biasprm[actuators, 2], 0.0),
    )


def actuator_indices(robot: Robot) -> np.ndarray:
    """The actuator driving each chain joint (one per joint, in ``robot.joint_names`` order).

    Raises:
        ModelError: as :func:`joint_drives`.
    """
    return joint_drives(robot).actuators


class _Controller:
    """Turns a joint reference ``(q̂, \\dot{\\hat q}, \\ddot{\\hat q})`` into actuator controls by
    the laws of the module docstring, from the measured state; notes saturation."""

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
        a = drives.actuators
        self.ctrl_low = np.where(
            model.actuator_ctrllimited[a], model.actuator_ctrlrange[a, 0], -np.inf
        )
        self.ctrl_high = np.where(
            model.actuator_ctrllimited[a], model.actuator_ctrlrange[a, 1], np.inf
        )
        limited = model.actuator_forcelimited[drives.actuators].astype(bool)
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
        """``M(q) q̈ + c(q, q̇) + g(q) − τ_passive`` on the chain joints at the measured state,
        by ``mj_inverse`` on a scratch copy (the other joints' accelerations taken as 0)."""
        scratch = self.scratch
        scratch.qpos[:], scratch.qvel[:] = data.qpos, data.qvel
        if self.model.na:
            scratch.act[:] = data.act
        scratch.qacc[:] = 0.0
        scratch.qacc[self.dofs] = qacc
        mujoco.mj_inverse(self.model, scratch)
        return scratch.qfrc_inverse[self.dofs].copy()

    def _unreachable_inertia(self, torque: np.ndarray, accel: np.ndarray) -> np.ndarray:
        """The part of the inertial feed-forward ``M q̈`` (just computed by
        :meth:`inverse_dynamics`) that would push a joint's torque past its actuator's range.

        A reference that chatters (near a singularity the QP's joint velocities flip from
        tick to tick) asks for accelerations no actuator can give; sent anyway, they saturate
        the actuator and take away the feedback and gravity terms that keep the arm on the
        path. So the inertial term is scaled down first, per joint, to fit the range.
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
        """The controls of the chain's actuators, and whether ``ctrlrange`` clips any."""
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
            tau = self.inverse_dynamics(data, qacc)
            motor_u = tau / (g * drives.gain)
            u[~servo] = motor_u[~servo]
        clipped = bool(np.any((u < self.ctrl_low) | (u > self.ctrl_high)))
        return np.clip(u, self.ctrl_low, self.ctrl_high), clipped

    def force_saturated(self, data: mujoco.MjData) -> bool:
        """True when an actuator force (or a joint's actuator torque) sits at its range."""
        force = data.actuator_force[self.drives.actuators]
        torque = data.qfrc_actuator[self.dofs]
        tol = 1e-9
        return bool(
            np.any((force <= self.force_low + tol) | (force >= self.force_high - tol))
            or np.any((torque <= self.joint_low + tol) | (torque >= self.joint_high - tol))
        )


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
    on_tick: Callable[[int, int], None] | None = None,
) -> SimulationResult:
    """Run the closed loop described in the module docstring.

    Args:
        robot: The robot; its model needs a position servo or a torque motor on every chain
            joint (:func:`joint_drives`).
        problem: A :class:`redik.Problem` whose ``step(q, dt)`` returns ``Δq``. It is reset
            (:meth:`redik.Problem.reset`) at the start: the run starts at rest and does not
            continue the motion of an earlier run, so the same problem simulated twice gives
            the same result.
        task: The task of ``problem`` that tracks the reference (it must have
            ``set_target(T)``, like :class:`redik.FrameTask`).
        reference: A path (:class:`~redik.apps.trajectory.CartesianPath`,
            :class:`~redik.apps.trajectory.CircularPath`) or a function ``t -> T_d``.
        duration: Seconds to simulate; default the path's duration.
        q0: Initial joint values (default ``robot.home``); the arm starts at rest there.
        control_rate: Control ticks per second; the physics step must divide the period.
        command: ``"position"`` or ``"integrate"`` (module docstring).
        feedforward: Add the inverse-dynamics torque ``τ_ff`` to the position servos'
            commands (gravity, Coriolis, inertia, joint damping). Motors always use it: a
            torque actuator has no other way to hold the arm up.
        motor_bandwidth: ``ω`` (rad/s) of the motors' computed-torque law
            (``K_p = ω²``, ``K_d = 2ω``); keep ``ω · dt`` well below 1.
        error_bound: ``(position m, rotation rad)``: warn (:class:`TrackingWarning`) when the
            tracking error exceeds either; None for no check.
        on_tick: Called as ``on_tick(k, total)`` after every tick (e.g. a progress bar).

    Raises:
        InvalidInput: bad duration, rate, command, bandwidth or bound; a control period that
            is not a whole number of physics steps.
        ModelError: a chain joint without an actuator :func:`simulate` can drive.
    """
    if command not in COMMANDS:
        raise InvalidInput(f"command must be one of {COMMANDS}, got {command!r}")
    if isinstance(reference, PosePath):
        pose_at, start = reference.pose, reference.start_time
        duration = reference.duration if duration is None else duration
    elif callable(reference):
        pose_at, start = reference, 0.0
    else:
        raise InvalidInput(f"reference must be a trajectory.PosePath or t -> T, got {reference!r}")
    duration = positive(duration, "duration", unit="s")
    control_rate = positive(control_rate, "control_rate", unit="Hz")
    motor_bandwidth = positive(motor_bandwidth, "motor_bandwidth", unit="rad/s")
    feedforward = flag(feedforward, "feedforward")
    if error_bound is not None:
        if not isinstance(error_bound, (tuple, list)) or len(error_bound) != 2:
            raise InvalidInput(
                f"error_bound must be (position m, rotation rad), both positive, or None; "
                f"got {error_bound!r}"
            )
        error_bound = (
            positive(error_bound[0], "error_bound[0]", allow_inf=True, unit="m"),
            positive(error_bound[1], "error_bound[1]", allow_inf=True, unit="rad"),
        )
    if on_tick is not None and not callable(on_tick):
        raise InvalidInput(f"on_tick must be callable or None, got {on_tick!r}")
    dt = 1.0 / control_rate
    substeps = dt / robot.model.opt.timestep
    if abs(substeps - round(substeps)) > 1e-6 or round(substeps) < 1:
        raise InvalidInput(
            f"the control period {dt:g} s must be a whole number of physics steps "
            f"({robot.model.opt.timestep:g} s)"
        )
    substeps = round(substeps)
    q = robot.home.copy() if q0 is None else robot.check_q(q0, "q0").copy()
    drives = joint_drives(robot)
    controller = _Controller(robot, drives, feedforward, motor_bandwidth)
    qpos_adr = robot.qpos_indices

    data = mujoco.MjData(robot.model)
    data.qpos[:] = robot.full_qpos(q)
    mujoco.mj_forward(robot.model, data)
    T = np.eye(4)
    ee = robot.frame(getattr(task, "frame_name", None))

    ticks = round(duration * control_rate)
    times = start + np.arange(1, ticks + 1) * dt
    q_log, command_log = np.empty((ticks, robot.dof)), np.empty((ticks, robot.dof))
    qpos_log = np.empty((ticks, robot.model.nq))
    targets = np.empty((ticks, 4, 4))
    position_error, rotation_error = np.empty(ticks), np.empty(ticks)
    reference_error = np.empty((ticks, 2))
    saturated = np.zeros(ticks, dtype=bool)
    q_command = q.copy()
    velocity = np.zeros(robot.dof)
    problem.reset()  # the arm starts at rest: no motion of an earlier run to continue
    still = np.zeros(robot.dof)
    for k, t in enumerate(times):
        q_measured = data.qpos[qpos_adr].copy()
        # Aim at where the reference will be when this command has been applied.
        T_d = pose_at(t)  # once a tick: a user's t -> T may be costly
        task.set_target(T_d)
        targets[k] = T_d
        if command == "position":
            q_command = q_measured + problem.step(q_measured.copy(), dt)
            ctrl, clipped = controller.controls(data, q_command, still, still)
        else:
            # The reference over this tick runs from q̂_k (now) to q̂_{k+1} (at t): track it
            # with position, velocity and acceleration taken at the same instant.
            dq = problem.step(q_command, dt)
            previous_velocity, velocity = velocity, dq / dt
            accel = (velocity - previous_velocity) / dt
            ctrl, clipped = controller.controls(data, q_command, velocity, accel)
            q_command = q_command + dq
        data.ctrl[drives.actuators] = ctrl
        mujoco.mj_step(robot.model, data, nstep=substeps)
        saturated[k] = clipped or controller.force_saturated(data)
        mujoco.mj_kinematics(robot.model, data)  # mj_step leaves poses of the previous state
        _site_pose(data, ee, T)
        position_error[k], rotation_error[k] = pose_errors(T, targets[k])
        reference_error[k] = pose_errors(robot.fk(q_command, ee), targets[k])
        q_log[k] = data.qpos[qpos_adr]
        command_log[k] = q_command
        qpos_log[k] = data.qpos
        if on_tick is not None:
            on_tick(k, ticks)
    result = SimulationResult(
        times=times,
        q=q_log,
        q_command=command_log,
        qpos=qpos_log,
        targets=targets,
        position_error=position_error,
        rotation_error=rotation_error,
        control_rate=control_rate,
        reference_position_error=reference_error[:, 0],
        reference_rotation_error=reference_error[:, 1],
        saturated=saturated,
        drives=drives.kinds,
        error_bound=error_bound,
    )
    if not result.within_bound:
        warn(_diagnosis(robot.name, result), TrackingWarning)
    return result


def _diagnosis(name: str, result: SimulationResult) -> str:
    """The :class:`TrackingWarning` message: the errors, and which part is to blame."""
    position, rotation = result.error_bound
    message = (
        f"{name}: tracking error exceeds the bound {position * 1e3:g} mm / {rotation:g} rad: "
        f"{result.summary()}."
    )
    if (
        result.reference_position_error.max() > 0.5 * position
        or result.reference_rotation_error.max() > 0.5 * rotation
    ):
        message += (
            " The IK reference itself leaves the path: the QP cannot follow it there (a "
            "singularity, a joint or velocity limit); change the path, the start posture or "
            "the limits."
        )
    if result.saturation_fraction > 0.0:
        message += (
            " Actuators saturated (ctrlrange or forcerange): the servos could not apply the "
            "torque the motion needs."
        )
    return message


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
