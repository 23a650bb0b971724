r"""Iterate a :class:`redik.Problem` to a solution of its whole task stack: one driver.

:func:`solve_problem` solves

.. math::

    \min_q f_K(q) \;\text{ s.t. }\; \dots \;\text{ s.t. }\; \min_q f_1(q) \;\text{ s.t. }\;
    e_0(q) = 0,\quad q \in \mathcal{Q},

level 0's targets first, then every lower level (posture, joint-limit avoidance) within
what the levels above and the limits leave (Kanoun, Lamiraux & Wieber, IEEE T-RO 2011). The
problem only answers steps (:mod:`redik.qp.problem`); this package decides which steps to
take, when to stop and where to start again:

- :mod:`~redik.solvers.task_stack.steps`: the reach, polish and optimise steps;
- :mod:`~redik.solvers.task_stack.attempt`: one attempt, a loop choosing among them (a
  watchdog descent, an undamped Gauss–Newton polish, SQP steps restored onto level 0);
- :mod:`~redik.solvers.task_stack.starts`: the seeded restarts, per-chain warm start and
  random draws;
- :mod:`~redik.solvers.task_stack.solve`: :func:`solve_problem` and the verdict;
- :mod:`~redik.solvers.task_stack.options`, :mod:`~redik.solvers.task_stack.result`:
  :class:`SolveOptions` and :class:`QPResult`.
"""

from redik.solvers.task_stack.options import SolveOptions
from redik.solvers.task_stack.result import QPResult
from redik.solvers.task_stack.solve import solve_problem

__all__ = ["QPResult", "SolveOptions", "solve_problem"]
