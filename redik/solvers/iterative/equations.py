r"""A user's own task function ``x = f(q)``: :func:`solve_equations` and its residual.

``f`` maps ``n`` coordinates to an ``r``-dimensional task; the residual is
``e(q) = x_d − f(q)`` and its Jacobian ``J = ∂f/∂q`` — given as ``jac``, or by finite
differences (:func:`finite_difference_jacobian`). :func:`solve_equations` runs one of the
iterative methods on it (Lynch & Park, *Modern Robotics* §6.2; the course notes 000 and
002): ``"newton"`` (:func:`~redik.solvers.iterative.newton.newton_raphson`),
``"transpose"`` (:func:`~redik.solvers.iterative.transpose.jacobian_transpose`) or
``"hybrid"`` (:func:`~redik.solvers.iterative.hybrid.transpose_then_newton`), the same loops
:func:`redik.solve_pose` runs on a robot's pose. Its options are those of the methods and
the stopping rules of :mod:`~redik.solvers.iterative.rules`, so a course's worked example
reproduces line by line: ``tol=0`` runs every iteration of the budget (an iterate table),
``result.history[k]`` is ``q`` after iteration ``k``.

A pair ``tol = (ε_p, ε_R)`` tests the position and orientation parts of ``e`` separately,
ordered (position, orientation) as twists are in :mod:`redik.core.conventions`: the last
``orientation_size`` entries are the orientation, the others the position. It is 3 for
``r = 6`` (a pose: ``(p, r)``) and 1 for ``r = 3`` (a planar pose ``(x, y, φ)``, the notes'
minimum-coordinate algorithm) unless given; any other ``r`` must give it. ``e_p`` and
``e_R`` are the norms of the two parts (for Euler angles the notes' ``‖φ_1 − φ_2‖``, for
exponential coordinates ``‖r_1 − r_2‖``).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.result import IKResult, Status
from redik.core.validate import as_vector, integer, positive, real_array
from redik.solvers.iterative.hybrid import transpose_then_newton
from redik.solvers.iterative.iterates import Iterates
from redik.solvers.iterative.newton import newton_raphson
from redik.solvers.iterative.rules import (
    MAX_GROWTH,
    StoppingRules,
    Tolerance,
    gain_matrix,
    step_size,
)
from redik.solvers.iterative.transpose import jacobian_transpose

TaskFunction = Callable[[np.ndarray], np.ndarray]
"""A task function ``x = f(q)``: a length-``n`` vector to a length-``r`` vector."""

JacobianFunction = Callable[[np.ndarray], np.ndarray]
"""``J(q) = ∂f/∂q``, an ``r × n`` matrix."""

FD_SCHEMES = ("central", "forward")
"""The finite-difference schemes of :func:`finite_difference_jacobian`."""

METHOD_OPTIONS: dict[str, dict[str, object]] = {
    "newton": {"step": 1.0},
    "transpose": {"step": 0.5, "gain": None},
    "hybrid": {"switch_error": 0.1, "transpose_step": "armijo", "newton_step": 1.0, "gain": None},
}
"""The methods of :func:`solve_equations`, their own options and the defaults."""

_MAX_MAGNITUDE = 1e150
"""Largest ``|x_d|``, ``|q0|`` entry and ``‖e‖`` taken: ``‖e‖²`` (Armijo's test) stays finite.
A larger error at an iterate counts as non-finite (the step is refused)."""


def solve_equations(
    f: TaskFunction,
    x_d: np.ndarray,
    q0: np.ndarray,
    method: str = "newton",
    jac: JacobianFunction | None = None,
    *,
    tol: Tolerance = 1e-6,
    q_tol: float | None = None,
    rel_tol: float | None = None,
    max_iterations: int = 100,
    singular_tol: float | None = None,
    singular_test: str = "sigma_min",
    orientation_size: int | None = None,
    fd_step: float | None = None,
    fd_scheme: str = "central",
    max_growth: float = MAX_GROWTH,
    **method_options: object,
) -> IKResult:
    r"""Solve ``f(q) = x_d`` for ``q`` from ``q0`` with one of the iterative methods.

    Args:
        f: The task function ``x = f(q)``.
        x_d: The desired task value (length ``r``).
        q0: The initial guess (length ``n``).
        method: ``"newton"``, ``"transpose"`` or ``"hybrid"``.
        jac: ``J(q)`` (``r × n``); None uses :func:`finite_difference_jacobian`.
        tol: The error test: ``‖e‖ ≤ tol``, a pair ``(ε_p, ε_R)`` (module docstring), 0 to
            run every iteration the other rules allow, or None for none
            (:mod:`~redik.solvers.iterative.rules`).
        q_tol: Stop when ``‖q_{k+1} − q_k‖ < q_tol`` (``"converged"`` when ``tol`` is met,
            0 or None).
        rel_tol: Stop when ``‖f(q_{k+1}) − f(q_k)‖ ≤ rel_tol ‖f(q_k)‖`` (as ``q_tol``).
        max_iterations: The iteration budget.
        singular_tol: Stop as ``"singular"`` when the singularity test holds before a
            (Newton) step.
        singular_test: ``"sigma_min"`` (``σ_min(J) ≤ singular_tol``) or ``"det"``
            (``|det J| ≤ singular_tol``, a square ``J`` only).
        orientation_size: The orientation part's length for a pair ``tol`` (module
            docstring).
        fd_step: The finite-difference step ``δ`` when ``jac`` is None (default automatic).
        fd_scheme: ``"central"`` or ``"forward"``.
        max_growth: The blow-up bound of ``"diverged"``.
        **method_options: ``"newton"``: ``step`` (``λ``, default 1, or ``"armijo"``);
            ``"transpose"``: ``step`` (``α``, default 0.5, or ``"armijo"``) and ``gain``
            (``K``: a matrix whose symmetric part is positive definite, a vector — the
            diagonal — or a number; default the identity); ``"hybrid"``:
            ``switch_error`` (default 0.1), ``transpose_step`` (default ``"armijo"``),
            ``newton_step`` (default 1) and ``gain``.

    Returns:
        An :class:`~redik.core.result.IKResult` with ``method`` the method's name,
        ``history[0] = q0`` and ``history[k]`` the iterate after step ``k``,
        ``error_history[k] = ‖e(history[k])‖``; with a pair ``tol`` its
        ``position_error``/``rotation_error`` are ``e_p``/``e_R``.

    Raises:
        InvalidInput: An unknown method or option, a shape mismatch between ``x_d``,
            ``f(q0)`` and ``jac(q0)``, a non-finite ``x_d``/``q0``, or a bad option value.
    """
    options = _method_options(method, method_options)
    rules = StoppingRules.checked(
        tol=tol, q_tol=q_tol, rel_tol=rel_tol, max_iterations=max_iterations,
        singular_tol=singular_tol, singular_test=singular_test, max_growth=max_growth,
    )  # fmt: skip
    residual = EquationResidual(f, x_d, jac, fd_step, fd_scheme)
    q0 = _finite_vector(q0, "q0")
    if q0.size == 0:
        raise InvalidInput("q0 must hold at least one joint value, got an empty vector")
    residual.split(isinstance(rules.tol, tuple), orientation_size)
    if rules.singular_test == "det" and residual.x_d.size != q0.size:
        raise InvalidInput(
            f"singular_test='det' needs a square J, but J is {residual.x_d.size} × {q0.size}; "
            "use 'sigma_min'"
        )
    if "gain" in options:
        options["gain"] = gain_matrix(options["gain"], residual.x_d.size)
    run = METHODS[method](residual, q0, rules, **options)
    return _result(run, residual, method)


METHODS: dict[str, Callable[..., Iterates[Any]]] = {
    "newton": newton_raphson,
    "transpose": jacobian_transpose,
    "hybrid": transpose_then_newton,
}
"""The loop of each method, by name."""


def _method_options(method: object, given: dict[str, object]) -> dict[str, object]:
    """The method's options: its defaults updated with ``given``, step sizes checked."""
    if not isinstance(method, str) or method not in METHOD_OPTIONS:
        raise InvalidInput(f"method must be one of {list(METHOD_OPTIONS)}, got {method!r}")
    known = METHOD_OPTIONS[method]
    unknown = sorted(set(given) - set(known))
    if unknown:
        raise InvalidInput(
            f"unknown option(s) {unknown} for method={method!r}; it takes {sorted(known)}"
        )
    options = {**known, **given}
    for name in ("step", "transpose_step", "newton_step"):
        if name in options:
            options[name] = step_size(options[name], name)
    if "switch_error" in options:
        options["switch_error"] = positive(options["switch_error"], "switch_error")
    return options


def _result(run: Iterates, residual: EquationResidual, method: str) -> IKResult:
    position = rotation = None
    if isinstance(run.rules.tol, tuple):
        position, rotation = residual.errors(run.point)
    return IKResult(
        q=run.q.copy(),
        success=run.status == Status.CONVERGED,
        status=run.final_status,
        iterations=run.iterations,
        error=run.norm,
        position_error=position,
        rotation_error=rotation,
        history=np.array(run.history),
        error_history=np.array(run.errors),
        method=method,
        message=run.message,
    )


class EquationPoint:
    """``q``, the task value ``x = f(q)``, ``e = x_d − x`` and ``‖e‖`` (and ``J`` once asked)."""

    __slots__ = ("J", "e", "norm", "q", "x")

    def __init__(self, q: np.ndarray, x: np.ndarray, e: np.ndarray, norm: float) -> None:
        self.q, self.x, self.e, self.norm = q, x, e, norm
        self.J: np.ndarray | None = None


class EquationResidual:
    """``e(q) = x_d − f(q)`` of a user's task function, with ``J = ∂f/∂q``.

    Args:
        f: The task function.
        x_d: The desired task value.
        jac: ``J(q)``, or None for finite differences.
        fd_step: The finite-difference step, or None for the automatic one.
        fd_scheme: ``"central"`` or ``"forward"``.

    Raises:
        InvalidInput: ``f`` or ``jac`` not callable, a bad ``x_d``, step or scheme.
    """

    def __init__(
        self,
        f: TaskFunction,
        x_d: np.ndarray,
        jac: JacobianFunction | None,
        fd_step: float | None,
        fd_scheme: str,
    ) -> None:
        if not callable(f):
            raise InvalidInput(f"f must be callable, got {f!r}")
        if jac is not None and not callable(jac):
            raise InvalidInput(f"jac must be callable or None, got {jac!r}")
        if fd_scheme not in FD_SCHEMES:
            raise InvalidInput(f"fd_scheme must be one of {FD_SCHEMES}, got {fd_scheme!r}")
        self.f, self.jac = f, jac
        self.x_d = _finite_vector(x_d, "x_d")
        self.fd_step = None if fd_step is None else positive(fd_step, "fd_step")
        self.fd_scheme = fd_scheme
        self.position_size = self.x_d.size

    def split(self, pair: bool, orientation_size: object) -> None:
        """Set the position and orientation parts a pair ``tol`` tests (module docstring).

        Raises:
            InvalidInput: A pair ``tol`` for a residual whose split is neither given nor
                implied by its length, or an ``orientation_size`` outside ``1 … r − 1``.
        """
        r = self.x_d.size
        if orientation_size is None:
            if pair and r not in (3, 6):
                raise InvalidInput(
                    f"tol = (ε_p, ε_R) needs the orientation part of the length-{r} residual: "
                    "give orientation_size=k (its last k entries); it is implied only for "
                    "r = 6 (3) and r = 3 (1: x, y, φ)"
                )
            orientation_size = 3 if r == 6 else 1
        size = integer(orientation_size, "orientation_size", 1)
        if size >= r and pair:
            raise InvalidInput(f"orientation_size must be below r = {r}, got {size}")
        self.position_size = r - size

    def start(self, q: np.ndarray) -> EquationPoint:
        """The point at ``q0``, ``f(q0)`` and ``jac(q0)`` checked against ``x_d`` and ``q0``.

        Raises:
            InvalidInput: ``f(q0)`` or ``jac(q0)`` of the wrong shape, or not finite.
        """
        x = real_array(self.f(q.copy()), "f(q0)")
        if x.shape != self.x_d.shape:
            raise InvalidInput(
                f"f(q0) has shape {x.shape} but x_d has shape {self.x_d.shape}; "
                "f must return a vector of the task's length"
            )
        point = self._point(q.copy(), x)
        if point is None:
            raise InvalidInput(
                f"f(q0) must be finite with ‖x_d − f(q0)‖ ≤ {_MAX_MAGNITUDE:g}, got {x.tolist()}"
            )
        if self.jac is not None:
            J = real_array(self.jac(q.copy()), "jac(q0)")
            expected = (self.x_d.size, q.size)
            if J.shape != expected:
                raise InvalidInput(f"jac(q0) must have shape {expected} (r × n), got {J.shape}")
            point.J = J
        return point

    def evaluate(self, q: np.ndarray) -> EquationPoint | None:
        """The point at ``q``, or None when ``f(q)`` is not finite (or ``‖e‖²`` overflows)."""
        return self._point(q, np.asarray(self.f(q.copy()), dtype=float))

    def jacobian(self, point: EquationPoint) -> np.ndarray | None:
        """``jac(q)``, or the finite-difference Jacobian; None when it is not finite."""
        if point.J is None:
            if self.jac is None:
                point.J = _difference_jacobian(
                    self.f, point.q, self.fd_step, self.fd_scheme, point.x
                )
            else:
                point.J = np.asarray(self.jac(point.q.copy()), dtype=float)
        return point.J if np.isfinite(point.J).all() else None

    def errors(self, point: EquationPoint) -> tuple[float, float]:
        """``(e_p, e_R)``: the norms of the position and orientation parts of ``e``."""
        k = self.position_size
        return float(np.linalg.norm(point.e[:k])), float(np.linalg.norm(point.e[k:]))

    def project(self, q: np.ndarray) -> np.ndarray:
        """``q`` itself: the coordinates are unbounded."""
        return q

    def task_value(self, point: EquationPoint) -> np.ndarray:
        """``x = f(q)``."""
        return point.x

    def _point(self, q: np.ndarray, x: np.ndarray) -> EquationPoint | None:
        e = self.x_d - x
        with np.errstate(over="ignore", invalid="ignore"):
            norm = float(np.linalg.norm(e))
        return EquationPoint(q, x, e, norm) if norm <= _MAX_MAGNITUDE else None


def finite_difference_jacobian(
    f: TaskFunction,
    q: np.ndarray,
    step: float | None = None,
    scheme: str = "central",
    f_q: np.ndarray | None = None,
) -> np.ndarray:
    r"""Finite-difference Jacobian of ``f`` at ``q``, column by column.

    ``scheme="central"``: ``J[:, i] = (f(q + h_i e_i) − f(q − h_i e_i)) / 2h_i``, error
    O(h²); ``scheme="forward"``: ``J[:, i] = (f(q + h_i e_i) − f(q)) / h_i``, error O(h)
    (the course's formula, one evaluation per column).

    With ``step=None`` the step balances truncation against rounding (Nocedal & Wright
    §8.1): ``h_i = ε^{1/3} max(1, |q_i|)`` for central differences (accurate to about
    ``ε^{2/3} ≈ 4·10⁻¹¹``), ``h_i = ε^{1/2} max(1, |q_i|)`` for forward ones (about
    ``ε^{1/2} ≈ 10⁻⁸``). A number ``step = δ`` uses ``h_i = δ`` for every column, as a
    textbook exercise does (with ``δ = 0.1`` the forward Jacobian of ``x²`` at 1 is 2.1).

    Args:
        f: The task function.
        q: Where to differentiate (length ``n``).
        step: The step ``δ > 0``, or None for the automatic one.
        scheme: One of :data:`FD_SCHEMES`.
        f_q: ``f(q)`` when already known (saves one evaluation for ``"forward"``).

    Returns:
        ``J`` (``r × n``).

    Raises:
        InvalidInput: An unknown scheme, a non-callable ``f``, a bad ``q`` or step.
    """
    if scheme not in FD_SCHEMES:
        raise InvalidInput(f"scheme must be one of {FD_SCHEMES}, got {scheme!r}")
    if not callable(f):
        raise InvalidInput(f"f must be callable, got {f!r}")
    if step is not None:
        step = positive(step, "the finite-difference step")
    return _difference_jacobian(f, _finite_vector(q, "q"), step, scheme, f_q)


def _difference_jacobian(
    f: TaskFunction, q: np.ndarray, step: float | None, scheme: str, f_q: np.ndarray | None
) -> np.ndarray:
    """:func:`finite_difference_jacobian` on checked arguments."""
    q = q.copy()
    if step is None:
        exponent = 1.0 / 3.0 if scheme == "central" else 0.5
        h = np.finfo(float).eps ** exponent * np.maximum(1.0, np.abs(q))
    else:
        h = np.full(q.size, step)
    forward = scheme == "forward"
    if forward and f_q is None:
        f_q = np.asarray(f(q.copy()), dtype=float)
    columns = []
    for i in range(q.size):
        saved = q[i]
        q[i] = saved + h[i]
        f_plus = np.asarray(f(q.copy()), dtype=float)
        if forward:
            columns.append((f_plus - f_q) / h[i])
        else:
            q[i] = saved - h[i]
            columns.append((f_plus - np.asarray(f(q.copy()), dtype=float)) / (2.0 * h[i]))
        q[i] = saved
    return np.stack(columns, axis=-1) if columns else np.empty((0, 0))


def _finite_vector(x: np.ndarray, name: str) -> np.ndarray:
    x = np.atleast_1d(real_array(x, name))
    if x.ndim != 1:
        raise InvalidInput(f"{name} must be a vector, got shape {x.shape}")
    x = as_vector(x, x.size, name)
    if np.abs(x).max(initial=0.0) > _MAX_MAGNITUDE:
        raise InvalidInput(f"{name} must be within ±{_MAX_MAGNITUDE:g} (‖e‖² overflows): {x}")
    return x
