r"""Generate MuJoCo models (MJCF strings) from Denavit–Hartenberg tables or screw axes.

A redik robot is always a MuJoCo model; this package is how a kinematic description from a
textbook or a datasheet becomes one. Both builders produce the same kind of scene:

* one body per joint, nested from the world, each holding one hinge or slide joint;
* capsules between consecutive joint origins and a sphere at each joint (so zero-length
  links still have mass and render), contact disabled (``contype = conaffinity = 0``):
  the models are for kinematics first, and the arm must not collide with itself;
* a site ``ee`` at the end-effector, a floor, a light and a camera ``track`` that follows
  the arm;
* joint ranges from ``limits`` (a joint is limited only where its limits are finite);
* a keyframe ``home``, and with ``actuators=True`` one ``<position>`` servo per joint
  (critically damped, stiffness from the joint-space inertia at ``home`` for a ≈4 Hz
  response, ``ctrlrange`` = joint range); bodies are gravity-compensated so the servos
  track commands without sagging;
* the kinematic description itself, stored in ``<custom>`` so it can be recovered from the
  file (:func:`read_dh`, :func:`read_screws`) together with any user ``custom`` numerics.

One idea per module:

- :mod:`~redik.models.builder.from_dh`: :func:`dh_to_mjcf`, a DH table → the bodies of the arm;
- :mod:`~redik.models.builder.from_screws`: :func:`screws_to_mjcf`, screw axes (product of
  exponentials) → the bodies of the arm;
- :mod:`~redik.models.builder.link`: :class:`~redik.models.builder.link.Link`, one body of the
  arm, the description both builders produce;
- :mod:`~redik.models.builder.serial_arm`: the arm (one ``Link`` per joint) → a checked MJCF
  document, with the options both builders share;
- :mod:`~redik.models.builder.servos`: the stiffness of the generated position servos;
- :mod:`~redik.models.builder.mjcf_text`: the MJCF text itself (numbers, poses, elements);
- :mod:`~redik.models.builder.description`: the DH table or screws stored in ``<custom>``,
  written and read back (:func:`read_dh`, :func:`read_screws`).

Units and conventions: :mod:`redik.core.conventions` (metres, radians). Screw axes follow Modern
Robotics (``S = (ω, v)``), the one place redik uses that order.
"""

from redik.models.builder.description import (
    DH_CONVENTION,
    DH_NUMERICS,
    DH_PRISMATIC,
    DH_TOOL,
    POE_HOME,
    POE_SCREWS,
    read_dh,
    read_screws,
)
from redik.models.builder.from_dh import dh_to_mjcf
from redik.models.builder.from_screws import screws_to_mjcf
from redik.models.builder.servos import SERVO_FREQUENCY

__all__ = [
    "DH_CONVENTION",
    "DH_NUMERICS",
    "DH_PRISMATIC",
    "DH_TOOL",
    "POE_HOME",
    "POE_SCREWS",
    "SERVO_FREQUENCY",
    "dh_to_mjcf",
    "read_dh",
    "read_screws",
    "screws_to_mjcf",
]
