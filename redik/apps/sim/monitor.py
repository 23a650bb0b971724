"""What MuJoCo reports during a run: instability warnings, and the contacts of the robot.

**Instability.** MuJoCo checks the state at every physics step; on a NaN, inf or value beyond
``mjMAXVAL`` in ``qpos``, ``qvel`` or ``qacc`` it counts a warning in ``data.warning``
(``mjWARN_BADQPOS``, ``mjWARN_BADQVEL``, ``mjWARN_BADQACC``) and resets the state to ``qpos0``,
and on a bad control it counts ``mjWARN_BADCTRL`` and zeroes the controls; when the constraint
or contact arena overflows it counts ``mjWARN_CNSTRFULL`` / ``mjWARN_CONTACTFULL`` and drops
constraints. A run carried on past any of these would record a reset or wrong state as if it
were motion. :class:`InstabilityWatch` compares the counters after every tick
(MuJoCo documentation, *Simulation: diagnostics*, ``mjtWarning``).

**Contacts.** :class:`ContactLog` reads MuJoCo's contacts after every tick and keeps those
that involve the robot: between two of its bodies (``"self"``) and between one of its bodies
and anything else (``"world"``). The robot's bodies are the kinematic trees (``body_rootid``)
that hold its joints, base included.
"""

from __future__ import annotations

import mujoco
import numpy as np

from redik.apps.sim.drives import actuator_name
from redik.apps.sim.result import Contact

W = mujoco.mjtWarning
WATCHED = {
    W.mjWARN_BADQPOS: ("a NaN, inf or huge value in qpos", "qpos"),
    W.mjWARN_BADQVEL: ("a NaN, inf or huge value in qvel", "dof"),
    W.mjWARN_BADQACC: ("a NaN, inf or huge value in qacc", "dof"),
    W.mjWARN_BADCTRL: ("a NaN, inf or huge control", "actuator"),
    W.mjWARN_CNSTRFULL: ("a full constraint arena (constraints dropped)", ""),
    W.mjWARN_CONTACTFULL: ("a full contact arena (contacts dropped)", ""),
}
"""The ``mjtWarning`` members that stop a run: what each means, and what its index names."""

RESET = {W.mjWARN_BADQPOS, W.mjWARN_BADQVEL, W.mjWARN_BADQACC}
"""The warnings after which MuJoCo has reset the state (unless auto-reset is disabled)."""

HINT = (
    "the physics diverged: a stiff actuator or a light body for the integrator (try "
    "<option integrator='implicitfast'/> or a smaller timestep), or a controller asking "
    "for more than the model can do"
)


class InstabilityWatch:
    """Notices a MuJoCo warning that appeared since the last look.

    Args:
        model: The simulated model.
        data: The simulation's data; its counters at construction are the baseline.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData):
        self.model = model
        self.seen = data.warning.number.copy()

    def check(self, data: mujoco.MjData, t: float) -> str:
        """The message for a watched warning raised since the last check, or "".

        Args:
            data: The simulation's data after a tick.
            t: The time the tick was to reach (s).
        """
        raised = [w for w in WATCHED if data.warning.number[w] > self.seen[w]]
        self.seen = data.warning.number.copy()
        if not raised:
            return ""
        warning = raised[0]
        meaning, _ = WATCHED[warning]
        where = self._where(warning, int(data.warning.lastinfo[warning]))
        reset = " and reset the state" if warning in RESET else ""
        return (
            f"MuJoCo found {meaning}{where} in the tick ending at t = {t:.3f} s "
            f"({mujoco.mjtWarning(warning).name}){reset}; {HINT}"
        )

    def _where(self, warning: int, index: int) -> str:
        """`` (dof 3, joint 'joint4')``: what the warning's ``lastinfo`` index names."""
        model, kind = self.model, WATCHED[warning][1]
        if kind == "qpos" and 0 <= index < model.nq:
            joint = int(np.searchsorted(model.jnt_qposadr, index, side="right") - 1)
            return f" (qpos[{index}], joint {_joint_name(model, joint)!r})"
        if kind == "dof" and 0 <= index < model.nv:
            return f" (dof {index}, joint {_joint_name(model, int(model.dof_jntid[index]))!r})"
        if kind == "actuator" and 0 <= index < model.nu:
            return f" (actuator {actuator_name(model, index)!r})"
        return ""


class ContactLog:
    """The contacts of the robot, tick by tick, grouped by body pair.

    Args:
        model: The simulated model.
        joints: Ids of the robot's joints; the trees that hold them are the robot.
    """

    def __init__(self, model: mujoco.MjModel, joints: np.ndarray):
        self.model = model
        roots = np.unique(model.body_rootid[model.jnt_bodyid[np.asarray(joints, dtype=int)]])
        self.robot = np.isin(model.body_rootid, roots)
        self.robot[0] = False
        self.pairs: dict[tuple[int, int], tuple[list[float], list[float]]] = {}

    def record(self, data: mujoco.MjData, t: float) -> None:
        """Add the contacts of ``data`` (touching or penetrating) at time ``t``."""
        n = data.ncon
        if n == 0:
            return
        dist = data.contact.dist[:n]
        touching = dist <= 0.0
        bodies = self.model.geom_bodyid[data.contact.geom[:n][touching]]
        robot = self.robot[bodies]
        mine = robot.any(axis=1)
        deepest: dict[tuple[int, int], float] = {}
        for (b1, b2), (r1, r2), depth in zip(
            bodies[mine], robot[mine], -dist[touching][mine], strict=True
        ):
            pair = (int(b1), int(b2)) if r1 and (not r2 or b1 <= b2) else (int(b2), int(b1))
            deepest[pair] = max(deepest.get(pair, 0.0), float(depth))
        for pair, depth in deepest.items():
            times, depths = self.pairs.setdefault(pair, ([], []))
            times.append(t)
            depths.append(depth)

    def contacts(self) -> tuple[Contact, ...]:
        """Every pair that touched, deepest first."""
        found = [
            Contact(
                body1=_body_name(self.model, b1),
                body2=_body_name(self.model, b2),
                kind="self" if self.robot[b2] else "world",
                times=np.array(times),
                depth=np.array(depths),
            )
            for (b1, b2), (times, depths) in self.pairs.items()
        ]
        return tuple(sorted(found, key=lambda contact: -contact.max_depth))


def _joint_name(model: mujoco.MjModel, joint: int) -> str:
    return mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, joint) or f"#{joint}"


def _body_name(model: mujoco.MjModel, body: int) -> str:
    if body == 0:
        return "world"
    return mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, body) or f"body #{body}"
