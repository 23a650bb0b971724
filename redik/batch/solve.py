r"""Damped least squares over a batch of pose targets: :func:`solve_batch`.

Every target runs its own Levenberg–Marquardt iteration (Nocedal & Wright §10.3; Buss,
*Introduction to inverse kinematics with Jacobian transpose, pseudoinverse and damped least
squares methods*, 2004), all of them advanced together by vectorised numpy calls:

.. math::

    Δq = J^\top (J J^\top + λ I_6)^{-1} e, \qquad
    e = \begin{pmatrix} p_d − p \\ \log(R_d R^\top)^\vee \end{pmatrix},

with ``J`` the ``"world"`` Jacobian of :mod:`redik.conventions` (``e`` is the world-frame
pose error, the error twist ``log(T⁻¹ T_d)`` of the conventions rotated to world axes, first
order). The ``6 × 6`` systems are solved by a Cholesky factorisation written out over the
batch. Joints resting on a limit that the step would push outward are held still and the step
re-solved without them; the candidate is then clamped into the limits and accepted for a
target only if it lowers that target's ``‖e‖`` — ``λ`` then shrinks, otherwise it grows and
``q`` stays.

An attempt ends when it converges, stalls (``λ`` past its ceiling, or ``‖e‖²`` not cut by
``progress`` over a ``window`` of iterations) or spends ``max_iterations``. A failed target is
re-seeded from random configurations within the limits, nearest pose first
(:class:`_Codebook`), up to ``restarts`` times. Converged targets leave the active set at
once, so the cost follows the targets still being solved.

Success is **strict**: position error ``‖p_d − p‖ ≤ pos_tol``, rotation angle of ``Rᵀ R_d`` ``≤
rot_tol`` and ``q`` within the limits, checked by a fresh batched FK of the returned ``q``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from ..exceptions import InvalidInput
from ..lie import ROTATION_TOLERANCE
from ..robot import Robot
from .chain import Chain
from .engines import map_chunks
from .kinematics import chain_poses, world_jacobian

BATCH_STATUSES = ("converged", "stalled", "max_iterations", "invalid")
"""Status names by code. The first three are those of :data:`redik.result.STATUSES`;
``"invalid"`` marks a target that is not a finite rigid transform (it is not solved)."""

CONVERGED, STALLED, MAX_ITERATIONS, INVALID = range(len(BATCH_STATUSES))

METHODS = ("dls",)
"""Methods of :func:`solve_batch`: damped least squares (Levenberg–Marquardt)."""

_SMALL_BATCH = 256

CHUNK_SIZE_RANGE = (1024, 8192)
"""Bounds of the automatic chunk size: large enough to vectorise, small enough for the
cache and to give every worker a share of a 10k batch."""


@dataclasses.dataclass(frozen=True)
class BatchOptions:
    """Settings of the batched damped least squares (see :func:`solve_batch`).

    Attributes:
        pos_tol: Position tolerance (m).
        rot_tol: Rotation tolerance (rad).
        max_iterations: Iterations per attempt before a target is re-seeded.
        restarts: Random re-seeds per target after its first attempt.
        damping: Initial ``λ`` of each attempt.
        damping_min, damping_max: ``λ`` bounds; past ``damping_max`` an attempt has stalled.
        damping_down, damping_up: Factors applied to ``λ`` on an accepted / rejected step.
        window, progress: Every ``window`` iterations an attempt must have cut ``‖e‖²`` to
            ``progress`` times its value at the previous check, or it has stalled.
        fanout: Attempts started side by side for a failed target once fewer than
            ``fanout_below`` attempts are in flight (one at a time before).
        codebook: Random configurations ranked by pose distance for the re-seeds.
    """

    pos_tol: float = 1e-6
    rot_tol: float = 1e-5
    max_iterations: int = 60
    restarts: int = 20
    damping: float = 0.1
    damping_min: float = 1e-12
    damping_max: float = 1e6
    damping_down: float = 0.3
    damping_up: float = 5.0
    window: int = 5
    progress: float = 0.5
    fanout: int = 4
    fanout_below: int = 1024
    codebook: int = 512

    def __post_init__(self) -> None:
        for name in ("pos_tol", "rot_tol", "damping", "damping_min", "damping_max"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0.0):
                raise InvalidInput(f"{name} must be a positive number, got {value!r}")
        if self.max_iterations < 1 or self.restarts < 0:
            raise InvalidInput(
                f"max_iterations must be ≥ 1 and restarts ≥ 0, got {self.max_iterations} "
                f"and {self.restarts}"
            )


@dataclasses.dataclass
class BatchResult:
    """Outcome of :func:`solve_batch`, one row per target.

    Attributes:
        q: ``B × n`` joint vectors, always finite and within the limits (for an invalid target
            its seed).
        success: Strict success mask (tolerances and limits, verified by FK of ``q``).
        position_error: ``‖p_d − p‖`` in metres (NaN for an invalid target).
        rotation_error: Angle of ``Rᵀ R_d`` in radians (NaN for an invalid target).
        iterations: Iterations spent on each target, summed over its attempts.
        restarts: Random re-seeds used by each target.
        status: Codes indexing :data:`BATCH_STATUSES`.
    """

    q: np.ndarray
    success: np.ndarray
    position_error: np.ndarray
    rotation_error: np.ndarray
    iterations: np.ndarray
    restarts: np.ndarray
    status: np.ndarray

    STATUSES = BATCH_STATUSES

    def __len__(self) -> int:
        return len(self.success)

    @property
    def status_names(self) -> np.ndarray:
        """``status`` as strings."""
        return np.asarray(BATCH_STATUSES)[self.status]

    @property
    def success_rate(self) -> float:
        """Fraction of targets solved (0 for an empty batch)."""
        return float(np.mean(self.success)) if len(self) else 0.0

    def summary(self) -> str:
        """One line: successes, and the worst errors among them."""
        solved = self.success
        parts = [f"{int(solved.sum())}/{len(self)} solved ({100 * self.success_rate:.2f} %)"]
        if solved.any():
            parts.append(f"max pos {self.position_error[solved].max():.1e} m")
            parts.append(f"max rot {self.rotation_error[solved].max():.1e} rad")
            parts.append(f"mean {self.iterations[solved].mean():.1f} it")
        counts = np.bincount(self.status, minlength=len(BATCH_STATUSES))
        parts += [
            f"{name} {count}" for name, count in zip(BATCH_STATUSES, counts, strict=True) if count
        ]
        return ", ".join(parts)

    @classmethod
    def concatenate(cls, parts: list[BatchResult]) -> BatchResult:
        """The results of consecutive chunks as one."""
        fields = [f.name for f in dataclasses.fields(cls)]
        return cls(**{name: np.concatenate([getattr(p, name) for p in parts]) for name in fields})


# --------------------------------------------------------------------------------------
# Boundary checks


def check_targets(T_targets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(T, valid)``: the targets as a float ``B × 4 × 4`` array and a per-target mask.

    A target is valid when it is finite, ends with ``[0, 0, 0, 1]`` and has a rotation block
    (orthonormal, det +1) within :data:`redik.lie.ROTATION_TOLERANCE`, as :func:`redik.lie.as_pose`
    checks one pose. Malformed targets are reported, not raised.

    Raises:
        InvalidInput: the array is not ``B × 4 × 4``.
    """
    T = np.asarray(T_targets, dtype=float)
    if T.ndim != 3 or T.shape[1:] != (4, 4):
        raise InvalidInput(f"T_targets must have shape (B, 4, 4), got {T.shape}")
    with np.errstate(invalid="ignore"):
        finite = np.isfinite(T).all(axis=(1, 2))
        R = np.where(finite[:, None, None], T[:, :3, :3], np.eye(3))
        gram = np.einsum("bki,bkj->bij", R, R) - np.eye(3)
        valid = (
            finite
            & (np.abs(T[:, 3] - (0.0, 0.0, 0.0, 1.0)).max(axis=1) <= ROTATION_TOLERANCE)
            & (np.abs(gram).max(axis=(1, 2)) <= ROTATION_TOLERANCE)
            & (np.abs(np.linalg.det(R) - 1.0) <= ROTATION_TOLERANCE)
        )
    return T, valid


def check_seeds(chain: Chain, q0: np.ndarray | None, size: int) -> np.ndarray:
    """Seeds as ``B × n`` within the limits: ``q0`` broadcast, or the home configuration.

    Raises:
        InvalidInput: ``q0`` is neither ``(n,)`` nor ``(B, n)``, or holds NaN/inf.
    """
    n = chain.dof
    if q0 is None:
        q0 = chain.home
    q0 = np.asarray(q0, dtype=float)
    if q0.shape not in ((n,), (size, n)):
        raise InvalidInput(f"q0 must have shape ({n},) or ({size}, {n}), got {q0.shape}")
    if not np.all(np.isfinite(q0)):
        raise InvalidInput("q0 holds NaN or inf")
    return np.clip(np.broadcast_to(q0, (size, n)), chain.lower, chain.upper)


# --------------------------------------------------------------------------------------
# Vectorised pieces (batch last: a vector per target is a column)


def _pose_error(
    chain: Chain, q: np.ndarray, Rd: np.ndarray, pd: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(e, J, position_error, rotation_error)`` at ``q`` (``n × A``) for targets ``Rd, pd``."""
    R, p, axes, origins = chain_poses(chain, q)
    J = world_jacobian(chain, p, axes, origins)
    e = np.empty((6, q.shape[1]))
    np.subtract(pd, p, out=e[:3])
    angle = rotation_log(Rd, R, out=e[3:])
    position = np.sqrt(np.einsum("ib,ib->b", e[:3], e[:3]))
    return e, J, position, angle


def rotation_log(Rd: np.ndarray, R: np.ndarray, out: np.ndarray) -> np.ndarray:
    r"""Write ``ω = log(R_d Rᵀ)^∨`` (``3 × A``) into ``out`` and return the angles ``‖ω‖``.

    From the skew part ``s = sin θ u`` and ``cos θ = (tr − 1)/2``, ``θ = atan2(‖s‖, cos θ)``
    is accurate at every angle; near ``θ = π``, where ``s`` loses its direction, the axis
    comes from the symmetric part ``(E + Eᵀ)/2 − cos θ I = (1 − cos θ) u uᵀ``.
    """
    E = np.einsum("ikb,jkb->ijb", Rd, R)
    out[0] = 0.5 * (E[2, 1] - E[1, 2])
    out[1] = 0.5 * (E[0, 2] - E[2, 0])
    out[2] = 0.5 * (E[1, 0] - E[0, 1])
    cos = 0.5 * (E[0, 0] + E[1, 1] + E[2, 2] - 1.0)
    sin = np.sqrt(np.einsum("ib,ib->b", out, out))
    angle = np.arctan2(sin, cos)
    scale = np.divide(angle, sin, out=np.ones_like(angle), where=sin > 1e-300)
    out *= scale
    flipped = np.flatnonzero((cos < 0.0) & (sin < 1e-6))
    if flipped.size:
        sym = 0.5 * (E[:, :, flipped] + E[:, :, flipped].transpose(1, 0, 2))
        sym -= np.eye(3)[:, :, None] * cos[flipped]
        column = np.argmax(np.diagonal(sym).T, axis=0)
        picked = np.take_along_axis(sym, column[None, None], axis=1)[:, 0]
        axis = picked / np.sqrt(np.einsum("ib,ib->b", picked, picked))
        sign = np.where(np.einsum("ib,ib->b", axis, out[:, flipped]) < 0.0, -1.0, 1.0)
        out[:, flipped] = axis * (sign * angle[flipped])
    return angle


def damped_step(J: np.ndarray, e: np.ndarray, damping: np.ndarray) -> np.ndarray:
    r"""``Δq = Jᵀ (J Jᵀ + λ I)⁻¹ e`` for every column: ``J`` is ``6 × n × A``, ``e`` ``6 × A``.

    The symmetric positive-definite ``6 × 6`` systems are solved by Cholesky ``L Lᵀ``,
    forward and back substitution, each entry one vector operation over the batch; below
    ``_SMALL_BATCH`` columns by LAPACK, one system after another.
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


# --------------------------------------------------------------------------------------
# One chunk


class _Codebook:
    """Restart seeds: random configurations ranked by how close their pose is to a target.

    The ``r``-th restart of a target starts from the ``r``-th nearest of ``size`` random
    configurations, by ``‖p − p_d‖² + (w ‖R − R_d‖_F)²`` with ``w`` = 0.5 m, a reach-sized
    weight that puts radians on the scale of metres. Near poses converge more often than
    uniform random seeds, and distinct near configurations are often distinct IK branches.
    """

    _ROTATION_WEIGHT = 0.5

    def __init__(self, chain: Chain, size: int, rng: np.random.Generator):
        self.q = rng.uniform(chain.sampling_lower, chain.sampling_upper, (size, chain.dof))
        R, p, _, _ = chain_poses(chain, np.ascontiguousarray(self.q.T))
        self.features = self._features(R.transpose(2, 0, 1), p.T)
        self.squared = np.einsum("ij,ij->i", self.features, self.features)

    def _features(self, R: np.ndarray, p: np.ndarray) -> np.ndarray:
        return np.concatenate((p, self._ROTATION_WEIGHT * R.reshape(-1, 9)), axis=1)

    def nearest(self, T: np.ndarray, count: int) -> np.ndarray:
        """``len(T) × count`` codebook indices, nearest pose first, for each target ``T[i]``."""
        distance = self.squared - 2.0 * self._features(T[:, :3, :3], T[:, :3, 3]) @ self.features.T
        count = min(count, distance.shape[1])
        nearest = np.argpartition(distance, count - 1, axis=1)[:, :count]
        order = np.argsort(np.take_along_axis(distance, nearest, axis=1), axis=1, kind="stable")
        return np.take_along_axis(nearest, order, axis=1)


@dataclasses.dataclass
class _Attempts:
    """The attempts in flight, one column each; several may serve the same target."""

    target: np.ndarray  # (A,) index of the target in the chunk
    q: np.ndarray  # (n, A)
    Rd: np.ndarray  # (3, 3, A)
    pd: np.ndarray  # (3, A)
    e: np.ndarray  # (6, A)
    J: np.ndarray  # (6, n, A)
    norm: np.ndarray  # ‖e‖²
    position: np.ndarray
    angle: np.ndarray
    damping: np.ndarray
    count: np.ndarray  # iterations of this attempt
    reference: np.ndarray  # ‖e‖² at the last progress check

    @classmethod
    def start(
        cls,
        chain: Chain,
        target: np.ndarray,
        q: np.ndarray,
        Rd: np.ndarray,
        pd: np.ndarray,
        options: BatchOptions,
    ) -> _Attempts:
        e, J, position, angle = _pose_error(chain, q, Rd, pd)
        norm = np.einsum("ib,ib->b", e, e)
        size = len(target)
        return cls(
            target=target,
            q=q,
            Rd=Rd,
            pd=pd,
            e=e,
            J=J,
            norm=norm,
            position=position,
            angle=angle,
            damping=np.full(size, options.damping),
            count=np.zeros(size, dtype=np.int64),
            reference=norm.copy(),
        )

    def __len__(self) -> int:
        return len(self.target)

    def select(self, mask: np.ndarray) -> _Attempts:
        return _Attempts(**{f.name: getattr(self, f.name)[..., mask] for f in _ATTEMPT_FIELDS})

    def extend(self, other: _Attempts) -> _Attempts:
        return _Attempts(
            **{
                f.name: np.concatenate((getattr(self, f.name), getattr(other, f.name)), axis=-1)
                for f in _ATTEMPT_FIELDS
            }
        )


_ATTEMPT_FIELDS = dataclasses.fields(_Attempts)


def solve_chunk(
    chain: Chain,
    T_targets: np.ndarray,
    q0: np.ndarray,
    options: BatchOptions,
    seed: np.random.SeedSequence,
) -> BatchResult:
    """Solve one chunk in this process: the unit of work of every engine.

    ``T_targets`` is ``B × 4 × 4`` (invalid targets allowed), ``q0`` ``B × n`` within limits;
    the random re-seeds come from ``seed`` alone, so a chunk's result does not depend on where
    it runs. Each target starts one attempt from its seed; a target whose attempts have all
    failed is re-seeded from :class:`_Codebook`, with up to ``fanout`` attempts side by side
    once few attempts are left, so the hardest targets are not retried one after another.
    """
    rng = np.random.default_rng(seed)
    T, valid = check_targets(T_targets)
    size = len(q0)
    q_out = np.array(q0, dtype=float).T.copy()  # n × B, batch last
    iterations = np.zeros(size, dtype=np.int64)
    restarts = np.zeros(size, dtype=np.int64)
    status = np.full(size, INVALID, dtype=np.int8)
    best = np.full(size, np.inf)
    done = ~valid

    Rd_all = np.ascontiguousarray(T[:, :3, :3].transpose(1, 2, 0))
    pd_all = np.ascontiguousarray(T[:, :3, 3].T)
    index = np.flatnonzero(valid)
    attempts = _Attempts.start(
        chain, index, q_out[:, index].copy(), Rd_all[..., index], pd_all[:, index], options
    )
    lower, upper = chain.lower[:, None], chain.upper[:, None]
    codebook = _Codebook(chain, max(options.codebook, options.restarts), rng)
    ranked = np.zeros((size, options.restarts), dtype=np.int64)

    while len(attempts):
        a = attempts
        converged = (a.position <= options.pos_tol) & (a.angle <= options.rot_tol)
        # Progress check every `window` iterations: an attempt that has not cut ‖e‖² by the
        # factor `progress` since the last check is in a local minimum or crawling.
        checkpoint = (a.count > 0) & (a.count % options.window == 0)
        stalled = (a.damping > options.damping_max) | (
            checkpoint & (a.norm > options.progress * a.reference)
        )
        a.reference = np.where(checkpoint, a.norm, a.reference)
        ended = converged | stalled | (a.count >= options.max_iterations)
        if ended.any():
            reason = np.where(converged, CONVERGED, np.where(stalled, STALLED, MAX_ITERATIONS))
            _keep_best(a, ended, reason, q_out, best, status)
            done[a.target[converged]] = True
            attempts = a.select(~ended & ~done[a.target])
            failed = np.unique(a.target[ended & ~converged])
            orphans = failed[~done[failed] & ~np.isin(failed, attempts.target)]
            # Side-by-side retries only pay when few attempts are left to vectorise over.
            width = options.fanout if len(attempts) < options.fanout_below else 1
            count = np.clip(options.restarts - restarts[orphans], 0, width)
            ids = np.repeat(orphans, count)
            if ids.size:
                first = orphans[restarts[orphans] == 0]  # rank their seeds once
                if first.size:
                    ranked[first] = codebook.nearest(T[first], options.restarts)
                # The k-th new attempt of a target takes its next unused rank.
                offset = np.arange(ids.size) - np.repeat(np.cumsum(count) - count, count)
                fresh = np.ascontiguousarray(codebook.q[ranked[ids, restarts[ids] + offset]].T)
                restarts[orphans] += count
                attempts = attempts.extend(
                    _Attempts.start(chain, ids, fresh, Rd_all[..., ids], pd_all[:, ids], options)
                )
            if not len(attempts):
                break
        _iterate(chain, attempts, lower, upper, options)
        iterations += np.bincount(attempts.target, minlength=size)

    return _verified(chain, T, valid, q_out.T, iterations, restarts, status, options)


def _keep_best(
    a: _Attempts,
    ended: np.ndarray,
    reason: np.ndarray,
    q_out: np.ndarray,
    best: np.ndarray,
    status: np.ndarray,
) -> None:
    """Store each ended attempt's ``q`` and reason where it beats its target's best so far.

    A converged attempt always wins; among several ending together the smallest ‖e‖ wins.
    """
    ids = a.target[ended]
    score = np.where(reason[ended] == CONVERGED, -1.0, a.norm[ended])
    order = np.lexsort((score, ids))
    first = order[np.unique(ids[order], return_index=True)[1]]
    ids, score = ids[first], score[first]
    better = score < best[ids]
    ids = ids[better]
    q_out[:, ids] = a.q[:, ended][:, first[better]]
    best[ids] = score[better]
    status[ids] = reason[ended][first[better]]


def _iterate(
    chain: Chain, a: _Attempts, lower: np.ndarray, upper: np.ndarray, options: BatchOptions
) -> None:
    """One damped least-squares iteration of every attempt, accepted where ‖e‖ drops."""
    candidate = a.q + damped_step(a.J, a.e, a.damping)
    # A joint resting on a limit that the step pushes outward is held still and the step
    # re-solved without it: clamping alone would leave the other joints' share unchanged.
    blocked = ((candidate < lower) & (a.q <= lower)) | ((candidate > upper) & (a.q >= upper))
    rows = np.flatnonzero(blocked.any(axis=0))
    if rows.size:
        J_free = a.J[:, :, rows] * ~blocked[None, :, rows]
        candidate[:, rows] = a.q[:, rows] + damped_step(J_free, a.e[:, rows], a.damping[rows])
    np.clip(candidate, lower, upper, out=candidate)
    e, J, position, angle = _pose_error(chain, candidate, a.Rd, a.pd)
    norm = np.einsum("ib,ib->b", e, e)
    accept = norm < a.norm
    # Most steps are accepted: take the new arrays whole and put back the few rejected.
    reject = np.flatnonzero(~accept)
    for name, new in (("e", e), ("J", J), ("norm", norm), ("position", position), ("angle", angle)):
        new[..., reject] = getattr(a, name)[..., reject]
        setattr(a, name, new)
    candidate[:, reject] = a.q[:, reject]
    a.q = candidate
    a.damping = np.where(
        accept,
        np.maximum(a.damping * options.damping_down, options.damping_min),
        a.damping * options.damping_up,
    )
    a.count += 1


def _verified(
    chain: Chain,
    T: np.ndarray,
    valid: np.ndarray,
    q: np.ndarray,
    iterations: np.ndarray,
    restarts: np.ndarray,
    status: np.ndarray,
    options: BatchOptions,
) -> BatchResult:
    """Errors and strict success from a fresh batched FK of the returned ``q``."""
    position = np.full(len(q), np.nan)
    rotation = np.full(len(q), np.nan)
    index = np.flatnonzero(valid)
    R, p, _, _ = chain_poses(chain, np.ascontiguousarray(q[index].T))
    position[index] = np.linalg.norm(T[index, :3, 3].T - p, axis=0)
    rotation[index] = rotation_log(
        np.ascontiguousarray(T[index, :3, :3].transpose(1, 2, 0)), R, out=np.empty((3, index.size))
    )
    within = np.all((q >= chain.lower) & (q <= chain.upper), axis=1)
    success = valid & within & (position <= options.pos_tol) & (rotation <= options.rot_tol)
    status = np.where(success, CONVERGED, np.where(status == CONVERGED, MAX_ITERATIONS, status))
    return BatchResult(
        q=q,
        success=success,
        position_error=position,
        rotation_error=rotation,
        iterations=iterations,
        restarts=restarts,
        status=status.astype(np.int8),
    )


def solve_batch(
    robot: Robot | Chain,
    T_targets: np.ndarray,
    q0: np.ndarray | None = None,
    method: str = "dls",
    pos_tol: float = 1e-6,
    rot_tol: float = 1e-5,
    restarts: int = 20,
    seed: int | np.random.SeedSequence | None = None,
    engine: str = "process",
    workers: int | None = None,
    address: str | None = None,
    chunk_size: int | None = None,
    max_iterations: int = 60,
    progress: Callable[[int], None] | None = None,
) -> BatchResult:
    """Solve ``B`` pose targets at once; strict success per target (see the module docstring).

    Args:
        robot: The robot, or its compiled :class:`~redik.batch.chain.Chain` (to compile once
            for many calls).
        T_targets: ``B × 4 × 4`` desired end-effector poses ``T_wd``. A target that is not a
            finite rigid transform is reported with status ``"invalid"``; the others are solved.
        q0: Seeds, ``(n,)`` for all or ``(B, n)``; default the robot's home configuration.
        method: ``"dls"``, damped least squares (Levenberg–Marquardt).
        pos_tol, rot_tol: Position (m) and rotation (rad) tolerances.
        restarts: Random re-seeds allowed per target after its first attempt.
        seed: Seed of the re-seeds; the same seed gives the same result on every engine and
            worker count.
        engine: ``"process"`` (all cores of this machine, the default), ``"local"`` (this
            process only) or ``"ray"``; see :mod:`redik.batch.engines`.
        workers: Processes or Ray CPUs; default every core.
        address: Ray cluster address (``engine="ray"``); default a local Ray instance.
        chunk_size: Targets per chunk, the unit of work (and of memory) of every engine;
            default a quarter of the batch within :data:`CHUNK_SIZE_RANGE`. It depends on
            the batch only, never on the workers, so results do not either.
        max_iterations: Iterations per attempt.
        progress: Called with the number of targets in each finished chunk.

    Returns:
        A :class:`BatchResult` with one row per target.

    Raises:
        InvalidInput: ``T_targets`` is not ``B × 4 × 4``, a bad ``q0``, method, engine or
            tolerance.
    """
    if method not in METHODS:
        raise InvalidInput(f"method must be one of {METHODS}, got {method!r}")
    if chunk_size is not None and chunk_size < 1:
        raise InvalidInput(f"chunk_size must be a positive integer, got {chunk_size!r}")
    chain = robot if isinstance(robot, Chain) else Chain.from_robot(robot)
    options = BatchOptions(
        pos_tol=pos_tol, rot_tol=rot_tol, restarts=restarts, max_iterations=max_iterations
    )
    T = np.asarray(T_targets, dtype=float)
    if T.ndim != 3 or T.shape[1:] != (4, 4):
        raise InvalidInput(f"T_targets must have shape (B, 4, 4), got {T.shape}")
    size = len(T)
    seeds = check_seeds(chain, q0, size)
    if chunk_size is None:
        chunk_size = int(np.clip(-(-size // 4), *CHUNK_SIZE_RANGE))
    starts = range(0, max(size, 1), chunk_size)  # an empty batch is one empty chunk
    root = seed if isinstance(seed, np.random.SeedSequence) else np.random.SeedSequence(seed)
    chunk_seeds = root.spawn(len(starts))
    chunks = (
        (T[start : start + chunk_size], seeds[start : start + chunk_size], chunk_seed)
        for start, chunk_seed in zip(starts, chunk_seeds, strict=True)
    )
    parts = map_chunks(
        _solve_chunk_task,
        (chain, options),
        chunks,
        engine=engine,
        workers=workers,
        address=address,
        on_result=None if progress is None else lambda part: progress(len(part)),
    )
    return BatchResult.concatenate(parts)


def _solve_chunk_task(
    shared: tuple[Chain, BatchOptions],
    T_targets: np.ndarray,
    q0: np.ndarray,
    seed: np.random.SeedSequence,
) -> BatchResult:
    chain, options = shared
    return solve_chunk(chain, T_targets, q0, options, seed)
