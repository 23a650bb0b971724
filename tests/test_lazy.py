"""redik.core.lazy and redik/__init__.py: ``import redik`` loads the layers up to the kinematics;
every public name and subpackage is there on first use, whatever was used before it."""

from __future__ import annotations

import ast
import json
import subprocess
import sys
from pathlib import Path

import pytest

import redik
from redik.core.lazy import lazy_submodules

ROOT = Path(__file__).resolve().parents[1]
UPPER_LAYERS = (
    "redik.apps",
    "redik.criteria",
    "redik.limits",
    "redik.qp",
    "redik.solvers",
    "redik.tasks",
)


def _fresh(code: str) -> dict:
    """What ``code`` prints as JSON, run in a new interpreter on this tree."""
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT,
        env={"PYTHONPATH": str(ROOT), "PATH": ""},
    )  # fmt: skip
    return json.loads(out.stdout)


@pytest.mark.slow
def test_import_redik_loads_no_upper_layer_nor_mink():
    loaded = _fresh("import json, sys, redik; print(json.dumps(sorted(sys.modules)))")
    assert not [m for m in loaded if m.startswith(UPPER_LAYERS)]
    assert "mink" not in loaded and "scipy.optimize" not in loaded and "scipy.special" not in loaded
    assert "redik.kinematics.robot" in loaded and "redik.lie" in loaded


@pytest.mark.slow
def test_a_subpackage_is_there_whatever_was_used_first():
    # solve_pose imports redik.solvers.pose, which binds redik.solvers without its analytic
    # subpackage: the package's own lazy __getattr__ still finds it.
    found = _fresh(
        "import json, redik; redik.solve_pose; "
        "print(json.dumps([redik.solvers.analytic.__name__, redik.apps.workspace.__name__, "
        "redik.models.dh.__name__, redik.kinematics.chain.__name__, "
        "redik.core.conventions.__name__]))"
    )
    assert found == [
        "redik.solvers.analytic", "redik.apps.workspace", "redik.models.dh",
        "redik.kinematics.chain", "redik.core.conventions",
    ]  # fmt: skip


def test_every_public_name_resolves_and_dir_lists_it():
    for name in redik.__all__:
        assert getattr(redik, name) is not None, name
    assert set(redik.__all__) <= set(dir(redik))
    from redik import FrameTask, solve_pose  # from-imports go through __getattr__ too

    assert solve_pose is redik.solve_pose and FrameTask is redik.tasks.FrameTask


def test_unknown_names_raise_attribute_error():
    with pytest.raises(AttributeError, match="module 'redik' has no attribute 'solve_everything'"):
        redik.solve_everything  # noqa: B018
    with pytest.raises(AttributeError, match=r"'redik\.solvers' has no attribute '__wrapped__'"):
        redik.solvers.__wrapped__  # noqa: B018
    assert not hasattr(redik.solvers, "no_such_solver")


def test_lazy_submodules_imports_only_submodules():
    getattr_ = lazy_submodules("redik.models")
    assert getattr_("dh").__name__ == "redik.models.dh"
    with pytest.raises(AttributeError, match=r"'redik\.models' has no attribute 'nothing'"):
        getattr_("nothing")


def test_the_type_checking_imports_are_the_lazy_table():
    """Editors and type checkers see the names that ``__getattr__`` resolves, from the same
    modules."""
    tree = ast.parse((ROOT / "redik" / "__init__.py").read_text(encoding="utf-8"))
    block = next(
        node
        for node in tree.body
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test)
    )
    imported = {
        alias.name: node.module
        for node in block.body
        if isinstance(node, ast.ImportFrom) and node.module != "redik"
        for alias in node.names
    }
    assert imported == redik._MODULE_OF
