r"""Tasks on the joint values themselves: a diagonal Jacobian, a reference posture.

.. math::

    e(q) = d ⊙ (q \ominus r), \qquad J = \mathrm{diag}(d)

over the robot's tangent coordinates, with a constant :math:`d` and reference
configuration :math:`r`; :math:`q \ominus r` is ``robot.difference(r, q)`` (plain
:math:`q - r` on a flat robot; ``mj_differentiatePos`` across ball and free joints). On a
ball joint, or a free joint's rotation, :math:`e = \log(R_r^\top R)` and a step
:math:`R \to R \exp(δ)` changes it by :math:`J_r^{-1}(e)\, δ` (Solà et al., *A micro Lie
theory*, 2018, App. B), not by :math:`δ`: :math:`J = \mathrm{diag}(d)` is exact only at
:math:`q = r`, as in mink's ``PostureTask``. It still gives the exact first-order descent,
since :math:`J_r^{-1}(e)\, e = e`: the step :math:`δ = -αe` lowers the error by
:math:`αe` to first order however large :math:`e` is (``tests/test_whole_model.py``)
(:class:`PostureTask`: :math:`d = 1`, :math:`r = q_{nom}`; :class:`JointLimitAvoidanceTask`:
:math:`d = \sqrt2 s`, :math:`r = \bar q`; :class:`DampingTask`: :math:`d = 1`, :math:`α = 0`).
Their objective is diagonal,

.. math::

    H = \mathrm{diag}(w^2 d^2), \qquad c = α\, w^2 d^2 ⊙ (q \ominus r),

so :mod:`redik.qp.assembly` adds all of a level's joint-space tasks with a few vector
operations instead of stacking ``n × n`` identity blocks.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from redik.kinematics.robot import Robot
from redik.tasks.kinematics import KinematicState
from redik.tasks.task import ResidualTask


class JointSpaceTask(ResidualTask):
    """Base of the tasks with ``e = d ⊙ (q ⊖ r)`` and ``J = diag(d)``.

    Subclasses set :attr:`jacobian_diagonal` (``d``) and :attr:`reference` (``r``) in
    :meth:`bind` (and bump :attr:`version` when they change them later).
    """

    def __init__(self, cost: ArrayLike, gain: float, priority: int):
        super().__init__(cost, gain, priority)
        self.jacobian_diagonal = np.empty(0)
        self.reference = np.empty(0)

    def bind(self, robot: Robot) -> JointSpaceTask:
        """Prepare for ``robot`` (the base class's contract); returns self."""
        self._set_size(robot.dof)
        self._rows = np.arange(robot.dof)
        super().bind(robot)
        return self

    def residual_into(
        self, state: KinematicState, e: NDArray[np.float64], J: NDArray[np.float64]
    ) -> None:
        """Write the error into ``e`` and its Jacobian into ``J`` (module docstring)."""
        if state.robot.flat:
            np.subtract(state.q, self.reference, out=e)
        else:
            e[:] = state.robot.difference(self.reference, state.q)
        e *= self.jacobian_diagonal
        J[:] = 0.0
        J[self._rows, state.chain_columns] = self.jacobian_diagonal

    def diagonal_terms(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``(w² d², α w² d²)``: the Hessian diagonal and the factor of ``q ⊖ r`` in ``c``."""
        hessian = (self.cost * self.jacobian_diagonal) ** 2
        return hessian, self.gain * hessian
