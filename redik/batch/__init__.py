"""Batch inverse kinematics: many targets at once, vectorised, on all cores or a Ray cluster.

- :mod:`~redik.batch.chain` compiles a robot's MuJoCo chain once into arrays;
- :mod:`~redik.batch.kinematics` evaluates FK and Jacobians over a whole batch;
- :mod:`~redik.batch.solve` runs damped least squares on a batch (:func:`solve_batch`);
- :mod:`~redik.batch.engines` spreads chunks over this process, a process pool or Ray.
"""

from .chain import Chain
from .engines import ENGINES
from .kinematics import forward_kinematics, jacobian
from .solve import BATCH_STATUSES, BatchResult, solve_batch

__all__ = [
    "BATCH_STATUSES",
    "ENGINES",
    "BatchResult",
    "Chain",
    "forward_kinematics",
    "jacobian",
    "solve_batch",
]
