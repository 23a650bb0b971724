"""The stiffness of the generated position servos (:func:`servo_gains`)."""

from __future__ import annotations

import math

import mujoco
import numpy as np
from numpy.typing import NDArray

SERVO_FREQUENCY = 4.0
"""Natural frequency (Hz) of the generated position servos at the ``home`` posture."""


def servo_gains(xml: str, nq: int, home: NDArray[np.float64]) -> list[float]:
    r"""Stiffness of the ``<position>`` servo of each joint of the model ``xml`` at ``home``.

    A critically damped servo (``dampratio="1"``) on joint *i* alone is a second-order system
    of natural frequency :math:`\sqrt{k_{p,i} / M_{ii}}`, so
    :math:`k_{p,i} = (2\pi f)^2 M_{ii}(q_{home})` with :math:`f` = :data:`SERVO_FREQUENCY`
    and :math:`M_{ii}` the diagonal of the joint-space inertia (``mj_mulM`` on a unit vector),
    rounded to two significant digits so the file stays readable.
    """
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    data.qpos[:] = home
    mujoco.mj_forward(model, data)
    gains = []
    unit, column = np.zeros(nq), np.zeros(nq)
    for i in range(nq):
        unit[:] = 0.0
        unit[i] = 1.0
        mujoco.mj_mulM(model, data, column, unit)
        kp = (2 * math.pi * SERVO_FREQUENCY) ** 2 * column[i]
        gains.append(round(kp, 1 - math.floor(math.log10(kp))))
    return gains
