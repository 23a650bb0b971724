"""The solvers, peers of one another (each uses another only through its entry points).

Each kind of problem has one loop, in one file:

- :mod:`~redik.solvers.iterative`: Newton–Raphson (``iterative/newton.py``), the Jacobian
  transpose (``iterative/transpose.py``) and the hybrid (``iterative/hybrid.py``) on any
  residual: a user's function (``solve_equations``) or a robot's pose
  (``PoseResidual``, which ``solve_pose`` and the redundancy tools use);
- :mod:`~redik.solvers.dls`: damped least squares (Levenberg–Marquardt), compiled
  (``dls/kernel.py``), for ``solve_pose(method="dls")`` and ``solve_batch``;
- :mod:`~redik.solvers.pose`: pose IK on a robot, ``solve_pose`` / ``solve_all``: validation,
  restarts and results around the loops above, the closed forms, and
  :mod:`~redik.solvers.pose.qp` its QP driver;
- :mod:`~redik.solvers.task_stack`: ``solve_problem``, the one driver that iterates a
  :class:`redik.Problem` (tasks and limits stacked into
  per-step QPs, costs and strict priorities);
- :mod:`~redik.solvers.analytic`: closed forms with every solution;
- :mod:`~redik.solvers.batch`: many targets at once, compiled, on every core;
- :mod:`~redik.solvers.redundancy`: null-space motion, gradient projection and the
  self-motion manifold.
"""

from redik.core.lazy import lazy_submodules

__getattr__ = lazy_submodules(__name__)
