r"""Which actuator drives each chain joint, and whether it is a position servo or a motor.

A MuJoCo actuator's force is ``gain · u + b₀ + b₁ l + b₂ \dot l`` on the transmission length
``l = gear · q`` (MuJoCo documentation, *Actuation model*): a ``<position>`` servo has
``gain = k_p``, ``b = [0, −k_p, −k_v]``; a ``<motor>`` has no bias. Those two are what
:func:`~redik.apps.sim.simulate` drives; anything else — velocity servos, integrated or
filtered activation, tendon or site transmissions, two actuators on one joint — is refused
by name with a :class:`~redik.core.exceptions.ModelError`.
"""

from __future__ import annotations

import dataclasses

import mujoco
import numpy as np

from redik.core.exceptions import ModelError
from redik.kinematics.robot import Robot

SERVO, MOTOR = "position", "motor"


@dataclasses.dataclass(frozen=True)
class JointDrives:
    r"""How :func:`~redik.apps.sim.simulate` drives each chain joint: one actuator per joint.

    Attributes:
        actuators: Actuator index of each chain joint (``robot.joint_names`` order).
        kinds: ``"position"`` (a servo ``k_p (u − l) − k_v \dot l``) or ``"motor"``
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
        """``(n,)`` True where the joint's actuator is a position servo."""
        return np.array([kind == SERVO for kind in self.kinds], dtype=bool)

    @property
    def lead(self) -> np.ndarray:
        """``k_v / k_p`` of each servo (seconds; 0 for a motor).

        A servo following a ramp ``q̂ = v t`` settles ``(k_v / k_p) v`` behind it, so its
        setpoint is led by that much.
        """
        return self.kv / self.gain


def joint_drives(robot: Robot) -> JointDrives:
    """The actuator driving each chain joint, and whether it is a position servo or a motor.

    Args:
        robot: The robot; every joint it moves needs exactly one actuator acting on it
            directly (a joint transmission).

    Returns:
        The actuators, their kinds and gains, in ``robot.joint_names`` order.

    Raises:
        ModelError: a chain joint has no actuator acting on it directly (only through a
            tendon or site, or none), more than one, or one of a kind
            :func:`~redik.apps.sim.simulate` cannot drive; the message names it.
    """
    model = robot.model
    by_joint, indirect = _actuators_by_joint(model)
    indices = [_the_actuator(robot, name, by_joint, indirect) for name in robot.joint_names]
    actuators = np.array(indices, dtype=int)
    kinds = tuple(_actuator_kind(model, a) for a in actuators)
    servo = np.array([kind == SERVO for kind in kinds])
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


def actuator_name(model: mujoco.MjModel, a: int) -> str:
    """The actuator's name, or ``#a`` for an unnamed one."""
    return mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_ACTUATOR, a) or f"#{a}"


def _actuators_by_joint(model: mujoco.MjModel) -> tuple[dict[int, list[int]], list[str]]:
    """Actuators with a joint transmission by joint id, and the others described by name."""
    by_joint: dict[int, list[int]] = {}
    indirect = []
    for a in range(model.nu):
        if model.actuator_trntype[a] == mujoco.mjtTrn.mjTRN_JOINT:
            by_joint.setdefault(int(model.actuator_trnid[a, 0]), []).append(a)
        else:
            trn = mujoco.mjtTrn(model.actuator_trntype[a]).name.removeprefix("mjTRN_").lower()
            indirect.append(f"{actuator_name(model, a)!r} ({trn})")
    return by_joint, indirect


def _the_actuator(
    robot: Robot, name: str, by_joint: dict[int, list[int]], indirect: list[str]
) -> int:
    """The one actuator on joint ``name``; :class:`ModelError` for none or several."""
    model = robot.model
    acting = by_joint.get(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name), [])
    if not acting:
        through = f"; actuators without a joint transmission: {', '.join(indirect)}"
        raise ModelError(
            f"joint {name!r} of {robot.name!r} has no actuator; simulate() needs one "
            f"position servo or motor per chain joint{through if indirect else ''}"
        )
    if len(acting) > 1:
        names = ", ".join(repr(actuator_name(model, a)) for a in acting)
        raise ModelError(
            f"joint {name!r} of {robot.name!r} is driven by {len(acting)} actuators "
            f"({names}); simulate() drives one per joint"
        )
    return acting[0]


def _actuator_kind(model: mujoco.MjModel, a: int) -> str:
    """``"position"`` or ``"motor"``; raises :class:`ModelError` for any other actuator."""
    name = actuator_name(model, a)
    dyn, gain = model.actuator_dyntype[a], model.actuator_gaintype[a]
    if dyn != mujoco.mjtDyn.mjDYN_NONE:
        raise ModelError(
            f"actuator {name!r} has activation dynamics ({mujoco.mjtDyn(dyn).name}: an "
            f"integrated velocity servo, a filtered or a muscle actuator); simulate() drives "
            f"position servos and torque motors without activation state"
        )
    if gain != mujoco.mjtGain.mjGAIN_FIXED or model.actuator_gainprm[a, 0] == 0.0:
        raise ModelError(f"actuator {name!r} has no fixed gain; simulate() cannot drive it")
    if model.actuator_gear[a, 0] == 0.0:
        raise ModelError(f"actuator {name!r} has gear 0: it applies no torque to its joint")
    if model.actuator_biastype[a] == mujoco.mjtBias.mjBIAS_NONE:
        return MOTOR
    return _affine_kind(model, a, name)


def _affine_kind(model: mujoco.MjModel, a: int, name: str) -> str:
    """``"position"`` for an affine bias ``[0, −k_p, −k_v]``; :class:`ModelError` otherwise."""
    kp, biasprm = model.actuator_gainprm[a, 0], model.actuator_biasprm[a]
    kv = -biasprm[2]
    if model.actuator_biastype[a] == mujoco.mjtBias.mjBIAS_AFFINE and biasprm[0] == 0.0:
        if kp > 0.0 and np.isclose(biasprm[1], -kp) and kv >= 0.0:
            return SERVO
        if biasprm[1] == 0.0 and np.isclose(kv, kp):
            raise ModelError(
                f"actuator {name!r} is a velocity servo (kv = {kv:g}, no position gain); "
                f"simulate() drives position servos and torque motors"
            )
    raise ModelError(
        f"actuator {name!r} has an affine bias {biasprm[:3].tolist()} that is neither a "
        f"position servo [0, -kp, -kv] nor none (a motor); simulate() cannot drive it"
    )
