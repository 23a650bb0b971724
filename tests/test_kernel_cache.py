"""numba's cache of a kernel is stamped by the modules it imports (redik.core.kernel_cache)."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from redik.core import kernel_cache

CALLEE = (
    "import numba\n\nLIMIT = {value}\n\n\n@numba.njit(cache=True)\ndef value():\n    return LIMIT\n"
)
CALLER = textwrap.dedent(
    """\
    import numba

    from kpkg.callee import value


    @numba.njit(cache=True)
    def call():
        return value()
    """
)


def make_package(root: Path, value: int) -> Path:
    package = root / "kpkg"
    package.mkdir(exist_ok=True)
    (package / "__init__.py").write_text("")
    (package / "callee.py").write_text(CALLEE.format(value=value))
    (package / "caller.py").write_text(CALLER)
    return package


def run_caller(root: Path, package: Path, env: dict[str, str]) -> str:
    """``call()`` in a fresh process whose kernel cache treats ``package`` as redik's."""
    script = textwrap.dedent(
        f"""\
        import sys
        from pathlib import Path
        sys.path.insert(0, {str(root)!r})
        from redik.core import kernel_cache
        kernel_cache.PACKAGE = Path({str(package)!r})
        from kpkg.caller import call
        print(call())
        """
    )
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, env=env, check=True
    )
    return done.stdout.strip()


@pytest.mark.slow
@pytest.mark.parametrize("where", ["in_tree", "cache_dir"])
def test_a_kernel_recompiles_when_a_module_it_imports_changes(tmp_path, where):
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    if where == "cache_dir":
        env["NUMBA_CACHE_DIR"] = str(tmp_path / "numba-cache")
    package = make_package(tmp_path, 1)
    assert run_caller(tmp_path, package, env) == "1"
    assert run_caller(tmp_path, package, env) == "1"  # loaded from the cache
    (package / "callee.py").write_text(CALLEE.format(value=2))  # caller.py is unchanged
    assert run_caller(tmp_path, package, env) == "2"
    cached = tmp_path / "numba-cache" if where == "cache_dir" else package / "__pycache__"
    assert any(cached.rglob("caller.call-*.nbi"))


def test_the_stamp_covers_the_top_level_imports_transitively(tmp_path, monkeypatch):
    package = make_package(tmp_path, 1)
    (package / "lazy.py").write_text("def f():\n    from kpkg.callee import value\n")
    monkeypatch.setattr(kernel_cache, "PACKAGE", package)
    kernel_cache._imports.cache_clear()
    kernel_cache.source_stamp.cache_clear()
    caller, callee = package / "caller.py", package / "callee.py"
    assert kernel_cache.dependencies(caller) == (callee, caller)
    assert kernel_cache.dependencies(package / "lazy.py") == (package / "lazy.py",)
    (package / "relative.py").write_text("from .callee import value\n")
    (package / "by_name.py").write_text("from kpkg import (  # the module itself\n    callee,\n)\n")
    init = package / "__init__.py"
    for importer in ("relative.py", "by_name.py"):
        assert callee in kernel_cache.dependencies(package / importer)
    assert kernel_cache.dependencies(package / "by_name.py") == (
        init,
        package / "by_name.py",
        callee,
    )
    before = kernel_cache.source_stamp(caller)
    callee.write_text(CALLEE.format(value=2))
    kernel_cache.source_stamp.cache_clear()
    assert kernel_cache.source_stamp(caller) != before


def test_redik_kernels_are_stamped_by_what_they_call():
    kernel = kernel_cache.PACKAGE / "solvers" / "dls" / "kernel.py"
    names = {
        p.relative_to(kernel_cache.PACKAGE).as_posix() for p in kernel_cache.dependencies(kernel)
    }
    assert {"kinematics/compiled.py", "solvers/dls/damped.py", "lie/so3.py"} <= names
    assert "apps/cli/__init__.py" not in names
