r"""Damped least squares: the step (compiled, and batched in numpy), its settings
(:class:`BatchOptions`) and the compiled Levenberg–Marquardt kernel, one solve per target.

Every pose solver of redik that uses damped least squares — :func:`redik.solvers.batch.solve_batch`
over many targets and :func:`redik.solve_pose` with ``method="dls"`` for one — runs this
kernel, compiled by numba (``cache=True``: once per machine, a few seconds). Per target it is
scalar code on a handful of 3-vectors and one small matrix, which numpy cannot vectorise well
across a shrinking set of unsolved targets; compiled, one iteration of a 7-joint arm costs
well under a microsecond. Targets are independent, so the batch entry point spreads them
over threads with ``numba.prange``.

The chain is that of :class:`~redik.kinematics.chain.Chain`; its FK, world Jacobian and pose
error are those of :mod:`redik.kinematics.compiled`. This module sits in the kinematics
layer (below the solvers) so that :mod:`redik.solvers.batch` and :mod:`redik.solvers.pose` share
it.

Each attempt iterates (Wampler 1986; Nakamura & Hanafusa 1986; damping after Sugihara 2011)

.. math::

    Δq = J^\top (J J^\top + λ I_6)^{-1} e, \qquad λ = μ\,‖e‖^2 + λ_{min}, \qquad
    e = \begin{pmatrix} p_d − p \\ \log(R_d R^\top)^\vee \end{pmatrix},

with ``(JᵀJ + λI)⁻¹Jᵀe`` when ``n < 6``, both by Cholesky. A trial is accepted only when it
lowers ``‖e‖`` (then ``μ`` halves), otherwise ``μ`` grows eightfold and ``q`` stays. With
limits respected, a joint that the step would carry out of its range stops at the limit and
the others re-solve for the rest of the error (the clamping loop of Chan & Dubey 1995, with
damping); a limited hinge whose range spans a full turn is wrapped by 2π instead. An attempt
ends converged (``‖p_d − p‖ ≤`` ``pos_tol`` and ``angle ≤ rot_tol``), stalled (``λ`` past
``λ_max``, or ``‖e‖`` not cut to ``required`` times its value ``patience`` iterations
earlier), diverged (a non-finite step) or at ``max_iterations``. A target that failed restarts from
random configurations drawn uniformly within the sampling bounds by its own generator
(splitmix64 seeded from the key and the target's index), so a result does not depend on
chunking, threads or processes. The best attempt wins: a converged one, else the smallest
``‖e‖``. The batch entry point finally checks each target strictly by a fresh FK of its
returned ``q``.
"""

from __future__ import annotations

import dataclasses
import math

import numba
import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.rotation_policy import ROTATION_TOLERANCE
from redik.core.validate import MAX_COORDINATE, fraction, integer
from redik.kinematics.compiled import (
    COMPILE,
    chain_kinematics,
    pose_error,
    valid_target,
    world_jacobian,
)
from redik.lie import apply_inverse_v

CONVERGED, STALLED, EXHAUSTED, INVALID, DIVERGED = range(5)
"""Status codes, shared with :data:`redik.solvers.batch.solve.BATCH_STATUSES` (``EXHAUSTED`` is
``"max_iterations"``: the iteration budget ran out)."""

# Indices into the float and integer settings arrays (few arguments keep the call cheap).
POS_TOL, ROT_TOL, DAMPING, MIN_DAMPING, MAX_DAMPING, REQUIRED, REACH, TARGET_TOL = range(8)
MAX_ITERATIONS, RESTARTS, PATIENCE, BOUNDED, CANDIDATES = range(5)

_BLOCK = 16
"""Targets per parallel work item: small enough to balance the threads on hard tails."""

_GAMMA = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)
_STREAM = np.uint64(0xD1B54A32D192ED03)
_TWO_TO_MINUS_53 = 2.0**-53


@numba.njit(**COMPILE)
def _next_uniform(state: np.ndarray) -> float:
    """A double in [0, 1) from the splitmix64 generator whose state is ``state[0]``."""
    state[0] += _GAMMA
    z = state[0]
    z = (z ^ (z >> np.uint64(30))) * _MIX1
    z = (z ^ (z >> np.uint64(27))) * _MIX2
    z = z ^ (z >> np.uint64(31))
    return float(z >> np.uint64(11)) * _TWO_TO_MINUS_53


@numba.njit(**COMPILE)
def gram(J, G):
    """The lower triangle of ``G = J Jᵀ`` (6 × 6) when ``n ≥ 6``, else of ``JᵀJ`` (n × n).

    It changes only when ``J`` does: an iteration whose trial is rejected, and each pass of
    the clamping loop, solve with the same ``G`` (:func:`damped_solve_gram`).
    """
    n = J.shape[1]
    if n >= 6:
        for i in range(6):
            for j in range(i + 1):
                total = 0.0
                for k in range(n):
                    total += J[i, k] * J[j, k]
                G[i, j] = total
    else:
        for i in range(n):
            for j in range(i + 1):
                total = 0.0
                for k in range(6):
                    total += J[k, i] * J[k, j]
                G[i, j] = total


@numba.njit(**COMPILE)
def damped_solve_gram(J, G, free, e, damping, A, y, dq):
    r"""``dq = J_fᵀ (J_f J_fᵀ + λI)⁻¹ e`` (``n ≥ 6``) or ``(J_fᵀJ_f + λI)⁻¹ J_fᵀ e``, where
    ``J_f`` is ``J`` with the columns not ``free`` zeroed (their ``dq`` is 0), from the Gram
    matrix ``G`` of the whole ``J`` (:func:`gram`).

    ``J_f J_fᵀ = G − Σ_k j_k j_kᵀ`` over the columns that are not free (``n ≥ 6``); for
    ``n < 6`` their rows and columns of ``JᵀJ`` are dropped. Cholesky ``A = L Lᵀ`` in place
    (lower triangle; the diagonal holds ``1 / L_jj``), then forward and back substitution.
    """
    n = J.shape[1]
    m = A.shape[0]
    if n >= 6:
        for i in range(6):
            for j in range(i + 1):
                A[i, j] = G[i, j]
            y[i] = e[i]
        for k in range(n):
            if not free[k]:
                for i in range(6):
                    for j in range(i + 1):
                        A[i, j] -= J[i, k] * J[j, k]
    else:
        for i in range(n):
            for j in range(i + 1):
                A[i, j] = G[i, j] if free[i] and free[j] else 0.0
            total = 0.0
            if free[i]:
                for k in range(6):
                    total += J[k, i] * e[k]
            y[i] = total
    for j in range(m):
        diagonal = A[j, j] + damping
        for k in range(j):
            diagonal -= A[j, k] * A[j, k]
        inverse = 1.0 / math.sqrt(diagonal)
        A[j, j] = inverse
        for i in range(j + 1, m):
            entry = A[i, j]
            for k in range(j):
                entry -= A[i, k] * A[j, k]
            A[i, j] = entry * inverse
    for i in range(m):  # L z = y
        value = y[i]
        for k in range(i):
            value -= A[i, k] * y[k]
        y[i] = value * A[i, i]
    for i in range(m - 1, -1, -1):  # Lᵀ x = z
        value = y[i]
        for k in range(i + 1, m):
            value -= A[k, i] * y[k]
        y[i] = value * A[i, i]
    if n >= 6:
        for k in range(n):
            total = 0.0
            if free[k]:
                for i in range(6):
                    total += J[i, k] * y[i]
            dq[k] = total
    else:
        for k in range(n):
            dq[k] = y[k]


@numba.njit(**COMPILE)
def damped_solve(J, free, e, damping, A, y, dq):
    r"""``dq = J_fᵀ (J_f J_fᵀ + λI)⁻¹ e`` (``n ≥ 6``) or ``(J_fᵀJ_f + λI)⁻¹ J_fᵀ e``, where
    ``J_f`` is ``J`` with the columns not ``free`` zeroed (their ``dq`` is 0)."""
    G = np.empty_like(A)
    gram(J, G)
    damped_solve_gram(J, G, free, e, damping, A, y, dq)


_SMALL_BATCH = 256


def damped_step(J: np.ndarray, e: np.ndarray, damping: np.ndarray) -> np.ndarray:
    r"""``Δq = Jᵀ (J Jᵀ + λ I)⁻¹ e`` for every column: ``J`` is ``6 × n × A``, ``e`` ``6 × A``.

    The symmetric positive-definite ``6 × 6`` systems are solved by Cholesky ``L Lᵀ``,
    forward and back substitution, each entry one vector operation over the batch; below
    ``_SMALL_BATCH`` columns by LAPACK, one system after another. The batch is last (a
    vector per target is a column), for callers that iterate a whole batch in numpy
    themselves (:class:`redik.solvers.redundancy.corrector.BatchCorrector`); the compiled
    one-target form is :func:`damped_solve`, tested equal to this one.
    """
    m, _, size = J.shape
    if size < _SMALL_BATCH:
        # Few columns: numpy's call overhead dominates, so one LAPACK call per system wins.
        Jb = J.transpose(2, 0, 1)
        A = Jb @ Jb.transpose(0, 2, 1)
        A[:, range(m), range(m)] += damping[:, None]
        return np.einsum("bik,bi->kb", Jb, np.linalg.solve(A, e.T[..., None])[..., 0])
    L: list[list[np.ndarray]] = [[] for _ in range(m)]
    for j in range(m):
        diagonal = np.einsum("kb,kb->b", J[j], J[j]) + damping
        for k in range(j):
            diagonal -= L[j][k] * L[j][k]
        np.sqrt(diagonal, out=diagonal)
        inverse = 1.0 / diagonal
        for i in range(j + 1, m):
            entry = np.einsum("kb,kb->b", J[i], J[j])  # (J Jᵀ)[i, j]
            for k in range(j):
                entry -= L[i][k] * L[j][k]
            entry *= inverse
            L[i].append(entry)
        L[j].append(diagonal)
    y: list[np.ndarray] = []
    for i in range(m):
        value = e[i].copy()
        for k in range(i):
            value -= L[i][k] * y[k]
        y.append(value / L[i][i])
    x: list[np.ndarray] = [y[0]] * m
    for i in reversed(range(m)):
        value = y[i].copy()
        for k in range(i + 1, m):
            value -= L[k][i] * x[k]
        x[i] = value / L[i][i]
    return np.einsum("ikb,ib->kb", J, np.array(x))


@dataclasses.dataclass(frozen=True)
class BatchOptions:
    """Settings of the damped least squares (see this module).

    Attributes:
        pos_tol: Position tolerance (m).
        rot_tol: Rotation tolerance (rad).
        max_iterations: Iterations per attempt before a target is re-seeded.
        restarts: Random re-seeds per target after its first attempt.
        damping: ``μ`` at the start of each attempt (``λ = μ‖e‖² + λ_min``).
        min_damping, max_damping: ``λ_min``, and the ``λ`` past which an attempt has stalled.
        patience, progress: An attempt whose ``‖e‖²`` fell by less than the fraction
            ``progress`` (in (0, 1)) over the last ``patience`` iterations has stalled.
        candidates: Each restart starts from the nearest in pose of this many random
            configurations (1: a uniform random start).

    The defaults were tuned on 20k random targets of panda, iiwa14 and ur5e: ``μ`` = 0.1 and
    16 candidates cut the iterations per solve by a fifth against ``μ`` = 1 and uniform
    starts; a patience of 8 (not 5) and 100 restarts take panda's hardest 0.1–0.2 % of
    targets (near its limits, where progress is slow) to 100 % for 6 % more iterations.
    """

    pos_tol: float = 1e-6
    rot_tol: float = 1e-5
    max_iterations: int = 60
    restarts: int = 100
    damping: float = 0.1
    min_damping: float = 1e-9
    max_damping: float = 1e6
    patience: int = 8
    progress: float = 0.5
    candidates: int = 16

    def __post_init__(self) -> None:
        fraction(self.progress, "progress")  # as Problem.solve: 1 would ask ‖e‖² to reach 0
        for name in ("pos_tol", "rot_tol", "damping", "min_damping", "max_damping"):
            value = getattr(self, name)
            if isinstance(value, bool) or not (
                isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0
            ):
                raise InvalidInput(f"{name} must be a positive number, got {value!r}")
        integers = (("max_iterations", 1), ("restarts", 0), ("patience", 1), ("candidates", 1))
        for name, minimum in integers:
            integer(getattr(self, name), name, minimum)

    def kernel_settings(self, bounded: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """The float and integer settings arrays of this module's kernel (the reach
        excess ``REACH`` is 0: :func:`solve_one` sets it per target in a copy; a target
        is valid within :data:`~redik.core.rotation_policy.ROTATION_TOLERANCE`, as
        :func:`~redik.core.rotation_policy.as_pose` checks one pose)."""
        settings = np.empty(8)
        settings[POS_TOL] = self.pos_tol
        settings[ROT_TOL] = self.rot_tol
        settings[DAMPING] = self.damping
        settings[MIN_DAMPING] = self.min_damping
        settings[MAX_DAMPING] = self.max_damping
        settings[REQUIRED] = math.sqrt(1.0 - self.progress)
        settings[REACH] = 0.0
        settings[TARGET_TOL] = ROTATION_TOLERANCE
        counts = np.empty(5, dtype=np.int64)
        counts[CANDIDATES] = self.candidates
        counts[MAX_ITERATIONS] = self.max_iterations
        counts[RESTARTS] = self.restarts
        counts[PATIENCE] = self.patience
        counts[BOUNDED] = int(bounded)
        return settings, counts


@numba.njit(**COMPILE)
def _workspace(n):
    m = 6 if n >= 6 else n
    return (
        np.empty((2, 3, 3)),  # R: current, trial
        np.empty((2, 3)),  # p
        np.empty((2, n, 3)),  # axes
        np.empty((2, n, 3)),  # origins
        np.empty((1, 6, n)),  # J of the current iterate
        np.empty((2, 6)),  # e
        np.empty((2, n)),  # q
        np.empty((m, m)),  # A
        np.empty(m),  # y
        np.empty(n),  # dq
        np.empty(6),  # rhs of the clamping loop
        np.empty(n, dtype=np.bool_),  # free
        np.empty(n),  # limit values of the clamping loop
        np.empty((m, m)),  # G, the Gram matrix of J
    )


@numba.njit(**COMPILE)
def _attempt(chain, Rd, pd, settings, counts, ws, errors, history, record):
    """One attempt from ``ws`` q[0]; returns ``(status, iterations, ‖e‖², ‖Jᵀe‖ at the
    end without components pushing against a limit)``. ``errors[k]`` is ``‖e‖`` after
    iteration ``k`` and, when ``record``, ``history[k]`` the iterate."""
    base, links, revolute, lower, upper, _, _, periodic = chain
    A, y, dq, free, G = ws[7], ws[8], ws[9], ws[11], ws[13]
    J = ws[4][0]
    # The current iterate (c) and the trial (t): buffers swap on an accepted step.
    Rc, Rt, pc, pt = ws[0][0], ws[0][1], ws[1][0], ws[1][1]
    ac, at, oc, ot = ws[2][0], ws[2][1], ws[3][0], ws[3][1]
    ec, et, qc, qt = ws[5][0], ws[5][1], ws[6][0], ws[6][1]
    n = revolute.shape[0]
    pos_tol, rot_tol = settings[POS_TOL], settings[ROT_TOL]
    lambda_min, lambda_max = settings[MIN_DAMPING], settings[MAX_DAMPING]
    required = settings[REQUIRED]
    max_iterations, patience, bounded = (
        counts[MAX_ITERATIONS],
        counts[PATIENCE],
        counts[BOUNDED] != 0,
    )

    swapped = False
    chain_kinematics(base, links, revolute, qc, Rc, pc, ac, oc)
    world_jacobian(revolute, pc, ac, oc, J)
    gram(J, G)
    position, angle = pose_error(Rd, pd, Rc, pc, ec)
    E = 0.0
    for k in range(6):
        E += ec[k] * ec[k]
    errors[0] = math.sqrt(E)
    if record:
        history[0] = qc
    mu = settings[DAMPING]
    status = EXHAUSTED
    iterations = 0
    ended = False
    while iterations < max_iterations:
        if position <= pos_tol and angle <= rot_tol:
            status = CONVERGED
            ended = True
            break
        damping = mu * E + lambda_min
        free[:] = True
        damped_solve_gram(J, G, free, ec, damping, A, y, dq)
        outside = False
        for j in range(n):
            qt[j] = qc[j] + dq[j]
            if qt[j] < lower[j] or qt[j] > upper[j]:
                outside = True
        if bounded and outside:
            for j in range(n):
                if periodic[j] and (qt[j] < lower[j] or qt[j] > upper[j]):
                    # A turn of 2π is the same pose: wrap instead of stopping.
                    qt[j] = lower[j] + np.mod(qt[j] - lower[j], 2.0 * np.pi)
            _clamp(J, ec, damping, qc, qt, lower, upper, ws)
        chain_kinematics(base, links, revolute, qt, Rt, pt, at, ot)
        trial_position, trial_angle = pose_error(Rd, pd, Rt, pt, et)
        E_trial = 0.0
        for k in range(6):
            E_trial += et[k] * et[k]
        if E_trial < E:  # accept, and trust the Gauss–Newton model more
            Rc, Rt, pc, pt, ac, at, oc, ot = Rt, Rc, pt, pc, at, ac, ot, oc
            ec, et, qc, qt = et, ec, qt, qc
            swapped = not swapped
            world_jacobian(revolute, pc, ac, oc, J)
            gram(J, G)
            position, angle, E = trial_position, trial_angle, E_trial
            mu = max(0.5 * mu, 1e-12)
        else:
            step = 0.0
            for j in range(n):
                step += dq[j] * dq[j]
            if not math.isfinite(step):
                status = DIVERGED
                ended = True
                break
            mu *= 8.0  # reject, and lean towards the gradient
        iterations += 1
        errors[iterations] = math.sqrt(E)
        if record:
            history[iterations] = qc
        if damping > lambda_max or (
            iterations >= patience and errors[iterations] > required * errors[iterations - patience]
        ):
            status = STALLED
            ended = True
            break
    if not ended and position <= pos_tol and angle <= rot_tol:
        status = CONVERGED
    if swapped:
        qt[:] = qc  # the caller reads the result from the first buffer
    # ‖Jᵀe‖ without the components that push against an active limit.
    gradient = 0.0
    for j in range(n):
        g = 0.0
        for k in range(6):
            g += J[k, j] * ec[k]
        if (qc[j] <= lower[j] and g < 0.0) or (qc[j] >= upper[j] and g > 0.0):
            g = 0.0
        gradient += g * g
    return status, iterations, E, math.sqrt(gradient)


@numba.njit(**COMPILE)
def _clamp(J, e, damping, q, qt, lower, upper, ws):
    """Joints that would leave their range stop at the limit; the others re-solve.

    Clipping alone bends the step away from the Gauss–Newton direction and parks the arm on
    its limits; instead each saturated joint's share of the error is handed to the joints
    still free: ``J_f Δq_f = e − J (q_lim − q)`` over the saturated columns.
    """
    A, y, dq, rhs, free, limit_value, G = ws[7], ws[8], ws[9], ws[10], ws[11], ws[12], ws[13]
    n = q.shape[0]
    free[:] = True
    for _ in range(n):
        over = False
        for j in range(n):
            if qt[j] < lower[j] or qt[j] > upper[j]:
                limit_value[j] = min(max(qt[j], lower[j]), upper[j])
                free[j] = False
                over = True
        if not over:
            return
        for k in range(6):
            value = e[k]
            for j in range(n):
                if not free[j]:
                    value -= J[k, j] * (limit_value[j] - q[j])
            rhs[k] = value
        damped_solve_gram(J, G, free, rhs, damping, A, y, dq)
        for j in range(n):
            qt[j] = q[j] + dq[j] if free[j] else limit_value[j]


@numba.njit(**COMPILE)
def _restart_seed(chain, Rd, pd, state, candidates, bounded, ws):
    """Into ``ws`` q[0]: the nearest in pose of ``candidates`` random configurations.

    Distance ``‖p − p_d‖² + (w ‖R − R_d‖_F)²`` with ``w`` = 0.5 m, a reach-sized weight that
    puts radians on the scale of metres: a start near the target converges more often than
    a uniform one, at the price of a few FKs (a fraction of one iteration each).
    """
    base, links, revolute, lower, upper, sampling_lower, sampling_upper, _ = chain
    R, p, axes, origins, q = ws[0][1], ws[1][1], ws[2][1], ws[3][1], ws[6]
    n = revolute.shape[0]
    best = np.inf
    for _ in range(candidates):
        for j in range(n):
            value = sampling_lower[j] + (sampling_upper[j] - sampling_lower[j]) * (
                _next_uniform(state)
            )
            q[1, j] = min(max(value, lower[j]), upper[j]) if bounded else value
        if candidates == 1:
            q[0] = q[1]
            return
        chain_kinematics(base, links, revolute, q[1], R, p, axes, origins)
        distance = 0.0
        for a in range(3):
            distance += (p[a] - pd[a]) ** 2
            for b in range(3):
                distance += 0.25 * (R[a, b] - Rd[a, b]) ** 2
        if distance < best:
            best = distance
            q[0] = q[1]


@numba.njit(**COMPILE)
def _solve_target(chain, Rd, pd, q0, state, settings, counts, ws, out, history, errors, record):
    """Attempts from ``q0`` then from random configurations until one converges.

    ``out`` receives the best attempt's ``q``; returns ``(status, iterations, restarts,
    history length, summary)`` with ``summary = (min ‖e‖, max ‖e‖, every ‖Jᵀe‖ ≤ 1e-4 ‖e‖,
    every attempt diverged)`` over the attempts, for the caller's unreachable diagnosis.
    """
    q = ws[6]
    bounded = counts[BOUNDED] != 0
    restarts = counts[RESTARTS]
    best_status, best_E, best_length = DIVERGED, np.inf, 0
    total, attempts = 0, 0
    error_min, error_max = np.inf, 0.0
    all_stationary, all_diverged = True, True
    work_history, work_errors = history[0], errors[0]
    while attempts <= restarts:
        if attempts == 0:
            q[0] = q0
        else:
            _restart_seed(chain, Rd, pd, state, counts[CANDIDATES], bounded, ws)
        status, iterations, E, gradient = _attempt(
            chain, Rd, pd, settings, counts, ws, work_errors, work_history, record
        )
        attempts += 1
        total += iterations
        error = math.sqrt(E)
        error_min, error_max = min(error_min, error), max(error_max, error)
        all_stationary = all_stationary and gradient <= 1e-4 * error
        all_diverged = all_diverged and status == DIVERGED
        if attempts == 1 or status == CONVERGED or E < best_E:
            best_status, best_E, best_length = status, E, iterations + 1
            out[:] = q[0]
            if record:
                history[1, : iterations + 1] = work_history[: iterations + 1]
                errors[1, : iterations + 1] = work_errors[: iterations + 1]
        if status == CONVERGED:
            break
        if attempts == 1 and settings[REACH] > 0.0:
            restarts = min(restarts, 2)  # beyond reach: a closest q is all there is to find
    summary = (error_min, error_max, all_stationary, all_diverged)
    return best_status, total, attempts - 1, best_length, summary


@numba.njit(**COMPILE)
def solve_one(chain, columns, reach, T, q0, key, settings, counts, out, history, errors, e):
    """One pose target, validated and solved in one compiled call (:func:`redik.solve_pose`).

    ``T`` (4 × 4) must be a rigid transform within ``settings[TARGET_TOL]``
    (:func:`~redik.kinematics.compiled.valid_target`, the exact case of
    :func:`redik.core.rotation_policy.as_pose`) and ``q0`` (the robot's ``q``) finite within
    ``±MAX_COORDINATE`` (as :meth:`redik.Robot.check_q`); otherwise nothing is solved and the
    status is :data:`INVALID`, so that the caller's full validation names the fault. The
    chain's joints are ``q0[columns]``, clipped into the limits when they are respected.
    ``reach = (a_x, a_y, a_z, r)``: no ``q`` puts the frame farther than ``r`` from ``a``; a
    target beyond it gets at most two restarts (:func:`_solve_target`).

    :func:`_solve_target` records the best attempt's history into ``history[1]`` and
    ``errors[1]`` (``history`` is 2 × (at least max_iterations + 1) × n). A fresh FK of the
    returned ``q`` (``out``) fills ``e`` with the world error there. Returns ``(status,
    iterations, restarts, history length, summary)``; the summary is that of
    :func:`_solve_target` followed by the position and rotation errors at ``q``, whether
    ``q`` is inside the limits, the body error ``‖log(T⁻¹ T_d)‖`` and the reach excess.
    """
    base, links, revolute, lower, upper = chain[0], chain[1], chain[2], chain[3], chain[4]
    n = revolute.shape[0]
    no_summary = (np.inf, 0.0, False, False, np.inf, np.inf, False, np.inf, 0.0)
    if not valid_target(T, settings[TARGET_TOL]):
        return INVALID, 0, 0, 0, no_summary
    for j in range(q0.shape[0]):
        if not abs(q0[j]) <= MAX_COORDINATE:  # also refuses NaN
            return INVALID, 0, 0, 0, no_summary
    Rd, pd = T[:3, :3], T[:3, 3]
    excess = 0.0
    if math.isfinite(reach[3]):
        dx, dy, dz = pd[0] - reach[0], pd[1] - reach[1], pd[2] - reach[2]
        distance = math.sqrt(dx * dx + dy * dy + dz * dz)
        if distance - reach[3] > 1e-9 * max(1.0, reach[3]):
            excess = distance - reach[3]
    local = settings.copy()
    local[REACH] = excess
    ws = _workspace(n)
    state = np.empty(1, dtype=np.uint64)
    state[0] = key
    start = np.empty(n)
    for j in range(n):
        value = q0[columns[j]]
        start[j] = min(max(value, lower[j]), upper[j]) if counts[BOUNDED] != 0 else value
    status, total, used, length, summary = _solve_target(
        chain, Rd, pd, start, state, local, counts, ws, out, history, errors, True
    )
    R, p, axes, origins = ws[0][0], ws[1][0], ws[2][0], ws[3][0]
    chain_kinematics(base, links, revolute, out, R, p, axes, origins)
    position, angle = pose_error(Rd, pd, R, p, e)
    inside = True
    for j in range(n):
        inside = inside and lower[j] <= out[j] <= upper[j]
    vx, vy, vz = apply_inverse_v(e[3], e[4], e[5], e[0], e[1], e[2])
    body_error = math.sqrt(vx * vx + vy * vy + vz * vz + e[3] * e[3] + e[4] * e[4] + e[5] * e[5])
    return status, total, used, length, (*summary, position, angle, inside, body_error, excess)


@numba.njit(**COMPILE)
def _solve_range(chain, T, q0, first, key, settings, counts, start, stop, results):
    q_out, status, iterations, restarts, position_error, rotation_error = results
    base, links, revolute, lower, upper = chain[0], chain[1], chain[2], chain[3], chain[4]
    n = revolute.shape[0]
    ws = _workspace(n)
    state = np.empty(1, dtype=np.uint64)
    errors = np.empty((2, counts[MAX_ITERATIONS] + 1))
    history = np.empty((2, 1, n))  # not recorded
    R, p = np.empty((3, 3)), np.empty(3)
    axes, origins = np.empty((n, 3)), np.empty((n, 3))
    e = np.empty(6)
    for t in range(start, stop):
        q_out[t] = q0[t]
        if not valid_target(T[t], settings[TARGET_TOL]):
            status[t] = INVALID
            iterations[t] = restarts[t] = 0
            position_error[t] = rotation_error[t] = np.nan
            continue
        # The generator of target t depends on the key and t's index in the whole batch only.
        state[0] = key + np.uint64(first + t) * _STREAM
        Rd, pd = T[t, :3, :3], T[t, :3, 3]
        code, count, used, _, _ = _solve_target(
            chain, Rd, pd, q0[t], state, settings, counts, ws, q_out[t], history, errors, False
        )
        # Strict success: a fresh FK of the returned q, its errors, and the limits.
        chain_kinematics(base, links, revolute, q_out[t], R, p, axes, origins)
        position, angle = pose_error(Rd, pd, R, p, e)
        inside = True
        for j in range(n):
            inside = inside and lower[j] <= q_out[t, j] <= upper[j]
        solved = inside and position <= settings[POS_TOL] and angle <= settings[ROT_TOL]
        if solved:
            code = CONVERGED
        elif code == CONVERGED:
            code = EXHAUSTED
        status[t], iterations[t], restarts[t] = code, count, used
        position_error[t], rotation_error[t] = position, angle


@numba.njit(**COMPILE)
def solve_serial(chain, T, q0, first, key, settings, counts, results):
    """Solve every target of a chunk on this thread (see :func:`solve_parallel`)."""
    _solve_range(chain, T, q0, first, key, settings, counts, 0, T.shape[0], results)


@numba.njit(parallel=True, **COMPILE)
def solve_parallel(chain, T, q0, first, key, settings, counts, results):
    """Solve every target of a chunk, blocks of targets spread over numba's threads.

    ``T`` (B × 4 × 4) are targets ``first … first + B − 1`` of the batch; ``results`` are
    the output arrays ``(q, status, iterations, restarts, position error, rotation error)``.
    """
    size = T.shape[0]
    blocks = (size + _BLOCK - 1) // _BLOCK
    for block in numba.prange(blocks):
        start = block * _BLOCK
        stop = min(size, start + _BLOCK)
        _solve_range(chain, T, q0, first, key, settings, counts, start, stop, results)
