"""Benchmarks behind ``redik bench NAME`` — scripts that measure, never tests.

Each module here is one benchmark: its docstring's first line is the help text, and it
defines ``add_arguments(parser)`` and ``run(args) -> int``. ``redik bench all`` runs every
benchmark with its defaults. Machines are noisy: benchmarks report medians and, where they
compare, ratios against a reference measured in the same run.
"""

from __future__ import annotations

import importlib
import os
import pkgutil
from types import ModuleType


def benchmarks() -> dict[str, ModuleType]:
    """The benchmark modules by name."""
    return {
        info.name: importlib.import_module(f"{__name__}.{info.name}")
        for info in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name)
        if not info.name.startswith("_")
    }


def load_average(label: str) -> str:
    """``label: 1-, 5- and 15-minute load averages (CPUs)``, to print beside a timing."""
    one, five, fifteen = os.getloadavg()
    return f"{label}: {one:.2f} {five:.2f} {fifteen:.2f} ({os.cpu_count()} CPUs)"
