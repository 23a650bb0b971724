r"""QP back-ends behind one small interface, chosen by name.

A :class:`Backend` solves a :class:`~redik.qp.problem_data.QP` and returns ``x``, or
raises :class:`~redik.core.exceptions.InfeasibleProblem` (the solver proved the constraints
empty) or :class:`~redik.core.exceptions.BackendError` (anything else), each naming the
back-end and the problem size. Names accepted by :func:`make_backend`:

``"daqp"``
    DAQP's own Python API called directly (no qpsolvers wrapping): the fast path. Bounds
    go in as DAQP's simple bounds.
``"proxsuite"``
    A persistent proxsuite ``dense.QP`` that keeps its workspace between calls and
    warm-starts from the previous solution (re-initialised when the sizes change, and
    retried cold when a warm start fails). ProxQP does not always certify infeasible
    rows: it may stop at its iteration limit, which is then a :class:`BackendError`.
``"cvxpy"``
    The QP written as a cvxpy program (slow; a readable reference).
any solver in ``qpsolvers.available_solvers`` (``"proxqp"``, ``"clarabel"``, ``"osqp"``,
``"quadprog"``, ``"highs"``, ``"piqp"``, ``"scs"``, and ``"daqp"`` as ``"qpsolvers:daqp"``)
    Through ``qpsolvers.solve_problem``, with tight default tolerances (below) that a
    keyword argument overrides.

A list of names is a :class:`FallbackChain`: each is tried in turn, and the error is
raised only when all fail.

Each back-end declares ``tolerance``, measured, not assumed: on damped IK QPs (Hessian
eigenvalues in [1e-3, ~10], active and inactive bounds, rows and equalities) with the
default settings below, both the largest constraint violation of its ``x`` and the
∞-norm distance of ``x`` to the exact minimiser stay below it
(``tests/test_qp_backends.py`` checks this for every installed back-end against an
active-set reference whose KKT conditions it verifies). The position box is shrunk by it
(:mod:`redik.limits.configuration_limit`). The distance of a tolerance-based solver (interior
point, ADMM, proximal) grows like :math:`\sqrt{\text{gap}/λ_{min}}` as the Hessian's
smallest eigenvalue :math:`λ_{min}` falls; active-set solvers (daqp, quadprog, highs) are
exact up to round-off. Settings passed to :func:`make_backend` replace the defaults, and
the declared tolerance is then the caller's to check.
"""

from __future__ import annotations

import abc
import importlib
import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import BackendError, InfeasibleProblem
from redik.qp.problem_data import QP

_BIG = 1e20  # proxsuite wants finite bounds

QPSOLVERS_SETTINGS: dict[str, dict[str, Any]] = {
    # ProxQP stops on its residuals; at eps_abs 1e-10 it may sit ~3e-5 inside an active
    # bound (objective off by 1e-4), at 1e-12 within 1e-7 of the minimiser.
    "proxqp": {"eps_abs": 1e-12, "eps_rel": 0.0},
    # ADMM: at eps 1e-8 it stops ~1e-5 from the minimiser, at 1e-10 ~6e-8. (Polishing
    # would do as well but prints "Polishing not needed" on stdout whatever `verbose`.)
    # Ill-conditioned levels (a pose alone, Hessian eigenvalues down to 1e-6) need up to
    # a few 1e5 iterations at that precision.
    "osqp": {"eps_abs": 1e-10, "eps_rel": 1e-10, "max_iter": 400000, "verbose": False},
    "highs": {"qp_regularization_value": 1e-12},  # its default 1e-7 biases x by ~1e-4
    "scs": {"eps_abs": 1e-11, "eps_rel": 1e-11, "max_iters": 200000},
    # Interior point: the duality gap decides the distance to the minimiser; at 1e-10
    # Clarabel is 2e-5 off, at 1e-12 1e-8 (at 1e-13 it fails to converge on some
    # ill-conditioned IK QPs, Hessian eigenvalues down to 1e-6).
    "clarabel": {"tol_gap_abs": 1e-12, "tol_gap_rel": 1e-12, "tol_feas": 1e-12},
    # PIQP's duality-gap tolerances default to 1e-8 and are what stopped it 2e-5 off;
    # eps_abs/eps_rel alone do not tighten them.
    "piqp": {
        "eps_abs": 1e-14,
        "eps_rel": 0.0,
        "eps_duality_gap_abs": 1e-14,
        "eps_duality_gap_rel": 0.0,
    },
}
"""Per-solver defaults for qpsolvers back-ends (tighter than the solvers' own)."""

QPSOLVERS_TOLERANCE = {
    "quadprog": 1e-9,
    "daqp": 1e-9,
    "highs": 1e-8,
    "piqp": 1e-8,
    "scs": 1e-7,
    "clarabel": 1e-7,
    "proxqp": 1e-6,
    "osqp": 1e-6,
}
"""Declared accuracy of the qpsolvers back-ends with :data:`QPSOLVERS_SETTINGS`. Worst
distance to the minimiser measured on the 108 QPs of ``tests/test_qp_backends.py``: daqp
2e-13, quadprog 0 (the reference), piqp 2e-10, scs 1e-10, highs 5e-10, clarabel 1e-9,
proxqp 5e-8, osqp 1.4e-7 (violations all below 1e-9). A solver not listed is declared
1e-6."""


ACTIVE_SET = {"daqp", "quadprog"}
"""qpsolvers back-ends that are active-set solvers (see :attr:`Backend.active_set`)."""

NATIVE_BOUNDS = {"daqp", "highs", "piqp", "proxqp"}
"""qpsolvers back-ends given the bounds as such (their solvers take a box natively)."""

_DAQP_EXITFLAGS = {
    -1: "infeasible",
    -2: "cycling",
    -3: "unbounded",
    -4: "iteration limit",
    -5: "non-convex",
    -6: "overdetermined initial active set",
}


class Backend(abc.ABC):
    """Solves one QP; a fresh instance per QP of a hierarchy (they may keep state).

    Attributes:
        name: The name it was made from.
        tolerance: Declared bound on both the constraint violation of ``x`` and its
            ∞-norm distance to the exact minimiser (module docstring: how it is measured).
        active_set: True for an active-set solver (daqp, quadprog): exact up to round-off,
            and on an IK-sized QP about as fast as checking whether the unconstrained
            minimiser is feasible — which :mod:`redik.qp.hierarchy` does first for the
            other back-ends (interior point, ADMM, proximal), slower and only within their
            tolerance.
    """

    name: str = ""
    tolerance: float = 1e-9
    active_set: bool = False

    @abc.abstractmethod
    def solve(self, qp: QP) -> NDArray[np.float64]:
        """The minimiser ``x`` (a fresh array)."""

    def reset(self) -> None:  # noqa: B027 - a stateless back-end has nothing to override
        """Forget the state kept from earlier QPs (a workspace, a warm start).

        The next solve starts cold, as on a fresh instance, and returns bit for bit what that would
        (:meth:`redik.Problem.reset`). A stateless back-end has nothing to forget.
        """

    def _error(self, reason: str, qp: QP) -> BackendError:
        return BackendError(f"QP back-end {self.name!r} failed ({reason}) on a QP with {qp.size()}")

    def _infeasible(self, qp: QP) -> InfeasibleProblem:
        return InfeasibleProblem(
            f"QP back-end {self.name!r} reports the constraints infeasible on a QP with "
            f"{qp.size()}: no joint step satisfies every limit"
        )

    def _checked(self, x: NDArray[np.float64] | None, qp: QP) -> NDArray[np.float64]:
        if x is None or not np.isfinite(x).all():
            raise self._error("non-finite solution", qp)
        return x


class DaqpBackend(Backend):
    """DAQP (dual active set, Arnström, Bemporad & Axehill 2022) through ``daqp.Model``.

    The workspace is set up once per problem size and updated in place afterwards, so a
    step costs one data copy and the solve; bounds are DAQP's simple bounds.
    """

    name = "daqp"
    tolerance = 1e-9
    active_set = True

    def __init__(self, **settings: Any) -> None:
        import daqp

        self._daqp = daqp
        self.settings = {"primal_tol": 1e-9, **settings}
        self._model: Any = None  # a daqp.Model (daqp ships no types)
        self._dims: tuple[int, int, int] | None = None

    def solve(self, qp: QP) -> NDArray[np.float64]:
        """The minimiser ``x`` of ``qp`` (:meth:`Backend.solve`)."""
        n = qp.n
        if qp.C is None and qp.A is None:
            upper, lower = (
                (qp.ub, qp.lb)
                if qp.lb is not None and qp.ub is not None
                else (np.empty(0), np.empty(0))
            )
            A = _empty_rows(n)
        else:
            uppers: list[NDArray[np.float64]] = []
            lowers: list[NDArray[np.float64]] = []
            rows: list[NDArray[np.float64]] = []
            if qp.lb is not None and qp.ub is not None:
                uppers.append(qp.ub)
                lowers.append(qp.lb)
            for M, lo, up in ((qp.C, qp.l, qp.u), (qp.A, qp.b, qp.b)):
                if M is not None and lo is not None and up is not None:
                    uppers.append(up)
                    lowers.append(lo)
                    rows.append(M)
            upper, lower = np.concatenate(uppers), np.concatenate(lowers)
            A = np.ascontiguousarray(np.vstack(rows))
        dims = (n, upper.shape[0], qp.n_eq)
        if self._model is None or dims != self._dims:
            sense = np.zeros(upper.shape[0], dtype=np.int32)
            if qp.n_eq:
                sense[-qp.n_eq :] = 5
            self._model = self._daqp.Model()
            self._dims = dims
            exitflag, _ = self._model.setup(qp.H, qp.c, A, upper, lower, sense)
            self._check(exitflag, qp, "set-up")
            self._model.settings = {**self._model.settings, **self.settings}
        else:
            # DAQP cannot update zero-length bounds (an unconstrained QP): pass none.
            bounded = upper.shape[0] > 0
            exitflag = self._model.update(
                H=qp.H,
                f=qp.c,
                A=A if A.shape[0] else None,
                bupper=upper if bounded else None,
                blower=lower if bounded else None,
            )
            self._check(exitflag, qp, "update")
        try:
            x, _, exitflag, _ = self._model.solve()
        except (RuntimeError, IndexError) as error:  # a state the checks above did not catch
            self._model = None
            raise self._error(f"{type(error).__name__}: {error}", qp) from None
        self._check(exitflag, qp, "solve")
        return self._checked(x, qp)

    def reset(self) -> None:
        """Forget the state kept from earlier QPs: the next solve starts cold."""
        self._model = None

    def _check(self, exitflag: int, qp: QP, stage: str) -> None:
        """Raise on a failed DAQP exit flag, forgetting the workspace.

        Set-up and update check the data before any solve: a bound or row whose lower side
        exceeds its upper one (or a zero row with a negative right-hand side) is
        ``-1``, a Hessian that is not positive definite ``-5``. Unchecked, a failed set-up
        left a model that raised a raw ``RuntimeError`` at the solve, and a failed update
        one that returned the previous QP's solution.
        """
        if exitflag >= (1 if stage == "solve" else 0):  # the solve's 0 is no solution either
            return
        self._model = None
        if exitflag == -1:
            raise self._infeasible(qp)
        reason = _DAQP_EXITFLAGS.get(exitflag, "?")
        raise self._error(f"{stage} exit flag {exitflag}: {reason}", qp)


_EMPTY_ROWS: dict[int, NDArray[np.float64]] = {}


def _empty_rows(n: int) -> NDArray[np.float64]:
    rows = _EMPTY_ROWS.get(n)
    if rows is None:
        rows = _EMPTY_ROWS[n] = np.zeros((0, n))
    return rows


class ProxsuiteBackend(Backend):
    """proxsuite's dense ProxQP (Bambade et al. 2022), persistent and warm-started."""

    name = "proxsuite"
    tolerance = 1e-6  # measured worst 3e-9 on the tests' QPs, 9e-8 on others (eps_abs 1e-12)

    def __init__(self, eps_abs: float = 1e-12, **settings: Any) -> None:
        from proxsuite import proxqp

        self._proxqp = proxqp
        self._qp: Any = None  # a proxqp.dense.QP (proxsuite ships no types)
        self._dims: tuple[int, int, int, bool] | None = None
        self.settings = {"eps_abs": eps_abs, "eps_rel": 0.0, **settings}

    def solve(self, qp: QP) -> NDArray[np.float64]:
        """The minimiser ``x`` of ``qp`` (:meth:`Backend.solve`)."""
        proxqp = self._proxqp
        box = qp.lb is not None
        dims = (qp.n, qp.n_eq, qp.n_rows, box)
        data = [
            qp.H,
            qp.c,
            qp.A if qp.A is not None else np.empty((0, qp.n)),
            qp.b if qp.b is not None else np.empty(0),
            qp.C if qp.C is not None else np.empty((0, qp.n)),
            np.maximum(qp.l, -_BIG) if qp.l is not None else np.empty(0),
            np.minimum(qp.u, _BIG) if qp.u is not None else np.empty(0),
        ]
        if qp.lb is not None and qp.ub is not None:
            data += [np.maximum(qp.lb, -_BIG), np.minimum(qp.ub, _BIG)]
        warm = self._qp is not None and dims == self._dims
        status = self._run(data, dims, warm)
        if warm and status != proxqp.QPSolverOutput.PROXQP_SOLVED:
            # A warm start (and the previous preconditioner) can stall on a changed
            # problem; a cold start decides.
            status = self._run(data, dims, warm=False)
        if status == proxqp.QPSolverOutput.PROXQP_PRIMAL_INFEASIBLE:
            self._qp = None
            raise self._infeasible(qp)
        if status != proxqp.QPSolverOutput.PROXQP_SOLVED:
            self._qp = None
            raise self._error(f"status {status.name}", qp)
        return self._checked(self._qp.results.x.copy(), qp)

    def _run(
        self, data: list[NDArray[np.float64]], dims: tuple[int, int, int, bool], warm: bool
    ) -> Any:
        proxqp = self._proxqp
        if warm:
            self._qp.update(*data)
        else:
            self._qp = proxqp.dense.QP(*dims)
            for key, value in self.settings.items():
                setattr(self._qp.settings, key, value)
            self._qp.settings.initial_guess = proxqp.InitialGuess.WARM_START_WITH_PREVIOUS_RESULT
            self._dims = dims
            self._qp.init(*data)
        self._qp.solve()
        return self._qp.results.info.status

    def reset(self) -> None:
        """Forget the state kept from earlier QPs: the next solve starts cold."""
        self._qp = None


class QpsolversBackend(Backend):
    """Any solver of ``qpsolvers`` (Caron et al.) through ``qpsolvers.solve_problem``."""

    def __init__(self, solver: str, **settings: Any) -> None:
        import qpsolvers
        from qpsolvers.warnings import SparseConversionWarning

        if solver not in qpsolvers.available_solvers:
            raise BackendError(
                f"unknown or uninstalled QP back-end {solver!r}; available: {available_backends()}"
            )
        self._qpsolvers = qpsolvers
        self._sparse_warning = SparseConversionWarning
        self.solver = solver
        self.name = solver
        self.tolerance = QPSOLVERS_TOLERANCE.get(solver, 1e-6)
        self.active_set = solver in ACTIVE_SET
        self.settings = {**QPSOLVERS_SETTINGS.get(solver, {}), **settings}

    def solve(self, qp: QP) -> NDArray[np.float64]:
        """The minimiser ``x`` of ``qp`` (:meth:`Backend.solve`)."""
        if self.solver in NATIVE_BOUNDS:
            G, h = qp.one_sided()
            problem = self._qpsolvers.Problem(qp.H, qp.c, G, h, qp.A, qp.b, qp.lb, qp.ub)
        else:
            # Bounds as rows, as mink passes them: qpsolvers' own conversion of a box for a
            # solver without one is slow (Clarabel: ~10x the solve).
            G, h = qp.one_sided(bounds=True)
            problem = self._qpsolvers.Problem(qp.H, qp.c, G, h, qp.A, qp.b)
        try:
            with warnings.catch_warnings():
                # Dense matrices are converted for sparse solvers; fine at these sizes.
                warnings.simplefilter("ignore", self._sparse_warning)
                solution = self._qpsolvers.solve_problem(
                    problem, solver=self.solver, **self.settings
                )
        except Exception as error:  # a solver's own exception types vary by solver
            raise self._error(f"{type(error).__name__}: {error}", qp) from error
        if not solution.found:
            raise self._error("no solution found", qp)
        return self._checked(np.array(solution.x, dtype=float), qp)


class CvxpyBackend(Backend):
    """The QP as a cvxpy program (Diamond & Boyd 2016).

    Solved by Clarabel unless ``solver=`` names another.
    """

    name = "cvxpy"
    tolerance = 1e-7

    def __init__(self, **settings: Any) -> None:
        import cvxpy

        self._cp = cvxpy
        self.settings = {"solver": "CLARABEL", **QPSOLVERS_SETTINGS["clarabel"], **settings}

    def solve(self, qp: QP) -> NDArray[np.float64]:
        """The minimiser ``x`` of ``qp`` (:meth:`Backend.solve`)."""
        cp = self._cp
        x = cp.Variable(qp.n)
        H = 0.5 * (qp.H + qp.H.T)
        objective = 0.5 * cp.quad_form(x, cp.psd_wrap(H)) + qp.c @ x
        constraints = []
        if qp.lb is not None and qp.ub is not None:
            finite_lb, finite_ub = np.isfinite(qp.lb), np.isfinite(qp.ub)
            if np.any(finite_lb):
                constraints.append(x[finite_lb] >= qp.lb[finite_lb])
            if np.any(finite_ub):
                constraints.append(x[finite_ub] <= qp.ub[finite_ub])
        G, h = qp.one_sided()
        if G is not None:
            constraints.append(G @ x <= h)
        if qp.A is not None and qp.b is not None:
            constraints.append(qp.A @ x == qp.b)
        problem = cp.Problem(cp.Minimize(objective), constraints)
        try:
            problem.solve(**self.settings)
        except cp.error.SolverError as error:
            raise self._error(str(error), qp) from error
        if problem.status in (cp.INFEASIBLE, cp.INFEASIBLE_INACCURATE):
            raise self._infeasible(qp)
        if problem.status not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE):
            raise self._error(f"status {problem.status}", qp)
        return self._checked(np.array(x.value, dtype=float), qp)


class FallbackChain(Backend):
    """Try back-ends in order; the first that succeeds wins.

    Raises :class:`InfeasibleProblem` when every back-end reports infeasibility, else a
    :class:`BackendError` listing each back-end's failure.
    """

    def __init__(self, backends: Sequence[Backend]):
        if not backends:
            raise BackendError("a fallback chain needs at least one back-end")
        self.backends = list(backends)
        self.name = " -> ".join(backend.name for backend in self.backends)
        self.tolerance = max(backend.tolerance for backend in self.backends)
        self.active_set = all(backend.active_set for backend in self.backends)
        self.last_used: str | None = None

    def solve(self, qp: QP) -> NDArray[np.float64]:
        """The minimiser ``x`` of ``qp`` (:meth:`Backend.solve`)."""
        failures: list[Exception] = []
        for backend in self.backends:
            try:
                x = backend.solve(qp)
            except (BackendError, InfeasibleProblem) as error:
                failures.append(error)
                continue
            self.last_used = backend.name
            return x
        if all(isinstance(error, InfeasibleProblem) for error in failures):
            raise InfeasibleProblem(
                f"every back-end of {self.name!r} reports the constraints infeasible on a QP "
                f"with {qp.size()}"
            )
        raise BackendError(
            f"every back-end of the fallback chain failed on a QP with {qp.size()}: "
            + "; ".join(str(error) for error in failures)
        )

    def reset(self) -> None:
        """Forget the state kept from earlier QPs: the next solve starts cold."""
        for backend in self.backends:
            backend.reset()


_NATIVE_MODULES = {"daqp": "daqp", "proxsuite": "proxsuite", "cvxpy": "cvxpy"}
"""The back-ends redik calls directly, and the module each needs."""


def available_backends() -> list[str]:
    """Every name :func:`make_backend` accepts on this machine.

    The back-ends whose module imports, and the solvers qpsolvers found.
    """
    names = [name for name, module in _NATIVE_MODULES.items() if _importable(module)]
    try:
        import qpsolvers
    except ImportError:
        return names
    names += [name for name in qpsolvers.available_solvers if name != "daqp"]
    names += ["qpsolvers:daqp"] if "daqp" in qpsolvers.available_solvers else []
    return names


def _importable(module: str) -> bool:
    try:
        importlib.import_module(module)
    except ImportError:
        return False
    return True


def make_backend(spec: str | Sequence[str] | Backend, **settings: Any) -> Backend:
    """A fresh back-end from a name or a list of names (a fallback chain).

    A fresh back-end from a name or a list of names (fallback chain); a :class:`Backend` instance is
    returned as it is (it is the caller's, with its state).

    ``settings`` go to the solver (e.g. ``eps_abs`` for proxqp). Raises
    :class:`BackendError` for an unknown or uninstalled name.
    """
    if isinstance(spec, Backend):
        return spec
    if not isinstance(spec, str):
        if (
            isinstance(spec, bytes)
            or not isinstance(spec, Sequence)
            or not spec
            or not all(isinstance(name, str) for name in spec)
        ):
            raise BackendError(
                f"a back-end is a name, a list of names or a Backend (a non-empty list), "
                f"got {spec!r}; available names: {available_backends()}"
            )
        return FallbackChain([make_backend(name, **settings) for name in spec])
    try:
        if spec == "daqp":
            return DaqpBackend(**settings)
        if spec == "proxsuite":
            return ProxsuiteBackend(**settings)
        if spec == "cvxpy":
            return CvxpyBackend(**settings)
        return QpsolversBackend(spec.removeprefix("qpsolvers:"), **settings)
    except ImportError as error:
        raise BackendError(
            f"QP back-end {spec!r} is not installed ({error}); available: {available_backends()}"
        ) from None
