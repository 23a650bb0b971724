r"""The compiled damped least-squares kernel: one Levenberg–Marquardt solve per target.

Every pose solver of redik that uses damped least squares — :func:`redik.batch.solve_batch`
over many targets and :func:`redik.solve_pose` with ``method="dls"`` for one — runs this
kernel, compiled by numba (``cache=True``: once per machine, a few seconds). Per target it is
scalar code on a handful of 3-vectors and one small matrix, which numpy cannot vectorise well
across a shrinking set of unsolved targets; compiled, one iteration of a 7-joint arm costs
well under a microsecond. Targets are independent, so the batch entry point spreads them
over threads with ``numba.prange``.

The chain is that of :class:`~redik.batch.chain.Chain`, ``T(q) = F_0 M_1(q_1) F_1 ⋯ M_n(q_n)
F_n``; FK walks it joint by joint and the world Jacobian (``"world"`` in
:mod:`redik.conventions`) follows from each joint's world axis ``ω_i`` and origin ``o_i``:
``J_i = (ω_i × (p − o_i), ω_i)`` for a hinge, ``(ω_i, 0)`` for a slide.

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
earlier), diverged (a non-finite step) or at ``max_iter``. A target that failed restarts from
random configurations drawn uniformly within the sampling bounds by its own generator
(splitmix64 seeded from the key and the target's index), so a result does not depend on
chunking, threads or processes. The best attempt wins: a converged one, else the smallest
``‖e‖``. The batch entry point finally checks each target strictly by a fresh FK of its
returned ``q``.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from ..lie import MAX_COORDINATE

CONVERGED, STALLED, MAX_ITERATIONS, INVALID, DIVERGED = range(5)
"""Status codes, shared with :data:`redik.batch.solve.BATCH_STATUSES`."""

# Indices into the float and integer settings arrays (few arguments keep the call cheap).
POS_TOL, ROT_TOL, DAMPING, MIN_DAMPING, MAX_DAMPING, REQUIRED, REACH, TARGET_TOL = range(8)
MAX_ITER, RESTARTS, PATIENCE, BOUNDED, CANDIDATES = range(5)

_COMPILE = {"cache": True, "error_model": "numpy", "fastmath": {"contract"}}
"""Compiled once per machine; a division by zero gives inf or NaN as in numpy (every such
result is caught as a non-finite step), not a Python exception, so divisions carry no
checks; fused multiply-adds are allowed (no reassociation: results stay reproducible)."""

_BLOCK = 16
"""Targets per parallel work item: small enough to balance the threads on hard tails."""

_GAMMA = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)
_STREAM = np.uint64(0xD1B54A32D192ED03)
_TWO_TO_MINUS_53 = 2.0**-53


@numba.njit(**_COMPILE)
def _next_uniform(state: np.ndarray) -> float:
    """A double in [0, 1) from the splitmix64 generator whose state is ``state[0]``."""
    state[0] += _GAMMA
    z = state[0]
    z = (z ^ (z >> np.uint64(30))) * _MIX1
    z = (z ^ (z >> np.uint64(27))) * _MIX2
    z = z ^ (z >> np.uint64(31))
    return float(z >> np.uint64(11)) * _TWO_TO_MINUS_53


@numba.njit(**_COMPILE)
def valid_target(T, tol):
    """True when ``T`` is a finite rigid transform: last row ``[0, 0, 0, 1]``, ``RᵀR = I``
    and ``det R = 1``, each within ``tol``, and a translation within ``±MAX_COORDINATE``
    (the checks of :func:`redik.lie.as_pose`)."""
    for a in range(4):
        for b in range(4):
            if not math.isfinite(T[a, b]):
                return False
    if abs(T[0, 3]) > MAX_COORDINATE or abs(T[1, 3]) > MAX_COORDINATE:
        return False
    if abs(T[2, 3]) > MAX_COORDINATE:
        return False
    if abs(T[3, 0]) > tol or abs(T[3, 1]) > tol or abs(T[3, 2]) > tol or abs(T[3, 3] - 1.0) > tol:
        return False
    for a in range(3):
        for b in range(a + 1):
            product = T[0, a] * T[0, b] + T[1, a] * T[1, b] + T[2, a] * T[2, b]
            if abs(product - (1.0 if a == b else 0.0)) > tol:
                return False
    det = (
        T[0, 0] * (T[1, 1] * T[2, 2] - T[1, 2] * T[2, 1])
        - T[0, 1] * (T[1, 0] * T[2, 2] - T[1, 2] * T[2, 0])
        + T[0, 2] * (T[1, 0] * T[2, 1] - T[1, 1] * T[2, 0])
    )
    return abs(det - 1.0) <= tol


@numba.njit(parallel=True, **_COMPILE)
def valid_targets(T, tol, out):
    """``out[t]`` = :func:`valid_target` of each ``T[t]`` (B × 4 × 4), over every thread."""
    for t in numba.prange(T.shape[0]):
        out[t] = valid_target(T[t], tol)


@numba.njit(**_COMPILE)
def chain_kinematics(base, links, revolute, q, R, p, axes, origins):
    """FK of the chain at ``q`` into ``R`` (3 × 3) and ``p``, with each joint's world axis
    and origin into ``axes`` and ``origins`` (n × 3)."""
    for a in range(3):
        p[a] = base[a, 3]
        for b in range(3):
            R[a, b] = base[a, b]
    for i in range(q.shape[0]):
        for a in range(3):
            axes[i, a] = R[a, 2]
            origins[i, a] = p[a]
        if revolute[i]:  # R · R_z(q): the x and y columns turn
            c, s = math.cos(q[i]), math.sin(q[i])
            for a in range(3):
                x, y = R[a, 0], R[a, 1]
                R[a, 0] = c * x + s * y
                R[a, 1] = c * y - s * x
        else:
            for a in range(3):
                p[a] += R[a, 2] * q[i]
        for a in range(3):
            r0, r1, r2 = R[a, 0], R[a, 1], R[a, 2]
            p[a] += r0 * links[i, 0, 3] + r1 * links[i, 1, 3] + r2 * links[i, 2, 3]
            for b in range(3):
                R[a, b] = r0 * links[i, 0, b] + r1 * links[i, 1, b] + r2 * links[i, 2, b]


@numba.njit(**_COMPILE)
def world_jacobian(revolute, p, axes, origins, J):
    """The world Jacobian (6 × n) from :func:`chain_kinematics`' axes and origins."""
    for i in range(revolute.shape[0]):
        ax, ay, az = axes[i, 0], axes[i, 1], axes[i, 2]
        if revolute[i]:
            dx, dy, dz = p[0] - origins[i, 0], p[1] - origins[i, 1], p[2] - origins[i, 2]
            J[0, i] = ay * dz - az * dy
            J[1, i] = az * dx - ax * dz
            J[2, i] = ax * dy - ay * dx
            J[3, i], J[4, i], J[5, i] = ax, ay, az
        else:
            J[0, i], J[1, i], J[2, i] = ax, ay, az
            J[3, i] = J[4, i] = J[5, i] = 0.0


@numba.njit(**_COMPILE)
def pose_error(Rd, pd, R, p, e):
    r"""Fill ``e = (p_d − p, log(R_d Rᵀ)^∨)``; return ``(‖p_d − p‖, rotation angle)``.

    From the skew part ``s = sin θ u`` and ``cos θ = (tr − 1)/2``, ``θ = atan2(‖s‖, cos θ)``
    is accurate at every angle; near ``θ = π``, where ``s`` loses its direction, the axis
    comes from the symmetric part ``(E + Eᵀ)/2 − cos θ I = (1 − cos θ) u uᵀ``.
    """
    for i in range(3):
        e[i] = pd[i] - p[i]
    # E = R_d Rᵀ, entry by entry (no temporary array in the hot loop).
    e00 = Rd[0, 0] * R[0, 0] + Rd[0, 1] * R[0, 1] + Rd[0, 2] * R[0, 2]
    e01 = Rd[0, 0] * R[1, 0] + Rd[0, 1] * R[1, 1] + Rd[0, 2] * R[1, 2]
    e02 = Rd[0, 0] * R[2, 0] + Rd[0, 1] * R[2, 1] + Rd[0, 2] * R[2, 2]
    e10 = Rd[1, 0] * R[0, 0] + Rd[1, 1] * R[0, 1] + Rd[1, 2] * R[0, 2]
    e11 = Rd[1, 0] * R[1, 0] + Rd[1, 1] * R[1, 1] + Rd[1, 2] * R[1, 2]
    e12 = Rd[1, 0] * R[2, 0] + Rd[1, 1] * R[2, 1] + Rd[1, 2] * R[2, 2]
    e20 = Rd[2, 0] * R[0, 0] + Rd[2, 1] * R[0, 1] + Rd[2, 2] * R[0, 2]
    e21 = Rd[2, 0] * R[1, 0] + Rd[2, 1] * R[1, 1] + Rd[2, 2] * R[1, 2]
    e22 = Rd[2, 0] * R[2, 0] + Rd[2, 1] * R[2, 1] + Rd[2, 2] * R[2, 2]
    sx, sy, sz = 0.5 * (e21 - e12), 0.5 * (e02 - e20), 0.5 * (e10 - e01)
    cos = 0.5 * (e00 + e11 + e22 - 1.0)
    sin = math.sqrt(sx * sx + sy * sy + sz * sz)
    angle = math.atan2(sin, cos)
    scale = angle / sin if sin > 1e-300 else 1.0
    e[3], e[4], e[5] = sx * scale, sy * scale, sz * scale
    if cos < 0.0 and sin < 1e-6:
        # The column of the largest diagonal entry of the symmetric part is the best axis.
        if e00 >= e11 and e00 >= e22:
            ux, uy, uz = e00 - cos, 0.5 * (e10 + e01), 0.5 * (e20 + e02)
        elif e11 >= e22:
            ux, uy, uz = 0.5 * (e01 + e10), e11 - cos, 0.5 * (e21 + e12)
        else:
            ux, uy, uz = 0.5 * (e02 + e20), 0.5 * (e12 + e21), e22 - cos
        norm = math.sqrt(ux * ux + uy * uy + uz * uz)
        sign = -1.0 if ux * e[3] + uy * e[4] + uz * e[5] < 0.0 else 1.0
        scale = sign * angle / norm
        e[3], e[4], e[5] = ux * scale, uy * scale, uz * scale
    position = math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
    return position, angle


@numba.njit(**_COMPILE)
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


@numba.njit(**_COMPILE)
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


@numba.njit(**_COMPILE)
def damped_solve(J, free, e, damping, A, y, dq):
    r"""``dq = J_fᵀ (J_f J_fᵀ + λI)⁻¹ e`` (``n ≥ 6``) or ``(J_fᵀJ_f + λI)⁻¹ J_fᵀ e``, where
    ``J_f`` is ``J`` with the columns not ``free`` zeroed (their ``dq`` is 0)."""
    G = np.empty_like(A)
    gram(J, G)
    damped_solve_gram(J, G, free, e, damping, A, y, dq)


@numba.njit(**_COMPILE)
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


@numba.njit(**_COMPILE)
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
    max_iter, patience, bounded = counts[MAX_ITER], counts[PATIENCE], counts[BOUNDED] != 0

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
    status = MAX_ITERATIONS
    iterations = 0
    ended = False
    while iterations < max_iter:
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


@numba.njit(**_COMPILE)
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


@numba.njit(**_COMPILE)
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


@numba.njit(**_COMPILE)
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


@numba.njit(**_COMPILE)
def solve_one(chain, T, q0, key, settings, counts, out, history, errors, e):
    """:func:`_solve_target` for one target ``T`` (4 × 4) from ``q0`` (clipped into the limits
    when they are respected), recording the best attempt's history into ``history[1]`` and
    ``errors[1]`` (``history`` is 2 × (at least max_iter + 1) × n).

    A fresh FK of the returned ``q`` fills ``e`` with the world error there; its position
    and rotation errors, and whether ``q`` is inside the limits, are appended to the summary.
    """
    base, links, revolute, lower, upper = chain[0], chain[1], chain[2], chain[3], chain[4]
    n = revolute.shape[0]
    ws = _workspace(n)
    state = np.empty(1, dtype=np.uint64)
    state[0] = key
    Rd, pd = T[:3, :3], T[:3, 3]
    start = np.empty(n)
    for j in range(n):
        start[j] = min(max(q0[j], lower[j]), upper[j]) if counts[BOUNDED] != 0 else q0[j]
    status, total, used, length, summary = _solve_target(
        chain, Rd, pd, start, state, settings, counts, ws, out, history, errors, True
    )
    R, p, axes, origins = ws[0][0], ws[1][0], ws[2][0], ws[3][0]
    chain_kinematics(base, links, revolute, out, R, p, axes, origins)
    position, angle = pose_error(Rd, pd, R, p, e)
    inside = True
    for j in range(n):
        inside = inside and lower[j] <= out[j] <= upper[j]
    return status, total, used, length, (*summary, position, angle, inside)


@numba.njit(**_COMPILE)
def _solve_range(chain, T, q0, first, key, settings, counts, start, stop, results):
    q_out, status, iterations, restarts, position_error, rotation_error = results
    base, links, revolute, lower, upper = chain[0], chain[1], chain[2], chain[3], chain[4]
    n = revolute.shape[0]
    ws = _workspace(n)
    state = np.empty(1, dtype=np.uint64)
    errors = np.empty((2, counts[MAX_ITER] + 1))
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
            code = MAX_ITERATIONS
        status[t], iterations[t], restarts[t] = code, count, used
        position_error[t], rotation_error[t] = position, angle


@numba.njit(**_COMPILE)
def solve_serial(chain, T, q0, first, key, settings, counts, results):
    """Solve every target of a chunk on this thread (see :func:`solve_parallel`)."""
    _solve_range(chain, T, q0, first, key, settings, counts, 0, T.shape[0], results)


@numba.njit(parallel=True, **_COMPILE)
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
