"""Plots of solver results: convergence curves (matplotlib, PNG).

Every function takes results as data (:class:`~redik.core.result.IKResult`) and either draws on a
given ``ax`` or creates a figure and, with ``path``, saves it as a PNG. Figures are built with
matplotlib's object-oriented API (:func:`new_figure`), not pyplot: they render headless,
leave the user's backend and pyplot's figure list alone, and matplotlib is only imported
when a plot is drawn.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.result import IKResult

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


def new_figure(
    nrows: int = 1,
    ncols: int = 1,
    *,
    figsize: tuple[float, float] = (6.0, 4.0),
    **subplot_options: Any,
) -> tuple[Figure, Any]:
    """A figure and its axes (``Figure.subplots(nrows, ncols, **subplot_options)``).

    The figure needs no GUI backend and stays out of pyplot's global state.
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=figsize, layout="constrained")
    return figure, figure.subplots(nrows, ncols, **subplot_options)


def save_figure(figure: Figure, path: str | Path, dpi: int = 120) -> Path:
    """Save ``figure`` as an image at ``path`` (parents created)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=dpi)
    return path


def convergence(
    results: Sequence[IKResult],
    labels: Sequence[str] | None = None,
    path: str | Path | None = None,
    ax: Axes | None = None,
) -> Axes:
    """Error norm ``‖e‖`` against iteration for several results, on a log scale.

    The classic Newton-versus-gradient picture: quadratic convergence shows as a curve that
    bends down ever more steeply, linear convergence as a straight line.

    Args:
        results: Results with an ``error_history`` (``error_history[k]`` after iteration k).
        labels: One legend entry per result; default each result's ``method``.
        path: Where to save the figure (of ``ax``, or the new one) as a PNG; None saves
            nothing.
        ax: Axes to draw on; default a new figure.

    Returns:
        The axes drawn on.

    Raises:
        InvalidInput: no results, a result without history, or a label count mismatch.
    """
    results = list(results)
    if not results:
        raise InvalidInput("convergence needs at least one result")
    if labels is None:
        labels = [result.method or f"result {i}" for i, result in enumerate(results)]
    labels = list(labels)
    if len(labels) != len(results):
        raise InvalidInput(f"got {len(results)} results but {len(labels)} labels")
    for label, result in zip(labels, results, strict=True):
        if np.size(result.error_history) == 0:
            raise InvalidInput(f"result {label!r} has an empty error_history")

    if ax is None:
        _, ax = new_figure(figsize=(6.0, 4.0))
    # Zero errors (an exact solve) cannot be drawn on a log scale: show them at the floor.
    floor = np.finfo(float).tiny
    for label, result in zip(labels, results, strict=True):
        errors = np.maximum(np.asarray(result.error_history, dtype=float), floor)
        ax.semilogy(np.arange(errors.size), errors, marker="o", markersize=3, label=label)
    ax.set_xlabel("iteration k")
    ax.set_ylabel("error norm ‖e‖")
    ax.set_title("Convergence")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    figure = ax.get_figure(root=True)  # an axes of a subfigure saves its whole figure
    if path is not None and figure is not None:
        save_figure(figure, path)
    return ax
