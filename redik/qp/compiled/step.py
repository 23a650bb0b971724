r"""One compiled call per step: every level's objective, the box, level 0, level 1.

:func:`solve_step` (one level) and :func:`solve_two_level_step` (two) run the stages of
:mod:`redik.qp.compiled.plan` in one call, and return to Python only where DAQP must solve a
QP with rows (:data:`LEVEL0_QP`, :data:`REDUCED_QP`), to be called again at the next stage.
A compiled call unboxes each of its arguments every time, a cost of the order of a small
step's work, so the plan keeps its arrays as views into two buffers that a call passes whole:

- ``table`` (int64): a header of sizes and flags (the ``H_*`` indices), the offsets of the
  views of ``work`` (:data:`OFFSETS`), then per level
  ``(first frame, end frame, first row, end row)``, the packed frames, their dof chains and
  columns (:mod:`redik.qp.compiled.frames`), each tangent coordinate's index in ``q``
  (−1 on ball and free joints) and where the quaternions of ``q`` start;
- ``work`` (float64): the views of :func:`float_views`, in its order.

:func:`buffer_sizes` is the one place their sizes are written; :func:`float_views` and
:func:`int_views` the one place they are sliced, in compiled code and in Python alike; a call
slices them once and hands the arrays on.
"""

from __future__ import annotations

import numba
import numpy as np
from numpy.typing import NDArray

from redik.core.validate import MAX_COORDINATE
from redik.kinematics.compiled import COMPILE
from redik.qp.compiled.box_qp import box_qp
from redik.qp.compiled.frames import TARGET_WIDTH, level_objective
from redik.qp.compiled.level0 import BINDS, NOT_DEFINITE, box_bounds, level0_point
from redik.qp.compiled.linalg import clip_into
from redik.qp.compiled.lower_level import DONE as LEVEL1_DONE
from redik.qp.compiled.lower_level import REDUCED_QP as LEVEL1_REDUCED_QP
from redik.qp.compiled.lower_level import add_direction, lower_level
from redik.qp.compiled.rows_qp import rows_qp

H_N, H_LEVELS, H_FRAMES, H_ROWS, H_COLLISION_ROWS, H_FREE, H_WIDTH, H_QUATERNIONS = range(8)
"""Header indices of ``table``: tangent coordinates, levels, frame tasks, their rows, the
collision rows (most), level 1's free directions, the dof chains' width, quaternions."""

H_POSITION, H_VELOCITY, H_FLAT, H_LEAST_SQUARES = range(8, 12)
"""Header flags: a configuration limit, a velocity limit, a flat robot, level 0 of two
levels a least-squares level."""

HEADER = 12
"""Length of ``table``'s header."""

START, AFTER_LEVEL0_QP, AFTER_REDUCED_QP = 0, 1, 2
"""Stages :func:`solve_step` starts at."""

DONE, LEVEL0_QP, REDUCED_QP, GENERAL = 0, 1, 2, 3
""":func:`solve_step`: ``x`` is the step; level 0's QP with its rows needs DAQP (then
:data:`AFTER_LEVEL0_QP`); level 1's reduced QP does (``z``, then :data:`AFTER_REDUCED_QP`);
the general path must answer."""

_CONTINUE = -1


OFFSETS = 22
"""Offsets of :func:`float_views`' 21 views in ``work``, stored after the header."""


@numba.njit(**COMPILE)
def buffer_sizes(
    table: NDArray[np.int64],
) -> tuple[int, NDArray[np.int64]]:
    """The sizes of ``table`` and of each view of ``work``, in :func:`float_views`'s order.

    Reads the header only; :func:`write_offsets` stores the views' offsets from the sizes.
    """
    n, levels, frames = table[H_N], table[H_LEVELS], table[H_FRAMES]
    rows, collision, free = table[H_ROWS], table[H_COLLISION_ROWS], table[H_FREE]
    width, quaternions = table[H_WIDTH], table[H_QUATERNIONS]
    table_size = HEADER + OFFSETS + 4 * levels + frames * (6 + 2 * width) + n + quaternions
    work = np.array([
        frames * TARGET_WIDTH, levels * 3 * n, levels * n, rows * n, rows, levels * n * n,
        levels * n, 3 * n, n, n, n, collision * n, collision, n * free, free * free, free,
        free, (n + collision) * free, n + collision, n + collision, 6,
    ])  # fmt: skip
    return table_size, work


@numba.njit(**COMPILE)
def write_offsets(
    table: NDArray[np.int64],
) -> int:
    """Store the offsets of :func:`float_views`' views after the header; return ``work``'s size."""
    sizes = buffer_sizes(table)[1]
    table[HEADER] = 0
    for k in range(sizes.shape[0]):
        table[HEADER + k + 1] = table[HEADER + k] + sizes[k]
    return int(table[HEADER + OFFSETS - 1])


@numba.njit(**COMPILE)
def float_views(
    work: NDArray[np.float64],
    table: NDArray[np.int64],
) -> tuple[NDArray[np.float64], ...]:
    """The plan's float arrays, views into ``work``.

    Returns:
        ``(targets, joint, gradients, A, b, H, c, box, lb, ub, x, C, u, N, Hz, cz, z, rows,
        rows_lower, rows_upper, settings)``: the frame tasks' targets (F × 24); per level
        the joint-space sums (L × 3 × n) and, on a robot that is not flat, their gradient
        (L × n); every level's frame rows and right-hand side (R × n, R); per level ``H``
        and ``c``; the box ``(q_min, q_max, v_max)``; the step's bounds and the step; the
        collision rows and bounds (M × n, M); level 1's null-space basis, reduced Hessian,
        linear term and solution; the reduced rows and their bounds; ``(ε, rank_tol, λ,
        max_step, rows_bound, primal_tol)``: the regularisation, the null space's threshold, the
        Levenberg–Marquardt term added to level 0's Hessian and the trust region
        ``|Δq_i| ≤ max_step`` (inf: none) of a static step, 1 when hard rows bound the
        last step (level 0 then goes to the rows' QP directly when a constraint binds: its
        rows usually bind again, and the box QP would be solved for nothing), and the
        violation above which the rows' QP counts a row as broken (DAQP's ``primal_tol``; 0
        for quadprog, which holds every row exactly).
    """
    n, levels, frames = table[H_N], table[H_LEVELS], table[H_FRAMES]
    rows, collision, free = table[H_ROWS], table[H_COLLISION_ROWS], table[H_FREE]
    o = table[HEADER : HEADER + OFFSETS]
    return (
        work[o[0] : o[1]].reshape(frames, TARGET_WIDTH),
        work[o[1] : o[2]].reshape(levels, 3, n),
        work[o[2] : o[3]].reshape(levels, n),
        work[o[3] : o[4]].reshape(rows, n),
        work[o[4] : o[5]],
        work[o[5] : o[6]].reshape(levels, n, n),
        work[o[6] : o[7]].reshape(levels, n),
        work[o[7] : o[8]].reshape(3, n),
        work[o[8] : o[9]],
        work[o[9] : o[10]],
        work[o[10] : o[11]],
        work[o[11] : o[12]].reshape(collision, n),
        work[o[12] : o[13]],
        work[o[13] : o[14]].reshape(n, free),
        work[o[14] : o[15]].reshape(free, free),
        work[o[15] : o[16]],
        work[o[16] : o[17]],
        work[o[17] : o[18]].reshape(n + collision, free),
        work[o[18] : o[19]],
        work[o[19] : o[20]],
        work[o[20] : o[21]],
    )


@numba.njit(**COMPILE)
def int_views(
    table: NDArray[np.int64],
) -> tuple[
    NDArray[np.int64],
    NDArray[np.int64],
    NDArray[np.int64],
    NDArray[np.int64],
    NDArray[np.int64],
    NDArray[np.int64],
]:
    """The plan's int arrays, views into ``table`` after its header.

    Returns:
        ``(levels, frames, chains, columns, scalar_q, quaternions)``: per level its frames'
        and rows' ranges (L × 4), the packed frames (F × 6), their dof chains and columns
        (F × W), each tangent coordinate's index in ``q`` (n,), the quaternions' starts.
    """
    n, levels, frames = table[H_N], table[H_LEVELS], table[H_FRAMES]
    width, quaternions = table[H_WIDTH], table[H_QUATERNIONS]
    k = HEADER + OFFSETS
    level_table = table[k : k + 4 * levels].reshape(levels, 4)
    k += 4 * levels
    frame_table = table[k : k + 6 * frames].reshape(frames, 6)
    k += 6 * frames
    chains = table[k : k + width * frames].reshape(frames, width)
    k += width * frames
    columns = table[k : k + width * frames].reshape(frames, width)
    k += width * frames
    scalar_q = table[k : k + n]
    return level_table, frame_table, chains, columns, scalar_q, table[k + n : k + n + quaternions]


@numba.njit(**COMPILE)
def valid_configuration(
    q: NDArray[np.float64],
    quaternions: NDArray[np.int64],
) -> bool:
    """Whether ``q`` is finite, within ``±MAX_COORDINATE``, without a zero quaternion."""
    for value in q:
        if not abs(value) <= MAX_COORDINATE:  # a NaN fails too
            return False
    for s in quaternions:
        if q[s] * q[s] + q[s + 1] * q[s + 1] + q[s + 2] * q[s + 2] + q[s + 3] * q[s + 3] < 1e-18:
            return False
    return True


@numba.njit(**COMPILE)
def _objectives(
    q: NDArray[np.float64],
    poses: tuple[NDArray[np.float64], ...],
    cdof: NDArray[np.float64],
    subtree_com: NDArray[np.float64],
    flat: bool,
    levels: NDArray[np.int64],
    frames: NDArray[np.int64],
    chains: NDArray[np.int64],
    columns: NDArray[np.int64],
    floats: tuple[NDArray[np.float64], ...],
) -> None:
    """Every level's ``H``, ``c`` (and frame rows) at the current kinematics."""
    targets, joint, gradients, A, b, H, c = floats[:7]
    J = np.empty((6, c.shape[1]))
    for level in range(levels.shape[0]):
        f0, f1, r0, r1 = levels[level, 0], levels[level, 1], levels[level, 2], levels[level, 3]
        level_objective(
            frames[f0:f1], chains[f0:f1], columns[f0:f1], targets[f0:f1], poses, cdof,
            subtree_com, joint[level], flat, q if flat else gradients[level], J, A[r0:r1],
            b[r0:r1], H[level], c[level],
        )  # fmt: skip


@numba.njit(**COMPILE)
def _level0(
    q: NDArray[np.float64],
    dt: float,
    m: int,
    table: NDArray[np.int64],
    levels: NDArray[np.int64],
    scalar_q: NDArray[np.int64],
    floats: tuple[NDArray[np.float64], ...],
) -> int:
    """The box and level 0 (the box QP when a bound binds); :data:`_CONTINUE` when solved."""
    A, b, H, c, box, lb, ub, x, C, u = floats[3:13]
    settings = floats[20]
    position, velocity = table[H_POSITION] != 0, table[H_VELOCITY] != 0
    if not box_bounds(q, scalar_q, box, position, velocity, dt, settings[3], lb, ub):
        return GENERAL
    A0, b0 = A[levels[0, 2] : levels[0, 3]], b[levels[0, 2] : levels[0, 3]]
    least_squares = table[H_LEAST_SQUARES] != 0
    shift = settings[0] + settings[2]
    for i in range(x.shape[0]):
        H[0, i, i] += settings[2]
    L = np.empty((x.shape[0], x.shape[0]))
    status = level0_point(H[0], c[0], A0, b0, least_squares, shift, lb, ub, C, u, m, x, L)
    if status == NOT_DEFINITE:
        return GENERAL
    rows_bound, settings[4] = settings[4] != 0.0, 0.0
    if status != BINDS:
        return _CONTINUE
    if (
        not (m > 0 and rows_bound)
        and box_qp(H[0], c[0], lb, ub, C, u, m, x, 4 * x.shape[0] + 10) > 0
    ):
        return _CONTINUE
    if m > 0 and not least_squares:
        active = rows_qp(L, c[0], C, u, m, lb, ub, settings[5], x)
        if active >= 0:
            settings[4] = 1.0 if active > 0 else 0.0
            return _CONTINUE
    return LEVEL0_QP


@numba.njit(**COMPILE)
def _level0_qp_bounds(m: int, floats: tuple[NDArray[np.float64], ...]) -> None:
    """Write level 0's QP bounds for DAQP into ``rows_lower``, ``rows_upper``: box, then rows.

    Level 1's reduced rows use the same arrays only after level 0 is solved.
    """
    lb, ub, _, _, u = floats[8:13]
    lower, upper = floats[18], floats[19]
    n = lb.shape[0]
    lower[:n], upper[:n] = lb, ub
    lower[n : n + m] = -np.inf
    upper[n : n + m] = u[:m]


@numba.njit(**COMPILE)
def _rows_bind(m: int, floats: tuple[NDArray[np.float64], ...]) -> float:
    """1.0 when a row of level 0 is active at ``x`` (to 1e-9), else 0.0."""
    x, C, u = floats[10], floats[11], floats[12]
    for i in range(m):
        value = 0.0
        for j in range(x.shape[0]):
            value += C[i, j] * x[j]
        if value >= u[i] - 1e-9:
            return 1.0
    return 0.0


@numba.njit(**COMPILE)
def _level1(
    m: int,
    clip: bool,
    levels: NDArray[np.int64],
    floats: tuple[NDArray[np.float64], ...],
) -> int:
    """Level 1 within level 0's optimal set, and the clip (:func:`~.lower_level.lower_level`)."""
    A, _, H, c, _, lb, ub, x, C, u, N, Hz, cz, _, rows, lower, upper, settings = floats[3:]
    A0 = A[levels[0, 2] : levels[0, 3]]
    status = lower_level(
        x, A0, H[1], c[1], lb, ub, C, u, m, settings[1], clip, N, Hz, cz, rows, lower, upper
    )
    if status == LEVEL1_DONE:
        return DONE
    return REDUCED_QP if status == LEVEL1_REDUCED_QP else GENERAL


@numba.njit(**COMPILE)
def _start(
    q: NDArray[np.float64],
    dt: float,
    m: int,
    poses: tuple[NDArray[np.float64], ...],
    cdof: NDArray[np.float64],
    subtree_com: NDArray[np.float64],
    table: NDArray[np.int64],
    floats: tuple[NDArray[np.float64], ...],
) -> int:
    """Every level's objective, the box and level 0; :data:`_CONTINUE` when level 0 is solved."""
    levels, frames, chains, columns, scalar_q, quaternions = int_views(table)
    if not valid_configuration(q, quaternions):
        return GENERAL
    flat = table[H_FLAT] != 0
    _objectives(q, poses, cdof, subtree_com, flat, levels, frames, chains, columns, floats)
    status = _level0(q, dt, m, table, levels, scalar_q, floats)
    if status == LEVEL0_QP:
        _level0_qp_bounds(m, floats)
    return status


@numba.njit(**COMPILE)
def solve_step(
    stage: int,
    q: NDArray[np.float64],
    dt: float,
    m: int,
    poses: tuple[NDArray[np.float64], ...],
    cdof: NDArray[np.float64],
    subtree_com: NDArray[np.float64],
    table: NDArray[np.int64],
    work: NDArray[np.float64],
) -> int:
    """Run a step of one level from ``stage`` (module docstring); ``x`` (in ``work``) receives it.

    A plan of two levels runs :func:`solve_two_level_step` instead: this entry leaves level 1's
    kernels out, so that a plan of one level never compiles them.

    Args:
        stage: :data:`START`, or :data:`AFTER_LEVEL0_QP` to resume after DAQP.
        q: The configuration (nq,).
        dt: The step's duration (s; 0 without a velocity limit).
        m: The number of collision rows in ``C``, ``u``.
        poses: ``(xpos, xmat, site_xpos, site_xmat, geom_xpos, geom_xmat)`` of ``data``,
            after forward kinematics at ``q``.
        cdof: ``data.cdof``.
        subtree_com: ``data.subtree_com``.
        table: The plan's int buffer.
        work: The plan's float buffer.

    Returns:
        :data:`DONE`, :data:`LEVEL0_QP` or :data:`GENERAL`.
    """
    floats = float_views(work, table)
    if stage == START:
        status = _start(q, dt, m, poses, cdof, subtree_com, table, floats)
        if status != _CONTINUE:
            return status
    elif stage == AFTER_LEVEL0_QP:
        floats[20][4] = _rows_bind(m, floats)
    if table[H_POSITION] != 0:
        clip_into(floats[10], floats[8], floats[9])
    return DONE


@numba.njit(**COMPILE)
def solve_two_level_step(
    stage: int,
    q: NDArray[np.float64],
    dt: float,
    m: int,
    poses: tuple[NDArray[np.float64], ...],
    cdof: NDArray[np.float64],
    subtree_com: NDArray[np.float64],
    table: NDArray[np.int64],
    work: NDArray[np.float64],
) -> int:
    """Run a step of two levels from ``stage``: :func:`solve_step`, then level 1.

    Args:
        stage: :data:`START`, or where to resume after DAQP.
        q: The configuration (nq,).
        dt: The step's duration (s; 0 without a velocity limit).
        m: The number of collision rows in ``C``, ``u``.
        poses: As :func:`solve_step`'s.
        cdof: ``data.cdof``.
        subtree_com: ``data.subtree_com``.
        table: The plan's int buffer.
        work: The plan's float buffer.

    Returns:
        :data:`DONE`, :data:`LEVEL0_QP`, :data:`REDUCED_QP` or :data:`GENERAL`.
    """
    floats = float_views(work, table)
    if stage == START:
        status = _start(q, dt, m, poses, cdof, subtree_com, table, floats)
        if status != _CONTINUE:
            return status
    elif stage == AFTER_LEVEL0_QP:
        floats[20][4] = _rows_bind(m, floats)
    if stage != AFTER_REDUCED_QP:
        return _level1(m, table[H_POSITION] != 0, int_views(table)[0], floats)
    x, lb, ub, N, z = floats[10], floats[8], floats[9], floats[13], floats[16]
    add_direction(x, N, z)
    if table[H_POSITION] != 0:
        clip_into(x, lb, ub)
    return DONE
