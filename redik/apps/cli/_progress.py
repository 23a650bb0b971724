"""Progress bars of the long subcommands: tqdm on stderr, only for a person watching.

A bar is drawn when stderr is a terminal and ``--quiet`` was not given; piped or redirected
output (CI logs, ``2> file``) stays clean. The module name starts with ``_``, so the CLI's
subcommand discovery skips it.
"""

from __future__ import annotations

import sys

from tqdm import tqdm


def wanted(quiet: bool) -> bool:
    """Whether to draw bars: stderr is a terminal and the user did not ask for quiet."""
    return not quiet and sys.stderr.isatty()


def bar(total: int | None, desc: str, unit: str, enabled: bool, leave: bool = True) -> tqdm:
    """A tqdm bar on stderr (a silent one when ``enabled`` is False)."""
    return tqdm(
        total=total, desc=desc, unit=unit, file=sys.stderr, disable=not enabled, leave=leave
    )
