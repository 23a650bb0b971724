r"""Use a mink limit (``mink.ConfigurationLimit``, ``mink.CollisionAvoidanceLimit``…).

A mink limit returns :math:`G Δv \le h` over the model's ``nv`` velocity columns from a
``mink.Configuration``. The adapter keeps the chain columns (``robot.dof_indices``) and
drops the rows that then vanish — they constrain joints off the chain, which redik holds
fixed. :class:`redik.Problem` keeps a configuration in sync only when such a limit (or a
mink task) is present, since the sync costs a second forward kinematics per step.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from redik.core.validate import positive
from redik.limits.limit import InequalityLimit
from redik.tasks.foreign import foreign_call

if TYPE_CHECKING:
    from mink import Configuration
    from mink.limits import Limit as MinkLimitBase


class MinkLimit(InequalityLimit):
    """Wrap a ``mink.Limit`` (anything with ``compute_qp_inequalities(configuration, dt)``).

    Args:
        limit: The mink limit.
        dt: The ``dt`` handed to mink when the step has none (mink limits other than
            velocity limits ignore it).
        priority: None (default): hard at every level; ``k``: ranked just above the tasks
            of priority ``k`` (:mod:`redik.limits.limit`).
    """

    needs_configuration = True

    def __init__(self, limit: MinkLimitBase, dt: float = 1.0, *, priority: int | None = None):
        self.limit = limit
        self.dt = positive(dt, "dt", unit="s")
        self._set_priority(priority)

    def inequalities(
        self, state: Configuration, dt: float | None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
        """``(G, h)`` at the current state, or None when inactive."""
        dt = self.dt if dt is None else dt
        constraint = foreign_call(self.limit, "compute_qp_inequalities", state, dt)
        if constraint.G is None or constraint.h is None:
            return None
        G = np.atleast_2d(constraint.G)[:, self._require_robot().dof_indices]
        h = np.atleast_1d(constraint.h)
        keep = np.any(G != 0.0, axis=1)
        if not np.any(keep):
            return None
        return G[keep], h[keep]
