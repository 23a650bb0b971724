"""Import on first use: the module ``__getattr__`` (PEP 562) of packages that load lazily.

``import redik`` loads the layers up to the kinematics; the task stack, the solvers (with their
compiled kernels) and the applications cost more to import than most scripts use, so their
packages are imported when a name first reaches them (``redik.solvers.analytic``,
``redik.apps.workspace``), as SciPy loads its subpackages (SPEC 1, *Lazy loading of
submodules and functions*, Scientific Python, 2022).
"""

from __future__ import annotations

import importlib
import importlib.util
from collections.abc import Callable
from types import ModuleType


def lazy_submodules(package: str) -> Callable[[str], ModuleType]:
    """A module ``__getattr__`` that imports a package's submodules on first access.

    Args:
        package: The package's ``__name__``.

    Returns:
        ``__getattr__(name)``: the submodule ``package.name``, imported now (Python then binds it
        on the package, so later accesses do not come back here); :class:`AttributeError` for a
        name that is no submodule (or starts with ``_``, so that probes such as ``__wrapped__``
        import nothing).
    """

    def __getattr__(name: str) -> ModuleType:
        if not name.startswith("_") and importlib.util.find_spec(f"{package}.{name}") is not None:
            return importlib.import_module(f"{package}.{name}")
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    return __getattr__
