"""Batch inverse kinematics: many targets at once, compiled, on all cores or a Ray cluster.

- :mod:`~redik.kinematics.chain` compiles a robot's MuJoCo chain once into arrays;
- :mod:`~redik.kinematics.batched` evaluates FK and Jacobians over a whole batch;
- :mod:`redik.solvers.dls` is the compiled (numba) damped least-squares solve of one
  target, shared with :func:`redik.solve_pose`;
- :mod:`~redik.solvers.batch.solve` runs it on a batch (:func:`solve_batch`);
- :mod:`~redik.solvers.batch.engines` spreads chunks over this process, a process pool or Ray
  (an :class:`Engine` owns its workers: create it once, reuse it, close it).
"""

from redik.kinematics.batched import forward_kinematics, jacobian
from redik.kinematics.chain import Chain
from redik.solvers.batch.engines import ENGINES, Engine, close_shared_engines
from redik.solvers.batch.solve import BATCH_STATUSES, BatchResult, solve_batch

__all__ = [
    "BATCH_STATUSES",
    "ENGINES",
    "BatchResult",
    "Chain",
    "Engine",
    "close_shared_engines",
    "forward_kinematics",
    "jacobian",
    "solve_batch",
]
