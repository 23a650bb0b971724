"""Compiled kinematics and damped least squares on a :class:`~redik.kinematics.chain.Chain`.

:mod:`~redik.kinematics.compiled` holds the chain's FK, world Jacobian and pose error;
:mod:`~redik.kinematics.dls` the damped least-squares step and the Levenberg–Marquardt kernel
that :func:`redik.solvers.batch.solve_batch` and :func:`redik.solve_pose` (``method="dls"``) run,
with its settings :class:`~redik.kinematics.dls.BatchOptions`. Both sit below the solvers
(README, Architecture) so that every solver can use them.
"""

from redik.kinematics.dls import BatchOptions

__all__ = ["BatchOptions"]
