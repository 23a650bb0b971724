r"""Damped least squares (Levenberg–Marquardt): the ``"dls"`` method, compiled.

Every damped least-squares pose solve of redik runs here: :func:`redik.solvers.batch.solve_batch`
over many targets (:func:`solve_serial`, :func:`solve_parallel`) and :func:`redik.solve_pose`
with ``method="dls"`` for one (:func:`solve_one`), the same compiled code (numba,
``cache=True``: compiled once per machine).

- :mod:`~redik.solvers.dls.damped` — the step ``Δq = Jᵀ(JJᵀ + λI)⁻¹e``, compiled for one target
  (:func:`damped_solve`) and batched in numpy (:func:`damped_step`);
- :mod:`~redik.solvers.dls.kernel` — the attempt (damping, acceptance, the clamping loop at
  the joint limits), the restarts and the entry points, one target per call or per thread;
- :mod:`~redik.solvers.dls.options` — :class:`DLSOptions`, the settings and their checks.

Each attempt iterates (Wampler 1986; Nakamura & Hanafusa 1986; damping after Sugihara 2011)

.. math::

    Δq = J^\top (J J^\top + λ I_6)^{-1} e, \qquad λ = μ\,‖e‖^2 + λ_{min}, \qquad
    e = \begin{pmatrix} p_d − p \\ \log(R_d R^\top)^\vee \end{pmatrix},

with the ``"world"`` Jacobian of :mod:`redik.core.conventions`; the kernel's docstring states
the acceptance rule, the joint limits and the restarts.
"""

from redik.solvers.dls.damped import damped_solve, damped_step
from redik.solvers.dls.kernel import (
    CONVERGED,
    DIVERGED,
    EXHAUSTED,
    INVALID,
    STALLED,
    UNREACHABLE,
    batch_results,
    reach_excess,
    solve_one,
    solve_parallel,
    solve_serial,
)
from redik.solvers.dls.options import DLSOptions

__all__ = [
    "CONVERGED",
    "DIVERGED",
    "EXHAUSTED",
    "INVALID",
    "STALLED",
    "UNREACHABLE",
    "DLSOptions",
    "batch_results",
    "damped_solve",
    "damped_step",
    "reach_excess",
    "solve_one",
    "solve_parallel",
    "solve_serial",
]
