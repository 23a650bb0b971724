"""Timing of the closed-form solvers, single pose and vectorised batch (not a test).

``run()`` builds ``n`` reachable targets by forward kinematics of random joint vectors
(:func:`redik.dh.forward`), then times each solver with :func:`time.perf_counter`, taking
the median over ``repeats``. The ``redik bench analytic`` command prints its result.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from redik.analytic.planar import planar_2r, planar_2r_batch
from redik.analytic.puma import dh_rows as puma_rows
from redik.analytic.puma import puma, puma_batch
from redik.analytic.ur import UR5E, ur, ur_batch
from redik.analytic.ur import dh_rows as ur_rows
from redik.dh import forward

#: PUMA 560 (a2, a3, d3, d4) in metres, as in the bundled scene.
PUMA560 = (0.4318, 0.01905, 0.1254, 0.4318)
PLANAR = (1.0, 0.8)


def _median_seconds(call: Callable[[], object], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def run(n: int = 2000, seed: int = 0, repeats: int = 5, n_single: int = 200) -> dict:
    """Time single and batched PUMA, UR and planar-2R solving.

    Args:
        n: Targets per batch.
        seed: Seed of the random joint vectors.
        repeats: Timed repetitions; the median is reported.
        n_single: How many of the targets are solved one by one per repetition.

    Returns:
        ``{"puma": {"single_us": …, "batch_us": …, "solutions_per_pose": …}, "ur": …,
        "planar_2r": …, "n": n}`` — microseconds per pose.
    """
    rng = np.random.default_rng(seed)
    q6 = rng.uniform(-np.pi, np.pi, (n, 6))
    puma_T = np.stack([forward(puma_rows(*PUMA560), q) for q in q6])
    ur_T = np.stack([forward(ur_rows(*UR5E), q) for q in q6])
    q2 = rng.uniform(-np.pi, np.pi, (n, 2))
    xy = np.stack(
        [
            PLANAR[0] * np.cos(q2[:, 0]) + PLANAR[1] * np.cos(q2.sum(1)),
            PLANAR[0] * np.sin(q2[:, 0]) + PLANAR[1] * np.sin(q2.sum(1)),
        ],
        axis=1,
    )
    n_single = min(n_single, n)
    cases = {
        "puma": (
            lambda: [puma(T, *PUMA560) for T in puma_T[:n_single]],
            lambda: puma_batch(puma_T, *PUMA560),
        ),
        "ur": (
            lambda: [ur(T, *UR5E) for T in ur_T[:n_single]],
            lambda: ur_batch(ur_T, *UR5E),
        ),
        "planar_2r": (
            lambda: [planar_2r(x, y, *PLANAR) for x, y in xy[:n_single]],
            lambda: planar_2r_batch(xy, *PLANAR),
        ),
    }
    report: dict = {"n": n, "n_single": n_single, "repeats": repeats}
    for name, (single, batch) in cases.items():
        report[name] = {
            "single_us": 1e6 * _median_seconds(single, repeats) / n_single,
            "batch_us": 1e6 * _median_seconds(batch, repeats) / n,
            "solutions_per_pose": float(batch().valid.sum() / n),
        }
    return report


def format_report(report: dict) -> str:
    """The report as a small table."""
    lines = [f"closed-form IK, µs per pose (batch of {report['n']}, median of {report['repeats']})"]
    lines.append(f"{'solver':<10} {'single':>10} {'batched':>10} {'solutions':>10}")
    for name in ("puma", "ur", "planar_2r"):
        row = report[name]
        lines.append(
            f"{name:<10} {row['single_us']:>10.1f} {row['batch_us']:>10.2f} "
            f"{row['solutions_per_pose']:>10.2f}"
        )
    return "\n".join(lines)


if __name__ == "__main__":
    print(format_report(run()))
