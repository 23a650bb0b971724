"""Headless closed-loop simulation: the IK problem as a controller, MuJoCo as the plant.

:func:`simulate` runs the loop (:mod:`~redik.apps.sim.loop`: one ``problem.step`` per control
tick, ``mj_step`` between ticks) and returns a :class:`SimulationResult`
(:mod:`~redik.apps.sim.result`): the measured and commanded joints, the tracking errors split
into the IK's and the servos' share, saturation, the robot's contacts, and a status that says
whether the run completed or stopped because MuJoCo reported the physics unsound
(:mod:`~redik.apps.sim.monitor`). The pieces, one job each:

- :mod:`~redik.apps.sim.drives`: which actuator drives each joint, servo or motor;
- :mod:`~redik.apps.sim.controller`: joint reference to actuator controls, with the
  inverse-dynamics feed-forward;
- :mod:`~redik.apps.sim.base`: a floating base, refused unsupported or held on request;
- :mod:`~redik.apps.sim.monitor`: MuJoCo's instability warnings and the contacts;
- :mod:`~redik.apps.sim.plots`: :func:`plot_tracking`.

Renders of a run come from its recorded states (:func:`redik.apps.render.render_states`; set
``MUJOCO_GL=egl`` before MuJoCo is first imported).
"""

from redik.apps.sim.controller import Controller
from redik.apps.sim.drives import JointDrives, actuator_indices, joint_drives
from redik.apps.sim.loop import COMMANDS, DEFAULT_ERROR_BOUND, simulate
from redik.apps.sim.plots import plot_tracking
from redik.apps.sim.result import Contact, SimulationResult, SimulationStatus
from redik.core.exceptions import InstabilityWarning, TrackingWarning

__all__ = [
    "COMMANDS",
    "DEFAULT_ERROR_BOUND",
    "Contact",
    "Controller",
    "InstabilityWarning",
    "JointDrives",
    "SimulationResult",
    "SimulationStatus",
    "TrackingWarning",
    "actuator_indices",
    "joint_drives",
    "plot_tracking",
    "simulate",
]
