r"""The compiled Levenberg–Marquardt kernel: attempts, joint limits and restarts per target.

Per target it is scalar code on a handful of 3-vectors and one small matrix, which numpy
cannot vectorise well across a shrinking set of unsolved targets; targets are independent,
so the batch entry points spread them over threads with ``numba.prange``. The chain is that
of :class:`~redik.kinematics.chain.Chain`; its FK, world Jacobian and pose error are those of
:mod:`redik.kinematics.compiled`, the step that of :mod:`redik.solvers.dls.damped`.

Each attempt iterates (Wampler 1986; Nakamura & Hanafusa 1986; damping after Sugihara 2011)

.. math::

    Δq = J^\top (J J^\top + λ I_6)^{-1} e, \qquad λ = μ\,‖e‖^2 + λ_{min}, \qquad
    e = \begin{pmatrix} p_d − p \\ \log(R_d R^\top)^\vee \end{pmatrix},

with ``(JᵀJ + λI)⁻¹Jᵀe`` when ``n < 6``. A trial is accepted only when it lowers ``‖e‖``
(then ``μ`` halves), otherwise ``μ`` grows eightfold and ``q`` stays. With limits respected,
a joint that the step would carry out of its range stops at the limit and the others
re-solve for the rest of the error (the clamping loop of Chan & Dubey 1995, with damping); a
limited hinge whose range spans a full turn is wrapped by 2π instead. An attempt ends
converged (``‖p_d − p‖ ≤ pos_tol`` and ``angle ≤ rot_tol``), stalled (``λ`` past
``λ_max``, or ``‖e‖`` not cut to ``required`` times its value ``patience`` iterations
earlier), diverged (a non-finite step) or at ``max_iterations``. An attempt that stalled
or ran out within ``POLISH_ERROR`` of the target is polished by undamped Gauss–Newton steps
with backtracking (:func:`_polish`: the damped steps suppress the weak singular direction a
target near a singularity needs). A target that failed restarts from random configurations
drawn within the sampling bounds (the nearest in pose of a few, or around the best ``q``
after a near miss; :func:`_restart_seed`) by its own generator (splitmix64 seeded from the
key and the target's index), so a result does not depend on chunking, threads or processes.
The best attempt wins: a converged one, else the smallest ``‖e‖``. A target beyond the
chain's reach (:func:`reach_excess`) gets at most two restarts and, unsolved, the status
``UNREACHABLE``. The batch entry points finally check each target strictly by a fresh FK of
its returned ``q``.

The settings arrive as two arrays indexed by the constants of
:mod:`redik.solvers.dls.options`; the work buffers are those of :func:`_workspace`, the
current iterate and the trial in the two rows of each (an accepted trial swaps the rows).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from redik.core.validate import MAX_COORDINATE
from redik.kinematics.compiled import (
    COMPILE,
    chain_kinematics,
    pose_error,
    valid_target,
    world_jacobian,
)
from redik.lie import apply_inverse_v
from redik.solvers.dls.damped import damped_solve_gram, gram
from redik.solvers.dls.options import (
    BOUNDED,
    CANDIDATES,
    DAMPING,
    MAX_DAMPING,
    MAX_ITERATIONS,
    MIN_DAMPING,
    PATIENCE,
    POLISH_DAMPING,
    POLISH_ERROR,
    POLISH_ITERATIONS,
    POS_TOL,
    REACH,
    REQUIRED,
    RESTARTS,
    ROT_TOL,
    TARGET_TOL,
)

CONVERGED, STALLED, EXHAUSTED, INVALID, DIVERGED, UNREACHABLE = range(6)
"""Status codes, shared with :data:`redik.solvers.batch.solve.BATCH_STATUSES` (``EXHAUSTED`` is
``"max_iterations"``: the iteration budget ran out; ``UNREACHABLE``: the target lies beyond
the chain's reach, :func:`reach_excess`)."""

_NEAREST, _AROUND_BEST = range(2)
"""The kinds of restart start (:func:`_restart_seed`)."""

PERTURBATION = 0.1
"""Half-width of a start around the best ``q``, as a fraction of each joint's sampling range."""

_BLOCK = 16
"""Targets per parallel work item: small enough to balance the threads on hard tails."""

_GAMMA = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)
_STREAM = np.uint64(0xD1B54A32D192ED03)
_TWO_TO_MINUS_53 = 2.0**-53

# The work buffers of one target (:func:`_workspace`), by index.
_R, _P, _AXES, _ORIGINS, _J, _E, _Q, _A, _Y, _DQ, _RHS, _FREE, _LIMIT, _G = range(14)


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
def _workspace(n):
    """The buffers of one target, by the indices ``_R`` … ``_G``.

    Rows 0 and 1 of the first seven are the current iterate and the trial.
    """
    m = 6 if n >= 6 else n
    return (
        np.empty((2, 3, 3)),  # R
        np.empty((2, 3)),  # p
        np.empty((2, n, 3)),  # joint axes
        np.empty((2, n, 3)),  # joint origins
        np.empty((1, 6, n)),  # J of the current iterate
        np.empty((2, 6)),  # e
        np.empty((2, n)),  # q
        np.empty((m, m)),  # A, the factored system
        np.empty(m),  # y
        np.empty(n),  # dq
        np.empty(6),  # right-hand side of the clamping loop
        np.empty(n, dtype=np.bool_),  # free joints
        np.empty(n),  # limit values of the clamping loop
        np.empty((m, m)),  # G, the Gram matrix of J
    )


@numba.njit(**COMPILE)
def _attempt(chain, Rd, pd, settings, counts, ws, errors, history, record):
    """One attempt from ``q[0]`` of the workspace, which ends holding the attempt's ``q``.

    ``errors[k]`` is ``‖e‖`` after iteration ``k`` and, when ``record``, ``history[k]`` the
    iterate (the caller records ``history[0]``). The loop is one function on purpose: a
    compiled call that takes arrays pays their reference counts at every iteration, and a
    solve is made of few, cheap iterations; only the clamping loop is a call (the 2π wrap
    before it is inlined by numba).

    Returns:
        ``(status, iterations, ‖e‖², ‖Jᵀe‖ at the end without the components that push
        against a limit)``.
    """
    base, links, revolute, lower, upper, _, _, periodic = chain
    A, y, dq, free, G, J = ws[_A], ws[_Y], ws[_DQ], ws[_FREE], ws[_G], ws[_J][0]
    # The current iterate (c) and the trial (t): the buffers swap on an accepted step.
    Rc, Rt, pc, pt, ac, at, oc, ot, ec, et, qc, qt = (
        ws[_R][0], ws[_R][1], ws[_P][0], ws[_P][1], ws[_AXES][0], ws[_AXES][1],
        ws[_ORIGINS][0], ws[_ORIGINS][1], ws[_E][0], ws[_E][1], ws[_Q][0], ws[_Q][1],
    )  # fmt: skip
    first, n = qc, revolute.shape[0]
    pos_tol, rot_tol, lambda_min, lambda_max, required, max_iterations, patience, bounded = (
        settings[POS_TOL], settings[ROT_TOL], settings[MIN_DAMPING], settings[MAX_DAMPING],
        settings[REQUIRED], counts[MAX_ITERATIONS], counts[PATIENCE], counts[BOUNDED],
    )  # fmt: skip
    chain_kinematics(base, links, revolute, qc, Rc, pc, ac, oc)
    world_jacobian(revolute, pc, ac, oc, J)
    gram(J, G)
    position, angle = pose_error(Rd, pd, Rc, pc, ec)
    E = position * position + angle * angle  # ‖e‖², e = (p_d − p, θ u)
    errors[0] = math.sqrt(E)
    mu, status, iterations, ended = settings[DAMPING], EXHAUSTED, 0, False
    while iterations < max_iterations:
        if position <= pos_tol and angle <= rot_tol:
            status, ended = CONVERGED, True
            break
        damping = mu * E + lambda_min
        free[:] = True
        damped_solve_gram(J, G, free, ec, damping, A, y, dq)
        outside = False
        for j in range(n):
            qt[j] = qc[j] + dq[j]
            outside = True if qt[j] < lower[j] or qt[j] > upper[j] else outside
        if bounded and outside:
            _wrap_periodic(qt, lower, upper, periodic)
            _clamp(J, ec, damping, qc, qt, lower, upper, ws)
        chain_kinematics(base, links, revolute, qt, Rt, pt, at, ot)
        trial_position, trial_angle = pose_error(Rd, pd, Rt, pt, et)
        E_trial = trial_position * trial_position + trial_angle * trial_angle
        if E_trial < E:  # accept, and trust the Gauss–Newton model more
            Rc, Rt, pc, pt, ac, at, oc, ot, ec, et, qc, qt = (
                Rt, Rc, pt, pc, at, ac, ot, oc, et, ec, qt, qc
            )  # fmt: skip
            world_jacobian(revolute, pc, ac, oc, J)
            gram(J, G)
            position, angle, E = trial_position, trial_angle, E_trial
            mu = max(0.5 * mu, 1e-12)
        elif not math.isfinite(E_trial):  # a non-finite step
            status, ended = DIVERGED, True
            break
        else:
            mu *= 8.0  # reject, and lean towards the gradient
        iterations += 1
        errors[iterations] = math.sqrt(E)
        if record:
            history[iterations] = qc
        if damping > lambda_max or (
            iterations >= patience and errors[iterations] > required * errors[iterations - patience]
        ):
            status, ended = STALLED, True
            break
    first[:] = qc  # the caller reads the result from the first row
    met = not ended and position <= pos_tol and angle <= rot_tol  # at the budget's end
    return CONVERGED if met else status, iterations, E, _limit_gradient(J, ec, qc, lower, upper)


@numba.njit(inline="always", **COMPILE)
def _wrap_periodic(trial, lower, upper, periodic):
    """Wrap by 2π each hinge of ``trial`` that left a range spanning a full turn (same pose).

    :func:`_clamp` then stops every other joint that left its range at the limit.
    """
    for j in range(trial.shape[0]):
        if periodic[j] and (trial[j] < lower[j] or trial[j] > upper[j]):
            trial[j] = lower[j] + np.mod(trial[j] - lower[j], 2.0 * np.pi)


@numba.njit(**COMPILE)
def _polish(chain, Rd, pd, settings, counts, ws, errors, history, record, iterations):
    r"""Undamped Gauss–Newton steps with backtracking from ``q[0]`` of the workspace.

    Near a singularity the damped attempt stalls a few µm from a reachable target: the
    weakest singular direction ``v`` of ``J`` (``σ ≪ 1``) turns with ``q``, so the full step
    overshoots along it, the trial is rejected, ``μ`` grows, and once ``λ ≫ σ²`` the step
    along ``v``, ``σ uᵀe / λ``, is the part damping suppresses. Each polish step keeps the
    Gauss–Newton direction ``Δq = Jᵀ(JJᵀ + λ_p I)⁻¹ e`` (``λ_p`` only keeps the system
    regular) and shortens it instead, ``q + 2⁻ᵏ Δq`` for the first ``k ≤ 10`` that lowers
    ``‖e‖`` (Nocedal & Wright §10.3, line-search Gauss–Newton; Deuflhard, *Newton Methods for
    Nonlinear Problems*, §4.3), the joints clamped at their limits as in :func:`_attempt`.

    It ends when ``‖e‖`` was not cut to ``REQUIRED`` times its value ``PATIENCE`` polish
    iterations earlier, the attempt's own progress test (Gauss–Newton converges quadratically
    near a root of full rank; slower progress means a stationary point of ``‖e‖`` that is
    not a root). Continues the attempt's ``errors`` and ``history`` from index ``iterations``.

    Returns:
        ``(converged, iterations, ‖e‖², ‖Jᵀe‖ without the components that push against a
        limit)`` at the polished ``q`` (left in ``q[0]``).
    """
    base, links, revolute, lower, upper, _, _, periodic = chain
    R, p, axes, origins, e, q = ws[_R][0], ws[_P][0], ws[_AXES][0], ws[_ORIGINS][0], ws[_E], ws[_Q]
    A, y, dq, free, G, J = ws[_A], ws[_Y], ws[_DQ], ws[_FREE], ws[_G], ws[_J][0]
    damping, stop = settings[POLISH_DAMPING], iterations + counts[POLISH_ITERATIONS]
    chain_kinematics(base, links, revolute, q[0], R, p, axes, origins)
    position, angle = pose_error(Rd, pd, R, p, e[0])
    E = position * position + angle * angle
    met = position <= settings[POS_TOL] and angle <= settings[ROT_TOL]
    while not met and iterations < stop:
        world_jacobian(revolute, p, axes, origins, J)
        gram(J, G)
        free[:] = True
        damped_solve_gram(J, G, free, e[0], damping, A, y, dq)
        for j in range(q.shape[1]):
            q[1, j] = q[0, j] + dq[j]
        if counts[BOUNDED] != 0:
            _wrap_periodic(q[1], lower, upper, periodic)
            _clamp(J, e[0], damping, q[0], q[1], lower, upper, ws)
        E_trial = _backtrack(chain, Rd, pd, ws, E)
        if not E_trial < E:
            break
        q[0] = q[1]
        chain_kinematics(base, links, revolute, q[0], R, p, axes, origins)
        position, angle = pose_error(Rd, pd, R, p, e[0])
        E = position * position + angle * angle
        met = position <= settings[POS_TOL] and angle <= settings[ROT_TOL]
        iterations += 1
        errors[iterations] = math.sqrt(E)
        if record:
            history[iterations] = q[0]
        if iterations - stop + counts[POLISH_ITERATIONS] >= counts[PATIENCE] and (
            errors[iterations] > settings[REQUIRED] * errors[iterations - counts[PATIENCE]]
        ):
            break  # linear progress at best: the attempt is at a stationary point, not a root
    world_jacobian(revolute, p, axes, origins, J)
    return met, iterations, E, _limit_gradient(J, e[0], q[0], lower, upper)


@numba.njit(**COMPILE)
def _backtrack(chain, Rd, pd, ws, E):
    """The first ``q[0] + 2⁻ᵏ (q[1] − q[0])``, ``k = 0 … 10``, whose ``‖e‖²`` is below ``E``.

    Leaves it in ``q[1]`` and returns its ``‖e‖²`` (the last one tried when none is below).
    Every fraction of a step inside the limits stays inside them.
    """
    base, links, revolute = chain[0], chain[1], chain[2]
    R, p, axes, origins, e, q, dq = (
        ws[_R][1], ws[_P][1], ws[_AXES][1], ws[_ORIGINS][1], ws[_E][1], ws[_Q], ws[_DQ]
    )  # fmt: skip
    for j in range(q.shape[1]):
        dq[j] = q[1, j] - q[0, j]
    E_trial = np.inf
    for k in range(11):
        for j in range(q.shape[1]):
            q[1, j] = q[0, j] + dq[j] * 0.5**k
        chain_kinematics(base, links, revolute, q[1], R, p, axes, origins)
        position, angle = pose_error(Rd, pd, R, p, e)
        E_trial = position * position + angle * angle
        if E_trial < E:
            break
    return E_trial


@numba.njit(**COMPILE)
def _clamp(J, e, damping, q, trial, lower, upper, ws):
    """Bring ``trial``, a damped step from ``q``, into the joint limits.

    Each joint that would leave its range stops at the limit and the joints still free
    re-solve for its share of the error, ``J_f Δq_f = e − J (q_lim − q)`` over the saturated
    columns: clipping alone would bend the step away from the Gauss–Newton direction and park
    the arm on its limits (the clamping loop of Chan & Dubey 1995, with damping).
    """
    A, y, dq, rhs, free, limit_value, G = (
        ws[_A], ws[_Y], ws[_DQ], ws[_RHS], ws[_FREE], ws[_LIMIT], ws[_G]
    )  # fmt: skip
    n = q.shape[0]
    free[:] = True
    for _ in range(n):
        over = False
        for j in range(n):
            if trial[j] < lower[j] or trial[j] > upper[j]:
                limit_value[j] = min(max(trial[j], lower[j]), upper[j])
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
            trial[j] = q[j] + dq[j] if free[j] else limit_value[j]


@numba.njit(**COMPILE)
def _limit_gradient(J, e, q, lower, upper):
    """``‖Jᵀe‖`` without the components that push against an active joint limit."""
    gradient = 0.0
    for j in range(q.shape[0]):
        g = 0.0
        for k in range(6):
            g += J[k, j] * e[k]
        if (q[j] <= lower[j] and g < 0.0) or (q[j] >= upper[j] and g > 0.0):
            g = 0.0
        gradient += g * g
    return math.sqrt(gradient)


@numba.njit(**COMPILE)
def _kind(attempt, best_E, settings):
    """The kind of start of restart ``attempt`` (:func:`_restart_seed`).

    The nearest of random configurations; once an attempt has ended within ``POLISH_ERROR``,
    every third restart starts around the best ``q`` instead.
    """
    if best_E <= settings[POLISH_ERROR] ** 2 and attempt % 3 == 0:
        return _AROUND_BEST
    return _NEAREST


@numba.njit(**COMPILE)
def _restart_seed(chain, Rd, pd, state, kind, counts, best, ws):
    """Into ``ws`` q[0]: the start of a restart, by ``kind``.

    - ``_NEAREST``: the nearest in pose of ``counts[CANDIDATES]`` random configurations,
      distance ``‖p − p_d‖² + (w ‖R − R_d‖_F)²`` with ``w`` = 0.5 m, a reach-sized weight
      that puts radians on the scale of metres: a start near the target converges more
      often than a uniform one, at the price of a few FKs (a fraction of one iteration each);
    - ``_AROUND_BEST``: ``best`` moved by up to ``±PERTURBATION`` of each joint's sampling
      range: an attempt that stopped near a singularity a few µm away is most often beside
      a solution on the other side of it.

    Every start is clipped into the limits when they are respected.
    """
    base, links, revolute, lower, upper, sampling_lower, sampling_upper, _ = chain
    R, p, axes, origins, q = ws[_R][1], ws[_P][1], ws[_AXES][1], ws[_ORIGINS][1], ws[_Q]
    bounded = counts[BOUNDED] != 0
    candidates = counts[CANDIDATES] if kind == _NEAREST else 1
    nearest = np.inf
    for _ in range(candidates):
        for j in range(revolute.shape[0]):
            span = sampling_upper[j] - sampling_lower[j]
            value = sampling_lower[j] + span * _next_uniform(state)
            if kind == _AROUND_BEST:
                value = best[j] + PERTURBATION * span * (2.0 * _next_uniform(state) - 1.0)
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
        if distance < nearest:
            nearest = distance
            q[0] = q[1]


@numba.njit(**COMPILE)
def _solve_target(chain, Rd, pd, q0, state, settings, counts, ws, out, history, errors, record):
    """Attempts from ``q0`` then from random configurations until one converges.

    ``out`` receives the best attempt's ``q``; returns ``(status, iterations, restarts,
    history length, summary)`` with ``summary = (min ‖e‖, max ‖e‖, every ‖Jᵀe‖ ≤ 1e-4 ‖e‖,
    every attempt diverged)`` over the attempts, for the caller's unreachable diagnosis.
    """
    q = ws[_Q]
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
            _restart_seed(chain, Rd, pd, state, _kind(attempts, best_E, settings), counts, out, ws)
        if record:
            work_history[0] = q[0]
        status, iterations, E, gradient = _attempt(
            chain, Rd, pd, settings, counts, ws, work_errors, work_history, record
        )
        if (status == STALLED or status == EXHAUSTED) and E <= settings[POLISH_ERROR] ** 2:
            met, iterations, E, gradient = _polish(
                chain, Rd, pd, settings, counts, ws, work_errors, work_history, record, iterations
            )
            status = CONVERGED if met else status
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
    if best_status != CONVERGED and settings[REACH] > 0.0:
        best_status = UNREACHABLE
    summary = (error_min, error_max, all_stationary, all_diverged)
    return best_status, total, attempts - 1, best_length, summary


@numba.njit(**COMPILE)
def reach_excess(reach, pd):
    """How far (m) ``pd`` lies beyond the ball ``reach = (a_x, a_y, a_z, r)`` (0 inside it).

    No ``q`` puts the frame farther than ``r`` from ``a``
    (:func:`redik.solvers.pose.frame.reach_bound`, :meth:`redik.kinematics.chain.Chain.reach`);
    an excess within round-off (``1e-9 max(1, r)``) counts as inside.
    """
    if not math.isfinite(reach[3]):
        return 0.0
    dx, dy, dz = pd[0] - reach[0], pd[1] - reach[1], pd[2] - reach[2]
    excess = math.sqrt(dx * dx + dy * dy + dz * dz) - reach[3]
    return excess if excess > 1e-9 * max(1.0, reach[3]) else 0.0


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
    excess = reach_excess(reach, pd)
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
    R, p, axes, origins = ws[_R][0], ws[_P][0], ws[_AXES][0], ws[_ORIGINS][0]
    chain_kinematics(base, links, revolute, out, R, p, axes, origins)
    position, angle = pose_error(Rd, pd, R, p, e)
    inside = True
    for j in range(n):
        inside = inside and lower[j] <= out[j] <= upper[j]
    vx, vy, vz = apply_inverse_v(e[3], e[4], e[5], e[0], e[1], e[2])
    body_error = math.sqrt(vx * vx + vy * vy + vz * vz + e[3] * e[3] + e[4] * e[4] + e[5] * e[5])
    return status, total, used, length, (*summary, position, angle, inside, body_error, excess)


@numba.njit(**COMPILE)
def _solve_range(chain, reach, T, q0, first, key, settings, counts, start, stop, results):
    q_out, status, iterations, restarts, position_error, rotation_error = results
    n = chain[2].shape[0]
    ws = _workspace(n)
    state = np.empty(1, dtype=np.uint64)
    errors = np.empty((2, counts[MAX_ITERATIONS] + counts[POLISH_ITERATIONS] + 1))
    history = np.empty((2, 1, n))  # not recorded
    local = settings.copy()
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
        local[REACH] = reach_excess(reach, pd)
        code, count, used, _, _ = _solve_target(
            chain, Rd, pd, q0[t], state, local, counts, ws, q_out[t], history, errors, False
        )
        position, angle, inside = _check(chain, Rd, pd, q_out[t], ws)
        if inside and position <= settings[POS_TOL] and angle <= settings[ROT_TOL]:
            code = CONVERGED
        elif code == CONVERGED:
            code = EXHAUSTED
        status[t], iterations[t], restarts[t] = code, count, used
        position_error[t], rotation_error[t] = position, angle


@numba.njit(inline="always", **COMPILE)
def _check(chain, Rd, pd, q, ws):
    """``(position error, rotation error, inside the limits)`` of ``q`` by a fresh FK.

    The strict verdict on a returned ``q`` (``ws`` rows 1 are overwritten).
    """
    base, links, revolute, lower, upper = chain[0], chain[1], chain[2], chain[3], chain[4]
    R, p, axes, origins, e = ws[_R][1], ws[_P][1], ws[_AXES][1], ws[_ORIGINS][1], ws[_E][1]
    chain_kinematics(base, links, revolute, q, R, p, axes, origins)
    position, angle = pose_error(Rd, pd, R, p, e)
    inside = True
    for j in range(q.shape[0]):
        inside = inside and lower[j] <= q[j] <= upper[j]
    return position, angle, inside


def batch_results(size: int, n: int) -> tuple[np.ndarray, ...]:
    """Output arrays of :func:`solve_serial` and :func:`solve_parallel` for ``size`` targets.

    ``(q (size × n), status (int8), iterations, restarts (int64), position error,
    rotation error)``.
    """
    return (
        np.empty((size, n)),
        np.empty(size, dtype=np.int8),
        np.empty(size, dtype=np.int64),
        np.empty(size, dtype=np.int64),
        np.empty(size),
        np.empty(size),
    )


@numba.njit(**COMPILE)
def solve_serial(chain, reach, T, q0, first, key, settings, counts, results):
    """Solve every target of a chunk on this thread (see :func:`solve_parallel`)."""
    _solve_range(chain, reach, T, q0, first, key, settings, counts, 0, T.shape[0], results)


@numba.njit(parallel=True, **COMPILE)
def solve_parallel(chain, reach, T, q0, first, key, settings, counts, results):
    """Solve every target of a chunk, blocks of targets spread over numba's threads.

    ``T`` (B × 4 × 4) are targets ``first … first + B − 1`` of the batch; ``reach`` the
    chain's reach ``(a_x, a_y, a_z, r)`` (:func:`reach_excess`); ``results`` are the output
    arrays ``(q, status, iterations, restarts, position error, rotation error)``.
    """
    size = T.shape[0]
    blocks = (size + _BLOCK - 1) // _BLOCK
    for block in numba.prange(blocks):
        start = block * _BLOCK
        stop = min(size, start + _BLOCK)
        _solve_range(chain, reach, T, q0, first, key, settings, counts, start, stop, results)
