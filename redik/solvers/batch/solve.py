r"""Damped least squares over a batch of pose targets: :func:`solve_batch`.

Every target runs its own Levenberg–Marquardt solve (Nocedal & Wright §10.3; Buss,
*Introduction to inverse kinematics with Jacobian transpose, pseudoinverse and damped least
squares methods*, 2004) in the compiled kernel of :mod:`redik.solvers.dls`, which states
the iteration, the joint-limit handling and the restarts:

.. math::

    Δq = J^\top (J J^\top + λ I_6)^{-1} e, \qquad λ = μ\,‖e‖^2 + λ_{min}, \qquad
    e = \begin{pmatrix} p_d − p \\ \log(R_d R^\top)^\vee \end{pmatrix},

with ``J`` the ``"world"`` Jacobian of :mod:`redik.core.conventions`. A failed target restarts
from random configurations within the limits, up to ``restarts`` times; each target's random
stream comes from ``(seed, its index in the batch)`` alone, so results do not depend on the
chunk size, the engine or the number of workers. The batch is cut into chunks (the unit of
work and memory of every engine); on the ``"local"`` engine the targets of a chunk are spread
over numba's threads, on ``"process"`` and ``"ray"`` each worker solves whole chunks.

Success is **strict**: position error ``‖p_d − p‖ ≤ pos_tol``, rotation angle of ``Rᵀ R_d`` ``≤
rot_tol`` and ``q`` within the limits, checked by a fresh FK of the returned ``q``.
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
from collections.abc import Callable, Iterator

import numba
import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.result import Status
from redik.core.rotation_policy import ROTATION_TOLERANCE, check_rotations
from redik.core.validate import MAX_COORDINATE, integer, real_array
from redik.core.validate import seed as check_seed
from redik.kinematics.chain import Chain
from redik.kinematics.compiled import valid_targets
from redik.kinematics.robot import Robot
from redik.solvers import dls
from redik.solvers.batch.checkpoint import Checkpoint, batch_fingerprint
from redik.solvers.batch.engines import ENGINES, Engine, as_engine
from redik.solvers.dls import DLSOptions

BATCH_STATUSES = (
    Status.CONVERGED,
    Status.STALLED,
    Status.MAX_ITERATIONS,
    Status.INVALID,
    Status.DIVERGED,
    Status.UNREACHABLE,
)
"""The :class:`~redik.core.result.Status` of each code of :mod:`redik.solvers.dls` (the
compiled kernel reports integers); ``INVALID`` marks a target that is not a finite rigid
transform (it is not solved), ``UNREACHABLE`` one beyond the chain's reach
(:meth:`~redik.kinematics.chain.Chain.reach`, the bound :func:`redik.solve_pose` tests)."""

METHODS = ("dls",)
"""Methods of :func:`solve_batch`: damped least squares (Levenberg–Marquardt)."""

CHUNK_SIZE_RANGE = (1024, 16384)
"""Bounds of the automatic chunk size: enough targets to keep every thread busy, few enough
to bound memory and to give every worker a share of a 10k batch."""


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
        status: Codes indexing :data:`BATCH_STATUSES` (``statuses`` has them as
            :class:`~redik.core.result.Status` members, ``status_names`` as strings).
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
    def statuses(self) -> list[Status]:
        """``status`` as :class:`~redik.core.result.Status` members, one per target."""
        return [BATCH_STATUSES[code] for code in self.status.tolist()]

    @property
    def status_names(self) -> np.ndarray:
        """``status`` as a numpy array of strings (the values of :attr:`statuses`)."""
        return np.asarray([status.value for status in BATCH_STATUSES])[self.status]

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


def check_targets(T_targets: np.ndarray, strict: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """``(T, valid)``: the targets as a float ``B × 4 × 4`` array and a per-target mask.

    A target is valid when it is finite, ends with ``[0, 0, 0, 1]``, has a translation within
    ``±``:data:`redik.core.validate.MAX_COORDINATE` and a rotation block
    accepted by the tolerance policy (:mod:`redik.core.rotation_policy`), as
    :func:`~redik.core.rotation_policy.as_pose` checks one pose: near-rotations come back projected
    onto SO(3) (one warning), or invalid when ``strict``. Malformed targets are reported, not
    raised.

    Raises:
        InvalidInput: the array is not ``B × 4 × 4`` real numbers.
    """
    T = real_array(T_targets, "T_targets")
    if T.ndim != 3 or T.shape[1:] != (4, 4):
        raise InvalidInput(f"T_targets must have shape (B, 4, 4), got {T.shape}")
    T = np.ascontiguousarray(T)
    # Compiled and on every core: the exact rigid transforms, nearly all of a batch, which a
    # serial numpy pass would hold up beside the parallel solves. The policy sees the rest.
    valid = np.empty(len(T), dtype=bool)
    valid_targets(T, ROTATION_TOLERANCE, valid)
    if valid.all():
        return T, valid
    rest = np.flatnonzero(~valid)
    with np.errstate(invalid="ignore"):
        finite = np.isfinite(T[rest]).all(axis=(1, 2))
        bottom = np.abs(T[rest, 3] - (0.0, 0.0, 0.0, 1.0)).max(axis=1, initial=0.0)
        far = np.abs(T[rest, :3, 3]).max(axis=1, initial=0.0)
        well_formed = finite & (bottom <= ROTATION_TOLERANCE) & (far <= MAX_COORDINATE)
    block = np.where(well_formed[:, None, None], T[rest, :3, :3], np.eye(3))
    R, accepted = check_rotations(block, "T_targets[:, :3, :3]", strict=strict)
    if R is not block:
        T = T.copy()
        T[rest, :3, :3] = np.where(well_formed[:, None, None], R, T[rest, :3, :3])
    valid[rest] = well_formed & accepted
    return T, valid


def check_seeds(chain: Chain, q0: np.ndarray | None, size: int) -> np.ndarray:
    """Seeds as ``B × n`` within the limits: ``q0`` broadcast, or the home configuration.

    Raises:
        InvalidInput: ``q0`` is neither ``(n,)`` nor ``(B, n)``, or holds NaN/inf.
    """
    n = chain.dof
    if q0 is None:
        q0 = chain.home
    q0 = real_array(q0, "q0")
    if q0.shape not in ((n,), (size, n)):
        raise InvalidInput(f"q0 must have shape ({n},) or ({size}, {n}), got {q0.shape}")
    if not np.all(np.isfinite(q0)):
        raise InvalidInput("q0 holds NaN or inf")
    return np.clip(np.broadcast_to(q0, (size, n)), chain.lower, chain.upper)


# --------------------------------------------------------------------------------------
# --------------------------------------------------------------------------------------
# One chunk


def solve_chunk(
    chain: Chain,
    T_targets: np.ndarray,
    q0: np.ndarray,
    options: DLSOptions,
    key: int,
    first: int = 0,
    parallel: bool = False,
) -> BatchResult:
    """Solve one chunk in this process: the unit of work of every engine.

    ``T_targets`` is ``B × 4 × 4``, ``q0`` ``B × n`` within limits, the targets ``first …
    first + B − 1`` of the batch; their random re-seeds depend on ``key`` and those indices
    alone. ``parallel`` spreads the targets over numba's threads. A target that is not a
    finite rigid transform (:func:`redik.kinematics.compiled.valid_target`, checked in the
    compiled code beside the solve) gets status ``"invalid"``.
    """
    T = np.ascontiguousarray(T_targets, dtype=float)
    size = len(T)
    results = dls.batch_results(size, chain.dof)
    settings, counts = options.kernel_settings()
    solve = dls.solve_parallel if parallel else dls.solve_serial
    centre, radius = chain.reach()
    reach = np.array([*centre, radius])
    solve(
        chain.kernel_arrays(), reach, T, np.ascontiguousarray(q0, dtype=float),
        np.int64(first), np.uint64(key), settings, counts, results,
    )  # fmt: skip
    q, status, iterations, restarts, position, rotation = results
    return BatchResult(
        q=q,
        success=status == dls.CONVERGED,
        position_error=position,
        rotation_error=rotation,
        iterations=iterations,
        restarts=restarts,
        status=status,
    )


def solve_batch(
    robot: Robot | Chain,
    T_targets: np.ndarray,
    q0: np.ndarray | None = None,
    method: str = "dls",
    pos_tol: float = 1e-6,
    rot_tol: float = 1e-5,
    restarts: int = DLSOptions.restarts,
    seed: int | None = None,
    engine: str | Engine = "local",
    workers: int | None = None,
    address: str | None = None,
    chunk_size: int | None = None,
    max_iterations: int = DLSOptions.max_iterations,
    progress: Callable[[int], None] | None = None,
    strict: bool = False,
    checkpoint: str | os.PathLike | None = None,
) -> BatchResult:
    """Solve ``B`` pose targets at once; strict success per target (see the module docstring).

    Args:
        robot: The robot, or its compiled :class:`~redik.kinematics.chain.Chain` (to compile once
            for many calls).
        T_targets: ``B × 4 × 4`` desired end-effector poses ``T_wd``. A target that is not a
            finite rigid transform is reported with status ``"invalid"``; the others are solved.
        q0: Seeds, ``(n,)`` for all or ``(B, n)``; default the robot's home configuration.
        method: ``"dls"``, damped least squares (Levenberg–Marquardt).
        pos_tol: Position tolerance (m).
        rot_tol: Rotation tolerance (rad).
        restarts: Random re-seeds allowed per target after its first attempt.
        seed: Seed of the re-seeds; the same seed gives the same result on every engine,
            worker count and chunk size.
        engine: An :class:`~redik.solvers.batch.engines.Engine` (which owns its workers:
            create it once, reuse it, close it), or the name of a shared one: ``"local"``
            (this process, the targets spread over threads on every core: the default),
            ``"process"`` (a pool of single-threaded processes, started on first use and
            kept until exit) or ``"ray"``; see :mod:`redik.solvers.batch.engines`.
        workers: Threads, processes or Ray CPUs of a named engine; default every core.
        address: Ray cluster address of a named engine (``"ray"``), ``"HEAD_IP:PORT"`` of a
            cluster started with ``ray start --head``; default a local Ray instance. A cluster
            with token authentication (Ray 2.60 asks joining nodes for one) needs
            ``RAY_AUTH_MODE=token`` and its token, from ``ray get-auth-token --generate`` on
            the head, in ``RAY_AUTH_TOKEN`` in the environment of every ``ray start
            --address`` and of this process before Ray is imported
            (:mod:`~redik.solvers.batch.engines` gives the commands).
        chunk_size: Targets per chunk, the unit of work (and of memory) of every engine;
            default a quarter of the batch within :data:`CHUNK_SIZE_RANGE`. Results do not
            depend on it.
        max_iterations: Iterations per attempt.
        progress: Called with the number of targets in each finished chunk.
        strict: Report near-rotation targets as ``"invalid"`` instead of projecting them
            onto SO(3) with a warning (:mod:`~redik.core.rotation_policy`).
        checkpoint: A directory where each finished chunk is written as it arrives
            (:mod:`~redik.solvers.batch.checkpoint`). Called again with the same arguments
            after a crash, ``solve_batch`` reads the chunks found there instead of solving
            them again (``progress`` is called for them first) and returns the result an
            uninterrupted run would have. Engine, workers and address may change between
            runs; anything else that changes the results may not.

    Returns:
        A :class:`BatchResult` with one row per target.

    Raises:
        InvalidInput: ``T_targets`` is not ``B × 4 × 4``, a bad ``q0``, method, engine or
            tolerance, a closed engine, or ``workers``/``address`` beside an ``Engine``.
        CheckpointMismatch: ``checkpoint`` holds the checkpoint of another batch (the message
            names what differs: targets, seeds, robot, options, seed or redik version).
        BackendError: Ray cannot be imported or reached, or a chunk's worker died more often
            than the engine retries it (:class:`~redik.solvers.batch.engines.Engine`).
    """
    if not isinstance(method, str) or method not in METHODS:
        raise InvalidInput(f"method must be one of {METHODS}, got {method!r}")
    if not isinstance(engine, str | Engine):
        raise InvalidInput(f"engine must be an Engine or one of {ENGINES}, got {engine!r}")
    chunk_size = integer(chunk_size, "chunk_size", 1, allow_none=True)
    workers = integer(workers, "workers", 1, allow_none=True)
    runner = as_engine(engine, workers, address)
    seed = check_seed(seed)
    chain = robot if isinstance(robot, Chain) else Chain.from_robot(robot)
    options = DLSOptions(
        pos_tol=pos_tol, rot_tol=rot_tol, restarts=restarts, max_iterations=max_iterations
    )
    with _numba_threads(runner) as parallel:
        T, valid = check_targets(T_targets, strict)  # once here: one warning, not one per chunk
        if not valid.all():
            T = np.where(valid[:, None, None], T, np.nan)  # each chunk sees the refused as invalid
        size = len(T)
        seeds = check_seeds(chain, q0, size)
        if chunk_size is None:
            chunk_size = int(np.clip(-(-size // 4), *CHUNK_SIZE_RANGE))
        root = np.random.SeedSequence(seed)
        key = int(root.generate_state(1, np.uint64)[0])
        store = None
        if checkpoint is not None:
            settings = dataclasses.asdict(options) | {
                "method": method,
                "chunk_size": chunk_size,
                "seed": seed,
                "result": [field.name for field in dataclasses.fields(BatchResult)],
            }
            store = Checkpoint.open(checkpoint, batch_fingerprint(chain, T, seeds, settings), key)
            key = store.key
        parts = _solve_chunks(
            runner, (chain, options, key, parallel), T, seeds, chunk_size, store, progress
        )
    return BatchResult.concatenate(parts)


@contextlib.contextmanager
def _numba_threads(runner: Engine) -> Iterator[bool]:
    """The threads numba runs one batch on; yields whether the kernel runs on several.

    The local engine's workers set them from the target checks on: OpenMP threads woken by a
    parallel region spin after it, so a batch on one thread wakes none and runs the serial
    kernel. Blocks of targets are handed out one at a time as threads free up.
    """
    threads = numba.get_num_threads()
    count = threads
    if runner.kind == "local":
        # numba's stubs omit config.NUMBA_NUM_THREADS (the thread pool's size).
        count = min(runner.workers, numba.config.NUMBA_NUM_THREADS)  # type: ignore[attr-defined]
    numba.set_num_threads(count)
    try:
        with numba.parallel_chunksize(1):
            yield runner.kind == "local" and count > 1
    finally:
        numba.set_num_threads(threads)


def _solve_chunks(
    runner: Engine,
    shared: tuple,
    T: np.ndarray,
    seeds: np.ndarray,
    chunk_size: int,
    store: Checkpoint | None,
    progress: Callable[[int], None] | None,
) -> list[BatchResult]:
    """The results of every chunk in order.

    Each is read from ``store``, or solved on ``runner`` (``shared`` as
    :func:`_solve_chunk_task` takes it) and then written to ``store``.
    """
    starts = range(0, max(len(T), 1), chunk_size)  # an empty batch is one empty chunk
    parts = {} if store is None else {i: BatchResult(**a) for i, a in store.finished().items()}
    todo = [start for start in starts if start not in parts]
    arriving = iter(todo)  # map reports results in chunk order

    def finished(part: BatchResult) -> None:
        first = next(arriving)
        if store is not None:
            store.save(first, {f.name: getattr(part, f.name) for f in dataclasses.fields(part)})
        parts[first] = part
        if progress is not None:
            progress(len(part))

    if progress is not None:
        for part in parts.values():
            progress(len(part))
    chunks = ((T[i : i + chunk_size], seeds[i : i + chunk_size], i) for i in todo)
    runner.map(_solve_chunk_task, shared, chunks, on_result=finished)
    return [parts[start] for start in starts]


def _solve_chunk_task(
    shared: tuple[Chain, DLSOptions, int, bool],
    T_targets: np.ndarray,
    q0: np.ndarray,
    first: int,
) -> BatchResult:
    chain, options, key, parallel = shared
    return solve_chunk(chain, T_targets, q0, options, key, first, parallel)
