r"""The iterative methods, one loop each on any residual: Newton, Jacobian transpose, hybrid.

Each method is one function, in the manner of Modern Robotics' code, where *IKinBody* sits
beside the generic Newton–Raphson it specialises (Lynch & Park §6.2):

- :mod:`~redik.solvers.iterative.newton` — :func:`newton_raphson`, ``q ← q + λ J⁺ e``;
- :mod:`~redik.solvers.iterative.transpose` — :func:`jacobian_transpose`, ``q ← q + α JᵀKe``;
- :mod:`~redik.solvers.iterative.hybrid` — :func:`transpose_then_newton`, the first far from
  the root and the second near it.

They run on a residual ``e(q) = x_d − f(q)`` with ``J = ∂f/∂q``
(:class:`~redik.solvers.iterative.iterates.Residual`):

- a user's task function, :mod:`~redik.solvers.iterative.equations`
  (:func:`solve_equations`, ``redik.solve_equations``);
- the pose error of a robot's frame, :mod:`~redik.solvers.iterative.pose_residual`
  (:class:`PoseResidual`: *IKinBody*'s body twist, *IKinSpace*'s space twist or the world
  error), which :func:`redik.solve_pose` hands to the same loops, restarts and joint limits
  kept outside the method.

What the loops share: :mod:`~redik.solvers.iterative.steps` (the Newton and transpose steps,
the null-space projection, the one Armijo search), :mod:`~redik.solvers.iterative.rules`
(the stopping rules and the status each gives) and :mod:`~redik.solvers.iterative.iterates`
(the record of a run).
"""

from redik.solvers.iterative.equations import (
    EquationResidual,
    finite_difference_jacobian,
    solve_equations,
)
from redik.solvers.iterative.hybrid import transpose_then_newton
from redik.solvers.iterative.iterates import Iterates, Residual
from redik.solvers.iterative.newton import newton_raphson
from redik.solvers.iterative.pose_residual import PosePoint, PoseResidual, world_error
from redik.solvers.iterative.rules import (
    MAX_GROWTH,
    StoppingRules,
    gain_matrix,
    step_size,
)
from redik.solvers.iterative.steps import (
    ARMIJO_ATTEMPT_TRIALS,
    ARMIJO_MAX_TRIALS,
    RANK_TOLERANCE,
    armijo_backtrack,
    linearised_minimiser,
    newton_step,
    nullspace_projection,
    transpose_step,
)
from redik.solvers.iterative.transpose import jacobian_transpose

__all__ = [
    "ARMIJO_ATTEMPT_TRIALS",
    "ARMIJO_MAX_TRIALS",
    "MAX_GROWTH",
    "RANK_TOLERANCE",
    "EquationResidual",
    "Iterates",
    "PosePoint",
    "PoseResidual",
    "Residual",
    "StoppingRules",
    "armijo_backtrack",
    "finite_difference_jacobian",
    "gain_matrix",
    "jacobian_transpose",
    "linearised_minimiser",
    "newton_raphson",
    "newton_step",
    "nullspace_projection",
    "solve_equations",
    "step_size",
    "transpose_step",
    "transpose_then_newton",
    "world_error",
]
