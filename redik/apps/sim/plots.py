"""Pictures of a closed-loop run (matplotlib, PNG, headless)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from redik.apps.plot import new_figure, save_figure
from redik.apps.sim.result import SimulationResult


def plot_tracking(result: SimulationResult, path: str | Path, title: str = "") -> Path:
    """Save a PNG: tracking errors over time, and each joint's command against its value.

    The spans during which the robot touched something are shaded on the error panel.

    Args:
        result: A run of :func:`~redik.apps.sim.simulate`.
        path: Where to write the PNG (parents created).
        title: Title of the error panel (default "closed-loop tracking error", with the
            status when the run did not complete).

    Returns:
        The path written.
    """
    fig, (ax_err, ax_q) = new_figure(2, 1, figsize=(8, 6.5), sharex=True)
    ax_err.plot(result.times, result.position_error * 1e3, label="position (mm)")
    ax_rot = ax_err.twinx()
    ax_rot.plot(result.times, result.rotation_error, color="tab:orange", label="rotation (rad)")
    ax_err.set_ylabel("position error [mm]")
    ax_rot.set_ylabel("rotation error [rad]", color="tab:orange")
    default = "closed-loop tracking error"
    if result.status != "completed":
        default += f" ({result.status})"
    ax_err.set_title(title or default)
    ax_err.grid(True, alpha=0.3)
    _shade_contacts(ax_err, result)
    for j in range(result.q.shape[1]):
        (line,) = ax_q.plot(result.times, result.q[:, j], label=f"q{j + 1}")
        ax_q.plot(result.times, result.q_command[:, j], "--", color=line.get_color(), lw=0.8)
    ax_q.set_xlabel("time [s]")
    ax_q.set_ylabel("joint value (solid) / command (dashed)")
    ax_q.legend(ncol=4, fontsize=7)
    ax_q.grid(True, alpha=0.3)
    return save_figure(fig, path, dpi=110)


def _shade_contacts(ax, result: SimulationResult) -> None:
    """Shade, on ``ax``, the spans of ticks at which a contact of the robot was recorded."""
    period = 1.0 / result.control_rate
    touched = np.unique(np.concatenate([c.times for c in result.contacts] or [np.empty(0)]))
    if not len(touched):
        return
    breaks = np.flatnonzero(np.diff(touched) > 1.5 * period)  # gaps between runs of ticks
    starts = np.concatenate(([touched[0]], touched[breaks + 1]))
    ends = np.concatenate((touched[breaks], [touched[-1]]))
    for k, (start, end) in enumerate(zip(starts, ends, strict=True)):
        label = "contact" if k == 0 else None
        ax.axvspan(start - period, end, color="tab:red", alpha=0.15, lw=0, label=label)
    ax.legend(loc="upper left", fontsize=7)
