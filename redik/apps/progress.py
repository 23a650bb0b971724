"""Progress bars of the long-running applications: one builder, tqdm on stderr.

Every bar of redik (``redik explore``, ``redik batch``, ``redik regress``, the steps of a
spec) is made by :func:`progress_bar`, so they all write to stderr, keep stdout for
results, and are silent when disabled. The command line draws one only for a person watching
(:func:`wanted`: stderr is a terminal and ``--quiet`` was not given); piped or redirected
output (CI logs, ``2> file``) stays clean.
"""

from __future__ import annotations

import sys
from collections.abc import Iterable

from tqdm import tqdm


def wanted(quiet: bool) -> bool:
    """Whether to draw bars: stderr is a terminal and the user did not ask for quiet."""
    return not quiet and sys.stderr.isatty()


def progress_bar(
    iterable: Iterable | None = None,
    *,
    total: int | None = None,
    desc: str | None = None,
    unit: str = "it",
    enabled: bool = True,
    leave: bool = True,
) -> tqdm:
    """A tqdm bar on stderr over ``iterable`` (or updated by hand), silent unless ``enabled``.

    Args:
        iterable: What to iterate, advancing the bar; None for a bar advanced by ``update``.
        total: Number of steps (default ``len(iterable)`` when it has one; None: a counter).
        desc: Label written before the bar.
        unit: Name of one step.
        enabled: Draw it; a disabled bar accepts every call and writes nothing.
        leave: Keep the finished bar on screen (False: erase it).
    """
    return tqdm(
        iterable, total=total, desc=desc, unit=unit, file=sys.stderr, disable=not enabled,
        leave=leave,
    )  # fmt: skip
