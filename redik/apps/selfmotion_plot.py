"""The self-motion manifold in joint space: scatter plots of joint pairs (matplotlib).

Each panel plots one pair of joints for every sample of a
:class:`~redik.solvers.redundancy.SelfMotion`, coloured by component or by a criterion; dashed
lines mark the joint limits. Uses the Agg backend when no other is selected, so it works
headless.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from redik.apps.plot import new_figure, save_figure
from redik.core.exceptions import InvalidInput

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from redik.solvers.redundancy.selfmotion import SelfMotion


def default_pairs(motion: SelfMotion, count: int = 6) -> list[tuple[int, int]]:
    """The ``count`` joint pairs along which the samples spread most (largest joint ranges)."""
    if len(motion.samples) == 0:
        return list(itertools.combinations(range(len(motion.joint_names)), 2))[:count]
    spread = np.ptp(motion.samples, axis=0)
    order = [int(k) for k in np.argsort(-spread)]
    pairs = itertools.combinations(
        order[: max(2, int(np.ceil((1 + np.sqrt(1 + 8 * count)) / 2)))], 2
    )
    return [(min(a, b), max(a, b)) for a, b in itertools.islice(pairs, count)]


def plot_joint_pairs(
    motion: SelfMotion,
    color_by: str = "component",
    pairs: Sequence[tuple[int, int]] | None = None,
    lower: np.ndarray | None = None,
    upper: np.ndarray | None = None,
    path: str | Path | None = None,
    marks: dict[str, np.ndarray] | None = None,
) -> Figure:
    """Scatter the samples on joint pairs, coloured by component or by a criterion.

    Args:
        motion: The sampled self-motion.
        color_by: ``"component"`` or the name of one of ``motion.criteria``.
        pairs: Joint index pairs, one panel each (default :func:`default_pairs`).
        lower: The robot's lower limits, drawn as dashed lines (optional).
        upper: The robot's upper limits, likewise.
        path: Where to save a PNG (optional).
        marks: Label → configuration, drawn as a marker on every panel (e.g. a QP
            solution, the best sample).

    Returns:
        The figure.

    Raises:
        InvalidInput: ``color_by`` names neither ``"component"`` nor a criterion.
    """
    values, cmap, label = _colouring(motion, color_by)
    pairs = default_pairs(motion) if pairs is None else list(pairs)
    columns = min(3, len(pairs))
    rows = int(np.ceil(len(pairs) / columns))
    figure, axes = new_figure(rows, columns, figsize=(4.2 * columns, 3.8 * rows), squeeze=False)
    scatter = None
    for ax, (i, j) in zip(axes.flat, pairs, strict=False):
        scatter = ax.scatter(
            motion.samples[:, i], motion.samples[:, j], c=values, cmap=cmap, s=4, linewidths=0
        )
        _limit_lines(ax, i, j, lower, upper)
        for (name, q), style in zip((marks or {}).items(), itertools.cycle("*XPD"), strict=False):
            ax.plot(q[i], q[j], style, ms=10, mec="black", label=name)
        ax.set_xlabel(f"{motion.joint_names[i]} [rad]")
        ax.set_ylabel(f"{motion.joint_names[j]} [rad]")
    for ax in list(axes.flat)[len(pairs) :]:
        ax.set_visible(False)
    if marks:
        axes.flat[0].legend(fontsize=7)
    if scatter is not None:
        figure.colorbar(scatter, ax=axes.ravel().tolist(), label=label, shrink=0.8)
    figure.suptitle(
        f"self-motion manifold: {len(motion.samples)} samples, dimension {motion.dimension}, "
        f"{motion.n_components} component(s)"
    )
    if path is not None:
        save_figure(figure, path, dpi=110)
    return figure


def _colouring(motion: SelfMotion, color_by: str) -> tuple[np.ndarray, str, str]:
    """``(values, colormap, colorbar label)`` of a colouring; the better end is bright."""
    if color_by == "component":
        return motion.component, "tab10", "component"
    if color_by not in motion.criteria:
        raise InvalidInput(
            f"color_by must be 'component' or one of {list(motion.criteria)}, got {color_by!r}"
        )
    maximize = motion.maximize[color_by]
    better = "higher" if maximize else "lower"
    cmap = "viridis" if maximize else "viridis_r"
    return motion.criteria[color_by], cmap, f"{color_by} ({better} is better)"


def _limit_lines(ax, i: int, j: int, lower: np.ndarray | None, upper: np.ndarray | None) -> None:
    """Dashed lines at the finite limits of joint ``i`` (vertical) and ``j`` (horizontal)."""
    for bounds in (lower, upper):
        if bounds is None:
            continue
        if np.isfinite(bounds[i]):
            ax.axvline(bounds[i], color="grey", linestyle="--", linewidth=0.8)
        if np.isfinite(bounds[j]):
            ax.axhline(bounds[j], color="grey", linestyle="--", linewidth=0.8)
