"""numba's disk cache of redik's kernels, kept fresh when a module they import changes.

numba caches a compiled function (``cache=True``) under a stamp of its own source file only.
A kernel's machine code also holds the callees it inlined and the module constants it read,
often from other files (the DLS kernel calls :mod:`redik.kinematics.compiled` and
:mod:`redik.lie`): after an edit there, numba would keep loading the old code until the
kernel's own file changed.

:func:`register` puts cache locators ahead of numba's own for the files of this package. They
store the same files in the same places, under a stamp that also covers every redik module
the kernel's file imports, transitively (found from its ``import`` lines, read once per
process): an edit to any of them recompiles the kernel on its next use. Files outside redik
keep numba's locators.
"""

from __future__ import annotations

import hashlib
import re
from functools import cache
from pathlib import Path
from typing import Any

from numba.core import caching

PACKAGE = Path(__file__).resolve().parent.parent
"""The directory of the ``redik`` package."""


_FROM = re.compile(r"^from\s+(\.*[\w.]*)\s+import\s+(\([^)]*\)|[^\n]*)", re.M)
_IMPORT = re.compile(r"^import\s+([\w.]+)", re.M)


def _module_file(module: str) -> Path | None:
    """The source file of module ``module`` of the package, or None if it has none."""
    parts = module.split(".")
    if parts[0] != PACKAGE.name:
        return None
    path = PACKAGE.parent.joinpath(*parts)
    for candidate in (path.with_suffix(".py"), path / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


def _absolute(module: str, path: Path) -> str:
    """``module`` as written in ``path`` (``.x``, ``..x``, or absolute) made absolute."""
    dots = len(module) - len(module.lstrip("."))
    if dots == 0:
        return module
    package = path.parent.relative_to(PACKAGE.parent).parts
    base = package[: len(package) - dots + 1]
    return ".".join([*base, module[dots:]] if module[dots:] else base)


@cache
def _imports(path: Path) -> tuple[Path, ...]:
    """The package's source files that ``path`` imports at its top level.

    Those are where the names a kernel calls or reads are defined (or re-exported from): the
    module of each ``import`` and ``from … import`` (relative ones too), and each imported
    name that is itself a module. Imports inside functions and under ``if TYPE_CHECKING:``
    are indented, and not followed.
    """
    text = path.read_text(encoding="utf-8")
    modules = [match.group(1) for match in _IMPORT.finditer(text)]
    for match in _FROM.finditer(text):
        module = _absolute(match.group(1), path)
        modules.append(module)
        names = re.sub(r"#[^\n]*", "", match.group(2)).strip("()")
        for name in names.split(","):
            if name.split():
                modules.append(f"{module}.{name.split()[0]}")
    found = {found for module in modules if (found := _module_file(module)) is not None}
    found.discard(path)
    return tuple(sorted(found))


def dependencies(path: Path) -> tuple[Path, ...]:
    """``path`` and every redik source file it imports, transitively, sorted."""
    seen, todo = {path}, [path]
    while todo:
        for imported in _imports(todo.pop()):
            if imported not in seen:
                seen.add(imported)
                todo.append(imported)
    return tuple(sorted(seen))


@cache
def source_stamp(path: Path) -> str:
    """A digest of the contents of ``path`` and of every redik file it imports.

    Computed once per file and process, as numba reads a stamp when a module defines its
    functions.
    """
    digest = hashlib.sha256()
    for source in dependencies(path):
        digest.update(str(source.relative_to(PACKAGE)).encode())
        digest.update(hashlib.sha256(source.read_bytes()).digest())
    return digest.hexdigest()


class _TreeStamp:
    """Mixin for numba's source-file locators: redik files only, stamped by their imports."""

    _py_file: str

    def get_source_stamp(self) -> str:
        """The stamp numba compares with the one saved beside the cached code."""
        return source_stamp(Path(self._py_file).resolve())

    @classmethod
    def from_function(cls, py_func: Any, py_file: str) -> Any:
        """This locator for a function defined in redik, else None (numba's own decide)."""
        if not Path(py_file).resolve().is_relative_to(PACKAGE):
            return None
        return super().from_function(py_func, py_file)  # type: ignore[misc]


class _UserProvided(_TreeStamp, caching.UserProvidedCacheLocator):
    """Under ``NUMBA_CACHE_DIR`` when it is set."""


class _InTree(_TreeStamp, caching.InTreeCacheLocator):
    """In ``__pycache__`` beside the sources."""


class _UserWide(_TreeStamp, caching.UserWideCacheLocator):
    """In the user's cache directory when the sources' directory is read-only."""


LOCATORS = (_UserProvided, _InTree, _UserWide)


def register() -> None:
    """Put :data:`LOCATORS` ahead of numba's (once; numba picks the first that applies)."""
    classes = caching.CacheImpl._locator_classes
    if classes[0] is not LOCATORS[0]:
        caching.CacheImpl._locator_classes = [*LOCATORS, *classes]
