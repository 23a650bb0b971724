"""The solvers, peers of one another (each uses another only through its entry points):

- :mod:`~redik.solvers.pose`: pose IK on a robot, ``solve_pose`` / ``solve_all``
  (damped least squares, Newton–Raphson, gradient, QP, closed form), with
  :mod:`~redik.solvers.pose.qp` its QP driver;
- :mod:`~redik.solvers.iterative`: root finding on a user function, ``solve_equations``
  (``newton_raphson``, ``gradient_descent``, ``gradient_then_newton``: the textbook
  iterations);
- :mod:`~redik.solvers.task_stack`: ``solve_problem``, the one driver that iterates a
  :class:`redik.Problem` (tasks and limits stacked into
  per-step QPs, costs and strict priorities);
- :mod:`~redik.solvers.analytic`: closed forms with every solution;
- :mod:`~redik.solvers.batch`: many targets at once, compiled, on every core;
- :mod:`~redik.solvers.redundancy`: null-space motion and the self-motion manifold.
"""

from redik.core.lazy import lazy_submodules

__getattr__ = lazy_submodules(__name__)
