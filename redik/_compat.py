"""Import paths of the flat tree (before the layer folders), kept for one release.

``import redik.pose_ik`` or ``from redik.robot import Robot`` still work: a finder on
``sys.meta_path`` answers the old dotted name with the module that now holds the code (the same
module object, so ``isinstance`` checks and monkeypatching see one module), and warns once with
a :class:`DeprecationWarning` that names the new path. Modules split after the move into
packages are mapped the same way (``redik.solvers.pose_ik`` → ``redik.solvers.pose``, whose
public names are those of the old module). The table below is the whole map; the
longest old prefix wins (``redik.batch.chain`` → ``redik.kinematics.chain`` before
``redik.batch`` → ``redik.solvers.batch``).
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import warnings
from types import ModuleType

MOVED: dict[str, str] = {
    "redik.exceptions": "redik.core.exceptions",
    "redik.conventions": "redik.core.conventions",
    "redik._validate": "redik.core._validate",
    "redik.result": "redik.core.result",
    "redik.loading": "redik.models.loading",
    "redik.model_builder": "redik.models.builder",
    "redik.scene_library": "redik.models.scene_library",
    "redik.scenes": "redik.models.scenes",
    "redik.dh": "redik.models.dh",
    "redik.robot": "redik.kinematics.robot",
    "redik.batch.chain": "redik.kinematics.chain",
    "redik.batch.kinematics": "redik.kinematics.batched",
    "redik.iterative": "redik.solvers.iterative",
    "redik.pose_ik": "redik.solvers.pose",
    "redik.pose_qp": "redik.solvers.pose.qp",
    "redik.solvers.pose_ik": "redik.solvers.pose",
    "redik.solvers.pose_qp": "redik.solvers.pose.qp",
    "redik.problem": "redik.solvers.problem",
    "redik.analytic": "redik.solvers.analytic",
    "redik.batch": "redik.solvers.batch",
    "redik.redundancy.plot": "redik.apps.selfmotion_plot",
    "redik.redundancy": "redik.solvers.redundancy",
    **{
        f"redik.{name}": f"redik.apps.{name}"
        for name in (
            "trajectory",
            "sim",
            "render",
            "plot",
            "workspace",
            "taskspec",
            "regress",
            "demo",
            "bench",
            "cli",
        )
    },
}
"""Old dotted module name → new one."""


def new_name(old: str) -> str | None:
    """The module that now holds ``old`` (longest moved prefix), or ``None`` if it never moved."""
    parts = old.split(".")
    for end in range(len(parts), 1, -1):
        head = ".".join(parts[:end])
        if head in MOVED:
            return ".".join([MOVED[head], *parts[end:]])
    return None


class _Alias(importlib.abc.Loader):
    def __init__(self, target: str) -> None:
        self.target = target

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> ModuleType:
        module = importlib.import_module(self.target)
        self.real_spec = module.__spec__
        return module

    def exec_module(self, module: ModuleType) -> None:
        alias = module.__spec__.name
        # importlib has just set the alias spec on the shared module object: restore its own.
        module.__spec__ = self.real_spec
        # Answer the submodules the package has already imported under their old names too, so
        # that ``import redik.analytic.puma`` finds one in sys.modules; through the import
        # system it would set the module as the package's ``puma`` attribute, over the
        # function of that name.
        prefix = self.target + "."
        for name, submodule in list(sys.modules.items()):
            if name.startswith(prefix):
                old = alias + name[len(self.target) :]
                if new_name(old) == name:
                    sys.modules.setdefault(old, submodule)


class MovedModuleFinder(importlib.abc.MetaPathFinder):
    """Answers an old module name with its new module (see the module docstring)."""

    def find_spec(self, fullname, path=None, target=None):
        target_name = new_name(fullname)
        if target_name is None:
            return None
        warnings.warn(
            f"{fullname} moved to {target_name}; the old path works until the next release",
            DeprecationWarning,
            stacklevel=2,
        )
        return importlib.machinery.ModuleSpec(fullname, _Alias(target_name))


def install() -> None:
    """Put the finder first on ``sys.meta_path`` (once)."""
    if not any(isinstance(finder, MovedModuleFinder) for finder in sys.meta_path):
        sys.meta_path.insert(0, MovedModuleFinder())


install()
