r"""A level's objective at the current kinematics, compiled: frame rows, Gram matrix, joint terms.

**Jacobians from** ``cdof``. After ``mj_comPos`` every degree of freedom :math:`i` of the
model has its motion axis :math:`s_i = (ω_i, v_i)` (``data.cdof``: rotation first), a
spatial motion vector expressed at the centre of mass :math:`c` of its kinematic tree
(``data.subtree_com`` of the tree's root body; Featherstone, *Rigid Body Dynamics
Algorithms*, 2008, §2.2). A point :math:`p` fixed to body :math:`b` then moves with

.. math::

    J_p = \bigl[\, v_i + ω_i \times (p - c) \,\bigr]_i, \qquad
    J_ω = \bigl[\, ω_i \,\bigr]_i ,

over the dofs :math:`i` on the path from :math:`b` to the world, every other column zero.
This is MuJoCo's own ``mj_jac`` (``engine_core_smooth.c``), which ``mj_jacBody``,
``mj_jacSite`` and ``mj_jacGeom`` call; here the path is walked once, when the plan is built
(:func:`dof_chain`), and only the dofs the robot moves are kept, each written straight into
its robot column (no ``nv``-wide buffer, no column gather). Rows are the world Jacobian of
:mod:`redik.core.conventions`, ``(v, ω)``.

**A level's objective.** Each frame task writes its weighted rows
(:class:`~redik.tasks.FrameTask`: :func:`~redik.tasks.frame_task.pose_residual`;
:class:`~redik.tasks.PositionTask`: :math:`A = W J_p`, :math:`b = -α W (p - p_d)`), then
:math:`H = A^\top A + \operatorname{diag}(h)`, :math:`c = -A^\top b + f ⊙ q - o` with the
level's joint-space sums :math:`h = ε + \sum w^2 d^2`, :math:`f = \sum α w^2 d^2`,
:math:`o = \sum α w^2 d^2 ⊙ r` (:mod:`redik.qp.assembly`, :mod:`redik.tasks.joint_space_task`)
— the objective :class:`~redik.qp.assembly.LevelAssembly` builds, in one call.

**Packed frames.** ``frames[f] = (kind, id, root, length, task, row)`` (frame kind
:data:`BODY`/:data:`SITE`/:data:`GEOM`, its id, the root body of its tree, the length of its
dof chain, the task kind :data:`POSE`/:data:`POSITION`, its first row in its level's ``A``);
``chains[f, :length]`` the dofs and ``columns[f, :length]`` their robot columns;
``targets[f]`` the task's target and scales (:data:`TARGET_WIDTH` floats): the top three rows
of its target pose :math:`[R_d\; p_d]` row by row (a position task fills :math:`p_d`, the
fourth column), then for a pose the row scale :math:`-w` and the error scale :math:`-αw`
(:func:`~redik.tasks.frame_task.pose_residual`'s), for a position the cost :math:`w` (3) at
offset 12 and :math:`-α` at offset 18. The plan copies a target into its row when the task's
``target`` is a new object (``set_target`` makes one), the scales when its ``version`` moved
(:mod:`redik.qp.compiled.plan`).
"""

from __future__ import annotations

import mujoco
import numba
import numpy as np
from numpy.typing import NDArray

from redik.kinematics.compiled import COMPILE
from redik.tasks.frame_task import pose_residual

BODY, SITE, GEOM = 0, 1, 2
"""Frame kinds in the packed table."""

POSE, POSITION = 0, 1
"""Task kinds in the packed table: a :class:`~redik.tasks.FrameTask` (6 rows), a
:class:`~redik.tasks.PositionTask` (3 rows)."""

FRAME_KINDS = {"body": BODY, "site": SITE, "geom": GEOM}
"""Frame kind of each :class:`~redik.kinematics.robot.Frame` kind."""

TARGET_WIDTH = 24
"""Floats per packed target (module docstring)."""


def dof_chain(
    model: mujoco.MjModel, body: int, column_of: NDArray[np.int64]
) -> tuple[list[int], list[int]]:
    """The dofs ``mj_jac`` walks for a point on ``body`` that the robot moves, with their columns.

    Args:
        model: The MuJoCo model.
        body: The body the point is fixed to.
        column_of: Per model dof, its robot column, −1 for a dof the robot holds.

    Returns:
        ``(dofs, columns)``, from the body towards the root.
    """
    while body and not model.body_dofnum[body]:
        body = int(model.body_parentid[body])
    dofs: list[int] = []
    columns: list[int] = []
    if not body:
        return dofs, columns
    dof = int(model.body_dofadr[body] + model.body_dofnum[body] - 1)
    while dof >= 0:
        if column_of[dof] >= 0:
            dofs.append(dof)
            columns.append(int(column_of[dof]))
        dof = int(model.dof_parentid[dof])
    return dofs, columns


def pack_chains(
    model: mujoco.MjModel, bodies: list[int], column_of: NDArray[np.int64]
) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]:
    """The dof chains of ``bodies`` (:func:`dof_chain`) as rectangular arrays.

    Args:
        model: The MuJoCo model.
        bodies: One body per row.
        column_of: Per model dof, its robot column, −1 for a dof the robot holds.

    Returns:
        ``(chains, columns, lengths)``: int64 arrays (rows × width) and (rows,).
    """
    walks = [dof_chain(model, body, column_of) for body in bodies]
    width = max([1] + [len(dofs) for dofs, _ in walks])
    chains = np.zeros((len(bodies), width), dtype=np.int64)
    columns = np.zeros((len(bodies), width), dtype=np.int64)
    lengths = np.zeros(len(bodies), dtype=np.int64)
    for row, (dofs, cols) in enumerate(walks):
        chains[row, : len(dofs)] = dofs
        columns[row, : len(dofs)] = cols
        lengths[row] = len(dofs)
    return chains, columns, lengths


@numba.njit(**COMPILE)
def point_jacobian(
    cdof: NDArray[np.float64],
    subtree_com: NDArray[np.float64],
    root: int,
    point: NDArray[np.float64],
    chain: NDArray[np.int64],
    columns: NDArray[np.int64],
    length: int,
    J: NDArray[np.float64],
) -> None:
    """Write the world Jacobian of ``point`` into ``J`` (6 × n), MuJoCo's ``mj_jac``.

    Args:
        cdof: ``data.cdof`` (nv × 6).
        subtree_com: ``data.subtree_com`` (nbody × 3).
        root: The root body of the point's tree (``model.body_rootid``).
        point: The world point (3,).
        chain: The dofs of the point's body chain (:func:`dof_chain`).
        columns: The robot column of each.
        length: How many entries of ``chain`` are used.
        J: Written: rows ``ṗ`` then ``ω`` (module docstring); other columns zero.
    """
    J[:] = 0.0
    ox = point[0] - subtree_com[root, 0]
    oy = point[1] - subtree_com[root, 1]
    oz = point[2] - subtree_com[root, 2]
    for k in range(length):
        i = chain[k]
        j = columns[k]
        wx, wy, wz = cdof[i, 0], cdof[i, 1], cdof[i, 2]
        J[0, j] = cdof[i, 3] + (wy * oz - wz * oy)
        J[1, j] = cdof[i, 4] + (wz * ox - wx * oz)
        J[2, j] = cdof[i, 5] + (wx * oy - wy * ox)
        J[3, j] = wx
        J[4, j] = wy
        J[5, j] = wz


@numba.njit(**COMPILE)
def _frame_pose(
    kind: int,
    index: int,
    poses: tuple[NDArray[np.float64], ...],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The world rotation (3 × 3) and position of a frame; ``poses`` = the six pose arrays."""
    if kind == BODY:
        return poses[1][index].reshape(3, 3), poses[0][index]
    if kind == SITE:
        return poses[3][index].reshape(3, 3), poses[2][index]
    return poses[5][index].reshape(3, 3), poses[4][index]


@numba.njit(**COMPILE)
def _position_rows(
    p: NDArray[np.float64],
    target: NDArray[np.float64],
    J: NDArray[np.float64],
    A: NDArray[np.float64],
    b: NDArray[np.float64],
) -> None:
    """``A = W J_p``, ``b = −α W (p − p_d)`` of a position task (``target``: its packed row).

    In :class:`~redik.tasks.task.ResidualTask`'s order of operations: ``(e ⊙ w)·(−α)``.
    """
    for i in range(3):
        scale = target[12 + i]
        for j in range(J.shape[1]):
            A[i, j] = J[i, j] * scale
        b[i] = (p[i] - target[4 * i + 3]) * scale * target[18]


@numba.njit(**COMPILE)
def _pose_rows(
    R: NDArray[np.float64],
    p: NDArray[np.float64],
    target: NDArray[np.float64],
    J: NDArray[np.float64],
    A: NDArray[np.float64],
    b: NDArray[np.float64],
) -> None:
    """The rows of a pose task: :func:`~redik.tasks.frame_task.pose_residual` on its target."""
    R_d = np.empty((3, 3))
    p_d = np.empty(3)
    for i in range(3):
        for j in range(3):
            R_d[i, j] = target[4 * i + j]
        p_d[i] = target[4 * i + 3]
    pose_residual(R, p, R_d, p_d, J, target[12:18], target[18:24], A, b)


@numba.njit(**COMPILE)
def frame_rows(
    frames: NDArray[np.int64],
    chains: NDArray[np.int64],
    columns: NDArray[np.int64],
    targets: NDArray[np.float64],
    poses: tuple[NDArray[np.float64], ...],
    cdof: NDArray[np.float64],
    subtree_com: NDArray[np.float64],
    J: NDArray[np.float64],
    A: NDArray[np.float64],
    b: NDArray[np.float64],
) -> None:
    """Write the weighted rows ``A``, ``b`` of every frame task of a level.

    Args:
        frames: The packed frames (module docstring).
        chains: Their dof chains.
        columns: The robot columns of those dofs.
        targets: Their packed targets and scales.
        poses: ``(xpos, xmat, site_xpos, site_xmat, geom_xpos, geom_xmat)`` of ``data``.
        cdof: ``data.cdof``.
        subtree_com: ``data.subtree_com``.
        J: Scratch (6 × n).
        A: Written (rows × n).
        b: Written (rows,).
    """
    for f in range(frames.shape[0]):
        R, p = _frame_pose(frames[f, 0], frames[f, 1], poses)
        point_jacobian(cdof, subtree_com, frames[f, 2], p, chains[f], columns[f], frames[f, 3], J)
        row = frames[f, 5]
        target = targets[f]
        if frames[f, 4] == POSE:
            _pose_rows(R, p, target, J, A[row : row + 6], b[row : row + 6])
        else:
            _position_rows(p, target, J, A[row : row + 3], b[row : row + 3])


@numba.njit(**COMPILE)
def _nonzero_rows(A: NDArray[np.float64], first: NDArray[np.int64], end: NDArray[np.int64]) -> None:
    """Per column of ``A``, the range ``[first, end)`` of rows outside which it is zero."""
    m, n = A.shape
    for i in range(n):
        first[i], end[i] = m, 0
        for k in range(m):
            if A[k, i] != 0.0:
                first[i] = min(first[i], k)
                end[i] = k + 1


@numba.njit(**COMPILE)
def _gram(
    A: NDArray[np.float64],
    b: NDArray[np.float64],
    H: NDArray[np.float64],
    c: NDArray[np.float64],
) -> None:
    """``H = AᵀA`` (both triangles) and ``c = −Aᵀb``.

    A frame's rows are zero outside its chain's columns, so two columns of a whole body
    (an arm's and a leg's) often share no non-zero row: each product sums over the rows where
    both columns may be non-zero only. The terms left out are exact zeros, so every entry is
    the full sum's (a zero's sign aside).
    """
    m, n = A.shape
    first, end = np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64)
    _nonzero_rows(A, first, end)
    for i in range(n):
        total = 0.0
        for k in range(m):
            total += A[k, i] * b[k]
        c[i] = -total
        for j in range(i + 1):
            total = 0.0
            for k in range(max(first[i], first[j]), min(end[i], end[j])):
                total += A[k, i] * A[k, j]
            H[i, j] = total
            H[j, i] = total


@numba.njit(**COMPILE)
def level_objective(
    frames: NDArray[np.int64],
    chains: NDArray[np.int64],
    columns: NDArray[np.int64],
    targets: NDArray[np.float64],
    poses: tuple[NDArray[np.float64], ...],
    cdof: NDArray[np.float64],
    subtree_com: NDArray[np.float64],
    joint: NDArray[np.float64],
    flat: bool,
    q: NDArray[np.float64],
    J: NDArray[np.float64],
    A: NDArray[np.float64],
    b: NDArray[np.float64],
    H: NDArray[np.float64],
    c: NDArray[np.float64],
) -> None:
    """Write one level's ``H`` and ``c`` (and its rows ``A``, ``b``) at the current kinematics.

    Args:
        frames: The packed frames of the level (module docstring).
        chains: Their dof chains.
        columns: The robot columns of those dofs.
        targets: Their packed targets and scales.
        poses: ``(xpos, xmat, site_xpos, site_xmat, geom_xpos, geom_xmat)`` of ``data``.
        cdof: ``data.cdof``.
        subtree_com: ``data.subtree_com``.
        joint: The joint-space sums ``(h, f, o)`` (3 × n; module docstring).
        flat: The robot is flat (``q ⊖ r = q − r``): ``f ⊙ q − o`` is added to ``c``.
        q: The configuration (n,) on a flat robot; else the joint-space gradient
            ``Σ α w²d² ⊙ (q ⊖ r)`` (n,), added to ``c`` as it is.
        J: Scratch (6 × n).
        A: The level's rows (rows × n), written.
        b: Their right-hand side, written.
        H: Written (n × n).
        c: Written (n,).
    """
    frame_rows(frames, chains, columns, targets, poses, cdof, subtree_com, J, A, b)
    _gram(A, b, H, c)
    for i in range(c.shape[0]):
        H[i, i] += joint[0, i]
        if flat:
            c[i] += joint[1, i] * q[i] - joint[2, i]
        else:
            c[i] += q[i]
