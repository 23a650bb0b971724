r"""When a run of an iterative method stops, and with what status: :class:`StoppingRules`.

The rules are the course notes' (000, "Remarks on Jacobian (Pseudo-)Inverse and Transpose
Methods"; 002, "Issues in implementation") and Modern Robotics' (Lynch & Park §6.2), each
with its own :class:`~redik.core.result.Status`:

``tol`` — the error test
    ``‖e‖ ≤ tol`` → ``"converged"``. A pair ``(ε_p, ε_R)`` tests the two parts of a residual
    with a position and an orientation part separately (metres and radians do not belong
    in one norm): ``e_p ≤ ε_p`` and ``e_R ≤ ε_R``, the parts being those the residual
    defines (:meth:`Residual.errors`). ``tol = 0`` never stops a run early: every
    iteration of the budget runs (an iterate table) unless another rule fires, and at the
    end of the budget the run is ``"converged"`` only if ``e`` is exactly 0. ``tol = None``
    asks for no error test: the other rules decide.
``rel_tol`` — the relative change of the task value
    ``‖f(q_{k+1}) − f(q_k)‖ ≤ rel_tol · ‖f(q_k)‖``, tested after each step, ``f`` the task
    function ``x = f(q)`` of the notes' IK section (000, "Remarks"). The notes' Newton
    preliminary writes the same ratio for the function whose root is sought, here
    ``e = x_d − f(q)``; read so it cannot stop a converging run: a step ``λ J⁺ e`` gives
    ``e_{k+1} ≈ (1 − λ) e_k`` near the root, so ``‖e_{k+1} − e_k‖ / ‖e_k‖ → λ`` (1 for a full
    Newton step). On the task value the numerator is the same, ``‖e_{k+1} − e_k‖ → 0``, but
    the denominator tends to ``‖x_d‖``, so the ratio tends to 0 and the rule ends a
    converging run. For ``x_d = 0`` both readings coincide: use ``tol`` there.
``q_tol`` — the joint increment
    ``‖q_{k+1} − q_k‖ < q_tol``, tested after the step is taken (``q_{k+1}`` is kept and
    counted).
    When either of these two fires the run stops: ``"converged"`` if the error test holds
    or none was asked (``tol = None`` or ``0``: the change or the increment is then the
    criterion the user chose, as the notes allow), else ``"stalled"`` — a small change or
    increment does not certify a root, it happens at a local minimum of ``‖e‖`` too. The
    message names the rule.
``singular_tol`` — the singularity test, before each step
    ``σ_min(J) ≤ singular_tol`` (``singular_test="sigma_min"``, the smallest of the
    ``min(r, n)`` singular values), or ``|det J| ≤ singular_tol`` (``"det"``, a square ``J``
    only: the notes' "simpler test on its determinant, for m = n") → ``"singular"``, without
    moving.
``max_growth`` — divergence
    A step that produces NaN or inf, an iterate with ``‖q‖_∞ > max_growth · max(1,
    ‖q_0‖_∞)`` or an error with ``‖e‖ > max_growth · max(1, ‖e_0‖)`` → ``"diverged"``, with
    the last sane iterate. The iterate is tested before the residual is evaluated at it, so
    a task function that refuses such a ``q`` (a robot's FK beyond ±10¹⁰) never sees it.
    ``10⁸`` by default: beyond it a float64 angle has lost half its digits.
``max_iterations`` — the budget
    Spent → ``"max_iterations"`` (``"converged"`` if the error test holds there).

An Armijo search that finds no decrease of the merit stops the run as ``"stalled"``.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.validate import integer, non_negative, positive, real_array
from redik.solvers.iterative.steps import ARMIJO_MAX_TRIALS

MAX_GROWTH = 1e8
"""Default ``max_growth``: an iterate or error this many times its starting scale diverged."""

SINGULAR_TESTS = ("sigma_min", "det")
"""The singularity tests: ``σ_min(J) ≤ ε`` or ``|det J| ≤ ε``."""

Tolerance = float | tuple[float, float] | None
"""``tol``: a bound on ``‖e‖``, a pair ``(ε_p, ε_R)`` on the two parts of a pose residual, or
None for no error test."""

Step = float | str
"""A step size: a number ``λ > 0``, or ``"armijo"`` for a backtracking line search."""


@dataclasses.dataclass(frozen=True)
class StoppingRules:
    """The stopping rules of one run (module docstring), validated by :meth:`checked`.

    Attributes:
        tol: The error test: a bound, a pair ``(ε_p, ε_R)``, or None.
        rel_tol: The relative change of the task value, or None.
        q_tol: The joint increment, or None.
        singular_tol: The singularity test's bound, or None.
        singular_test: ``"sigma_min"`` or ``"det"``.
        max_iterations: The iteration budget.
        max_growth: The blow-up bound of ``"diverged"``.
        armijo_trials: Trials of one Armijo search.
    """

    tol: Tolerance = 1e-6
    rel_tol: float | None = None
    q_tol: float | None = None
    singular_tol: float | None = None
    singular_test: str = "sigma_min"
    max_iterations: int = 100
    max_growth: float = MAX_GROWTH
    armijo_trials: int = ARMIJO_MAX_TRIALS

    @classmethod
    def checked(cls, **values: object) -> StoppingRules:
        """The rules from values a user gave, each checked.

        Raises:
            InvalidInput: A negative or non-numeric tolerance, a pair that is not two of
                them, an unknown singularity test, or a budget that is not a positive integer.
        """
        checked: dict[str, Any] = {**values}
        if "tol" in values:
            checked["tol"] = tolerance(values["tol"])
        for name in ("rel_tol", "q_tol", "singular_tol"):
            if values.get(name) is not None:
                checked[name] = non_negative(values[name], name)
        test = values.get("singular_test", "sigma_min")
        if not isinstance(test, str) or test not in SINGULAR_TESTS:
            raise InvalidInput(f"singular_test must be one of {SINGULAR_TESTS}, got {test!r}")
        if "max_iterations" in values:
            checked["max_iterations"] = integer(values["max_iterations"], "max_iterations")
        if "max_growth" in values:
            checked["max_growth"] = positive(values["max_growth"], "max_growth", allow_inf=True)
        return cls(**checked)

    @property
    def stops_early(self) -> bool:
        """The error test may end a run before its budget (not for ``tol = 0`` or None)."""
        return isinstance(self.tol, tuple) or (self.tol is not None and self.tol > 0.0)


def tolerance(value: object) -> Tolerance:
    """``tol`` checked: None, a number ≥ 0 or a pair of them.

    Raises:
        InvalidInput: Anything else.
    """
    if value is None:
        return None
    if isinstance(value, (tuple, list, np.ndarray)):
        pair = [non_negative(part, "tol") for part in value]
        if len(pair) != 2:
            raise InvalidInput(f"tol must be a number or a pair (ε_p, ε_R), got {value!r}")
        return (pair[0], pair[1])
    return non_negative(value, "tol")


def step_size(value: object, name: str) -> Step:
    """A step checked: ``"armijo"`` or a finite number ``λ > 0``.

    Raises:
        InvalidInput: Anything else, naming ``name``.
    """
    if isinstance(value, str) and value == "armijo":
        return value
    if isinstance(value, str):
        raise InvalidInput(f"{name} must be a positive number or 'armijo', got {value!r}")
    return positive(value, name)


def gain_matrix(gain: object, r: int) -> np.ndarray | None:
    r"""The gain ``K`` of the Jacobian transpose as an ``r × r`` matrix (None: the identity).

    ``K > 0`` in the course notes' sense: ``xᵀKx > 0`` for every ``x ≠ 0``, that is, its
    symmetric part ``(K + Kᵀ)/2`` is positive definite. ``K`` itself need not be symmetric:
    a rotation by ``|φ| < π/2`` (``xᵀKx = cos φ ‖x‖²``) turns ``e`` out of ``ker Jᵀ``.

    Args:
        gain: A matrix, a length-``r`` vector (the diagonal), a positive number (``k I``) or
            None.
        r: The task dimension.

    Raises:
        InvalidInput: Another shape, a non-finite entry, or a symmetric part that is not
            positive definite (naming its smallest eigenvalue).
    """
    if gain is None:
        return None
    K = real_array(gain, "gain")
    if K.ndim == 0:
        K = K * np.eye(r)
    elif K.ndim == 1 and K.shape == (r,):
        K = np.diag(K)
    if K.shape != (r, r) or not np.all(np.isfinite(K)):
        raise InvalidInput(
            f"gain must be a positive number, a length-{r} vector or an {r} × {r} matrix, "
            f"got shape {K.shape}"
        )
    smallest = float(np.linalg.eigvalsh(0.5 * (K + K.T))[0])
    if not smallest > 0.0:
        raise InvalidInput(
            f"gain K must be positive definite (xᵀKx > 0: its symmetric part (K + Kᵀ)/2 "
            f"positive definite), but the smallest eigenvalue of (K + Kᵀ)/2 is {smallest:.3g} "
            f"for K = {K.tolist()}"
        )
    return K
