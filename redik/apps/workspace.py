r"""Where an arm can reach: primary and dexterous workspace, and reachability maps.

The **primary** (reachable) workspace is the set of end-effector positions reachable with
*some* orientation; the **dexterous** workspace those reachable with *every* orientation
(Siciliano et al., *Robotics: Modelling, Planning and Control*, §2.11). Both are estimated
numerically:

- :func:`sample` runs forward kinematics on random configurations within the limits — each
  end-effector position is reachable by construction — bins the points into cubic cells, and
  scores every occupied cell by :func:`reachability` at its centre;
- :func:`reachability` scores points by the fraction of a set of orientations for which
  :func:`redik.solvers.batch.solve_batch` finds a strict solution (tolerances and joint
  limits). A score of 1 marks the dexterous workspace (as far as the sampled orientations
  tell), 0 a point reached with none. Points outside the chain's reach ball
  (:meth:`Chain.reach`) score 0 without a solve.

"Every orientation" means every orientation the arm can take (Siciliano et al., §2.11:
"the orientations feasible for the direct kinematics"): by default the orientations are
drawn from the arm's own forward kinematics at random configurations
(:func:`attainable_rotations`), so a planar arm is asked for rotations about its plane's
normal and scores its dexterous workspace — the origin of a two-link arm with equal links —
as 1. Uniform rotations of SO(3) (:func:`random_rotations`) suit an arm that takes every
orientation; a planar or 5-joint arm scores 0 against them everywhere.

A score is an estimate from below: a missed solution lowers it, a reported one is verified.
Plots are written as PNG with matplotlib's object-oriented API (no display needed).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from redik.core.exceptions import InvalidInput
from redik.core.validate import seed as check_seed
from redik.kinematics.robot import Robot
from redik.solvers.batch import Chain, forward_kinematics, solve_batch

AXES = "xyz"


@dataclasses.dataclass
class ReachabilityMap:
    """Reachability scores of points.

    Attributes:
        points: ``(..., 3)`` positions in the world (the grid as given).
        score: ``points.shape[:-1]`` fractions of ``orientations`` solved, in ``[0, 1]``.
        solved: ``points.shape[:-1] + (K,)`` which orientation was solved at each point.
        orientations: ``K × 3 × 3`` end-effector orientations tried at every point.
    """

    points: np.ndarray
    score: np.ndarray
    solved: np.ndarray
    orientations: np.ndarray

    def plot_slice(self, path: str | Path, axis: str = "z", value: float | None = None) -> Path:
        """Write a PNG of the scores on the grid plane ``axis = value`` (default mid-grid).

        The points are sliced at the level of ``axis`` nearest to ``value``, so the map should
        be a grid (as :func:`numpy.meshgrid` makes) for a full picture.
        """
        from matplotlib.figure import Figure

        if axis not in AXES:
            raise InvalidInput(f"axis must be one of 'x', 'y', 'z', got {axis!r}")
        k = AXES.index(axis)
        points = self.points.reshape(-1, 3)
        score = self.score.reshape(-1)
        levels = np.unique(np.round(points[:, k], 9))
        target = levels[len(levels) // 2] if value is None else value
        level = levels[np.argmin(np.abs(levels - target))]
        on = np.abs(points[:, k] - level) <= 1e-9
        u, v = (i for i in range(3) if i != k)
        figure = Figure(figsize=(5.5, 4.5))
        ax = figure.add_subplot()
        marker = 3000.0 / max(1.0, np.sqrt(on.sum())) ** 2 * 4
        drawn = ax.scatter(
            points[on, u],
            points[on, v],
            c=score[on],
            cmap="viridis",
            vmin=0,
            vmax=1,
            marker="s",
            s=marker,
        )
        figure.colorbar(drawn, ax=ax, label="fraction of orientations solved")
        ax.set_xlabel(f"{AXES[u]} (m)")
        ax.set_ylabel(f"{AXES[v]} (m)")
        ax.set_aspect("equal")
        ax.set_title(f"reachability, {axis} = {level:.3f} m, {len(self.orientations)} orientations")
        path = Path(path)
        figure.savefig(path, dpi=100)
        return path


@dataclasses.dataclass
class WorkspaceSample:
    """Primary and dexterous workspace estimates of :func:`sample`.

    Attributes:
        points: ``n × 3`` end-effector positions of random configurations (primary workspace).
        q: ``n × dof`` the configurations.
        cell_size: Edge of the cubic cells (m).
        cells: Reachability of the centres of the cells holding at least one point.
    """

    points: np.ndarray
    q: np.ndarray
    cell_size: float
    cells: ReachabilityMap

    @property
    def score(self) -> np.ndarray:
        """Reachability score of each occupied cell, in ``[0, 1]``."""
        return self.cells.score

    @property
    def dexterous(self) -> np.ndarray:
        """Centres of the cells solved with every sampled orientation (``m × 3``)."""
        return self.cells.points[self.cells.score >= 1.0]

    def plot(self, directory: str | Path, name: str = "workspace") -> list[Path]:
        """Write ``name_3d.png`` (scatter) and ``name_slices.png`` (xy, xz) into ``directory``."""
        from matplotlib.figure import Figure

        directory = Path(directory)
        directory.mkdir(parents=True, exist_ok=True)
        shown = self.points[:: max(1, len(self.points) // 4000)]
        order = np.argsort(self.cells.score, kind="stable")  # best cells drawn on top
        centres, score = self.cells.points[order], self.cells.score[order]

        figure = Figure(figsize=(6, 5))
        ax = figure.add_subplot(projection="3d")
        ax.scatter(*shown.T, s=1, c="0.7", alpha=0.3, label="primary (FK samples)")
        dexterous = score >= 1.0
        ax.scatter(*centres[dexterous].T, s=12, c="tab:red", label="dexterous (every orientation)")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.set_zlabel("z (m)")
        ax.legend(loc="upper left", fontsize=8)
        figure.savefig(directory / f"{name}_3d.png", dpi=100)

        figure = Figure(figsize=(10, 4.5))
        for i, (u, v) in enumerate(((0, 1), (0, 2))):
            ax = figure.add_subplot(1, 2, i + 1)
            ax.scatter(shown[:, u], shown[:, v], s=1, c="0.8")
            drawn = ax.scatter(
                centres[:, u], centres[:, v], c=score, cmap="viridis", vmin=0, vmax=1, s=10
            )
            ax.set_xlabel(f"{AXES[u]} (m)")
            ax.set_ylabel(f"{AXES[v]} (m)")
            ax.set_aspect("equal")
            ax.set_title(f"{AXES[u]}{AXES[v]} projection")
        figure.colorbar(drawn, ax=figure.axes, label="fraction of orientations solved")
        figure.savefig(directory / f"{name}_slices.png", dpi=100)
        return [directory / f"{name}_3d.png", directory / f"{name}_slices.png"]


def random_rotations(count: int, rng: np.random.Generator | int | None = None) -> np.ndarray:
    """``count × 3 × 3`` rotations uniform on SO(3).

    Normalised Gaussian quaternions ``(w, x, y, z)`` are uniform on SO(3) (Shoemake,
    *Uniform random rotations*, Graphics Gems III, 1992); scipy's ``Rotation`` converts them
    in one vectorised call.

    Args:
        count: How many rotations.
        rng: A Generator whose stream carries on, or what :func:`numpy.random.default_rng`
            takes (as :meth:`redik.Robot.random_q`).

    Returns:
        ``count × 3 × 3`` rotation matrices.
    """
    quats = np.random.default_rng(rng).standard_normal((count, 4))
    return Rotation.from_quat(quats[:, [1, 2, 3, 0]]).as_matrix()  # scipy's order: (x, y, z, w)


def attainable_rotations(
    robot: Robot | Chain, count: int, rng: np.random.Generator | int | None = None
) -> np.ndarray:
    """``count × 3 × 3`` orientations the arm takes: its FK at random configurations.

    The configurations are uniform within the chain's sampling bounds (its joint limits,
    ``±π`` for an unlimited revolute joint), so the rotations cover the orientations the
    arm's forward kinematics can produce — all of SO(3) for a 6-joint arm with a full wrist,
    rotations about the plane's normal for a planar arm.

    Args:
        robot: The robot (or its compiled chain).
        count: How many orientations.
        rng: A Generator whose stream carries on, or what :func:`numpy.random.default_rng`
            takes.

    Returns:
        ``count × 3 × 3`` rotation matrices.
    """
    chain = robot if isinstance(robot, Chain) else Chain.from_robot(robot)
    rng = np.random.default_rng(rng)
    q = rng.uniform(chain.sampling_lower, chain.sampling_upper, (count, chain.dof))
    return forward_kinematics(chain, q)[:, :3, :3]


def reachability(
    robot: Robot | Chain,
    grid: np.ndarray,
    orientations: int | np.ndarray = 8,
    seed: int | None = None,
    restarts: int = 4,
    **solve_options,
) -> ReachabilityMap:
    """Score each point of ``grid`` by the fraction of ``orientations`` solved there.

    Args:
        robot: The robot (or its compiled chain).
        grid: ``(..., 3)`` positions, e.g. ``np.stack(np.meshgrid(xs, ys, zs,
            indexing="ij"), axis=-1)``.
        orientations: A count ``K`` of orientations the arm takes
            (:func:`attainable_rotations` from ``seed``), or ``K × 3 × 3`` rotation
            matrices (e.g. :func:`random_rotations` for uniform SO(3)).
        seed: Seed of the orientations and of the solver's re-seeds.
        restarts: Random re-seeds per target (each costs time at unreachable points).
        **solve_options: Passed to :func:`redik.solvers.batch.solve_batch` (``engine``,
            ``workers``, ``pos_tol``, …).

    Returns:
        The scores, which orientation was solved where, and the orientations tried.

    Raises:
        InvalidInput: a grid that is not finite ``(..., 3)`` positions, a count below 1 or
            orientations that are not ``K × 3 × 3``; a bad seed.
    """
    chain = robot if isinstance(robot, Chain) else Chain.from_robot(robot)
    grid = np.asarray(grid, dtype=float)
    if grid.ndim < 1 or grid.shape[-1] != 3 or not np.isfinite(grid).all():
        raise InvalidInput(f"grid must be finite positions of shape (..., 3), got {grid.shape}")
    rng = np.random.default_rng(check_seed(seed))
    if np.ndim(orientations) == 0:
        if int(orientations) < 1:
            raise InvalidInput(f"orientations must be at least 1, got {orientations!r}")
        rotations = attainable_rotations(chain, int(orientations), rng)
    else:
        rotations = np.asarray(orientations, dtype=float)
        if rotations.ndim != 3 or rotations.shape[1:] != (3, 3):
            raise InvalidInput(f"orientations must be K × 3 × 3, got {rotations.shape}")

    points = grid.reshape(-1, 3)
    centre, radius = chain.reach()
    # Beyond the reach ball nothing is reachable: no need to ask the solver.
    within = np.flatnonzero(np.linalg.norm(points - centre, axis=1) <= radius)
    K = len(rotations)
    T = np.zeros((within.size, K, 4, 4))
    T[:, :, :3, :3] = rotations[None]
    T[:, :, :3, 3] = points[within, None]
    T[:, :, 3, 3] = 1.0
    solved = np.zeros((len(points), K), dtype=bool)
    if within.size:
        result = solve_batch(
            chain,
            T.reshape(-1, 4, 4),
            seed=int(rng.integers(2**63)),
            restarts=restarts,
            **solve_options,
        )
        solved[within] = result.success.reshape(within.size, K)
    shape = grid.shape[:-1]
    return ReachabilityMap(
        points=grid,
        score=solved.mean(axis=1).reshape(shape),
        solved=solved.reshape((*shape, K)),
        orientations=rotations,
    )


def sample(
    robot: Robot | Chain,
    n: int,
    seed: int | None = None,
    orientations: int | np.ndarray = 8,
    resolution: int = 12,
    **solve_options,
) -> WorkspaceSample:
    """Estimate the primary and dexterous workspace from ``n`` random configurations.

    Args:
        robot: The robot (or its compiled chain).
        n: Number of random configurations (uniform within the sampling bounds).
        seed: Seed of the configurations, the orientations and the solver.
        orientations: As in :func:`reachability`, tried at every occupied cell's centre.
        resolution: Cells along the longest side of the sampled points' bounding box.
        **solve_options: Passed to :func:`reachability`.

    Returns:
        The sampled points and configurations, and the scores of the occupied cells.

    Raises:
        InvalidInput: ``n`` or ``resolution`` below 1; as :func:`reachability`.
    """
    if n < 1 or resolution < 1:
        raise InvalidInput(f"n and resolution must be positive, got {n} and {resolution}")
    chain = robot if isinstance(robot, Chain) else Chain.from_robot(robot)
    rng = np.random.default_rng(check_seed(seed))
    q = rng.uniform(chain.sampling_lower, chain.sampling_upper, (n, chain.dof))
    points = forward_kinematics(chain, q)[:, :3, 3]
    low = points.min(axis=0)
    cell_size = max(float(np.ptp(points, axis=0).max()) / resolution, 1e-9)
    occupied = np.unique(np.floor((points - low) / cell_size).astype(np.int64), axis=0)
    centres = low + (occupied + 0.5) * cell_size
    cells = reachability(
        chain, centres, orientations=orientations, seed=int(rng.integers(2**63)), **solve_options
    )
    return WorkspaceSample(points=points, q=q, cell_size=cell_size, cells=cells)
