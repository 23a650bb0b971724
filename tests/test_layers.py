"""The import-layer contract of redik/ (docs/architecture.md), checked on the source with ast.

Layers, lowest first; a module may import from its own layer or a lower one, never from a
higher one:

1. **core** — errors, conventions, result records, the boundary checks;
2. **lie** — SO(3)/SE(3) group math;
3. **models** — model files and their loading, third-party model packages, the bundled
   scenes, DH tables and the MJCF builders;
4. **kinematics** — robots (MuJoCo FK and Jacobians), the compiled chain, its vectorised and
   compiled FK, Jacobian and pose error;
5. **criteria** — secondary criteria, value and gradient;
6. **tasks and limits** — what a QP step should achieve and may not do;
7. **qp** — the differential IK ``Problem``, QP assembly, lexicographic hierarchy,
   back-ends;
8. **solvers** — analytic, iterative, damped least squares, pose IK (and its QP method), the
   task-stack driver, batch IK, redundancy;
9. **applications** — trajectories, simulation, rendering, plots, workspace, specs,
   regression, demo, benchmarks, CLI;
10. **package** — ``redik/__init__.py`` and ``__main__``, which export the public names.

Within the solvers layer the solver packages are peers: one uses another only through its
entry points (:data:`SOLVER_ENTRY_POINTS`), not by reaching into its internals.

Imports inside ``if TYPE_CHECKING:`` blocks are annotations only and not counted; imports
inside functions (lazy imports) are. A known violation may be listed in :data:`ALLOWED` with
its reason; the test fails when a new violation appears *and* when a listed one is gone
(delete its entry then), so the list stays true. It is empty.
"""

from __future__ import annotations

import ast
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1] / "redik"

LAYERS: list[tuple[str, tuple[str, ...]]] = [
    ("core", ("core.*",)),
    ("lie", ("lie.*",)),
    ("models", ("models.*",)),
    ("kinematics", ("kinematics.*",)),
    ("criteria", ("criteria",)),
    ("tasks and limits", ("tasks.*", "limits.*")),
    ("qp", ("qp.*",)),
    ("solvers", ("solvers.*",)),
    ("applications", ("apps.*",)),
    ("package", ("", "__main__")),
]
"""Each layer and its modules (names relative to ``redik``; ``pkg.*`` is the package and
everything in it; the most specific entry wins)."""

SOLVER_PACKAGES = tuple(
    f"solvers.{name}"
    for name in ("analytic", "iterative", "dls", "pose", "task_stack", "batch", "redundancy")
)

SOLVER_ENTRY_POINTS = {
    "solvers.analytic": ("solvers.analytic", "solvers.analytic.srs"),
    "solvers.batch": ("solvers.batch",),
    "solvers.dls": ("solvers.dls",),
    "solvers.iterative": ("solvers.iterative",),
    "solvers.pose": ("solvers.pose", "solvers.pose.qp", "solvers.pose.frame"),
    "solvers.task_stack": ("solvers.task_stack",),
    "solvers.redundancy": ("solvers.redundancy",),
}
"""The modules through which one solver package may use another."""

ALLOWED: dict[tuple[str, str], str] = {}
"""Known violations, ``(importer, imported)`` → why it is there and where it should go."""


def module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


MODULES = {module_name(path): path for path in sorted(ROOT.rglob("*.py"))}


def layer_of(module: str) -> int:
    best, best_length = None, -1
    for index, (_, patterns) in enumerate(LAYERS):
        for pattern in patterns:
            if pattern.endswith(".*"):
                package = pattern[:-2]
                hit = module == package or module.startswith(package + ".")
                length = len(package)
            else:
                hit, length = module == pattern, len(pattern) + 1  # exact beats a package
            if hit and length > best_length:
                best, best_length = index, length
    if best is None:
        raise AssertionError(f"redik.{module} is in no layer: add it to LAYERS in {__file__}")
    return best


def _type_checking_nodes(tree: ast.Module) -> set[int]:
    skipped = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            skipped.update(id(child) for stmt in node.body for child in ast.walk(stmt))
    return skipped


def imports(module: str) -> set[str]:
    """The redik modules ``module`` imports (relative to ``redik``), outside TYPE_CHECKING."""
    path = MODULES[module]
    tree = ast.parse(path.read_text(encoding="utf-8"))
    skipped = _type_checking_nodes(tree)
    package = module.split(".") if path.name == "__init__.py" else module.split(".")[:-1]
    package = [p for p in package if p]
    found = set()
    for node in ast.walk(tree):
        if id(node) in skipped:
            continue
        targets = []
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            elif node.module == "redik" or (node.module or "").startswith("redik."):
                target = node.module.removeprefix("redik").lstrip(".")
            else:
                continue
            for alias in node.names:
                full = f"{target}.{alias.name}".lstrip(".")
                targets.append(full if full in MODULES else target)
        elif isinstance(node, ast.Import):
            targets = [
                a.name.removeprefix("redik").lstrip(".")
                for a in node.names
                if a.name == "redik" or a.name.startswith("redik.")
            ]
        found.update(t for t in targets if t != module)
    return found


def solver_package(module: str) -> str | None:
    head = ".".join(module.split(".")[:2])
    return head if head in SOLVER_PACKAGES and layer_of(module) == SOLVERS else None


SOLVERS = [name for name, _ in LAYERS].index("solvers")


def violations() -> dict[tuple[str, str], str]:
    found = {}
    for module in MODULES:
        for imported in imports(module):
            if imported not in MODULES:
                raise AssertionError(f"redik.{module} imports redik.{imported}, not a module")
            low, high = layer_of(imported), layer_of(module)
            if low > high:
                found[(module, imported)] = (
                    f"{LAYERS[high][0]} imports {LAYERS[low][0]} (a higher layer)"
                )
                continue
            mine, theirs = solver_package(module), solver_package(imported)
            if mine and theirs and mine != theirs and imported not in SOLVER_ENTRY_POINTS[theirs]:
                found[(module, imported)] = f"solver {mine} reaches into {theirs}'s internals"
    return found


def test_every_module_has_a_layer():
    for module in MODULES:
        layer_of(module)


def test_no_import_from_a_higher_layer_beyond_the_allow_list():
    found = violations()
    new = {edge: why for edge, why in found.items() if edge not in ALLOWED}
    assert not new, "new layer violations:\n" + "\n".join(
        f"  redik.{a} -> redik.{b}: {why}" for (a, b), why in sorted(new.items())
    )


def test_every_allowed_violation_still_exists():
    found = violations()
    gone = sorted(edge for edge in ALLOWED if edge not in found)
    assert not gone, "fixed, now remove from ALLOWED: " + ", ".join(f"{a} -> {b}" for a, b in gone)


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("from ..solvers.pose.qp import solve_pose_qp\n", {"solvers.pose.qp"}),
        ("from .. import criteria\n", {"criteria"}),
        ("from .task import Task\n", {"tasks.task"}),
        ("import redik.solvers.task_stack\n", {"solvers.task_stack"}),
        ("from redik.solvers.batch import engines\n", {"solvers.batch.engines"}),
        (
            "from typing import TYPE_CHECKING\n"
            "if TYPE_CHECKING:\n    from ..solvers.task_stack import P\n",
            set(),
        ),
        ("def f():\n    from ..solvers.task_stack import Problem\n", {"solvers.task_stack"}),
        ("import numpy\nfrom mink import Task\n", set()),
    ],
)
def test_imports_are_resolved_as_python_does(tmp_path, monkeypatch, source, expected):
    probe = tmp_path / "probe.py"
    probe.write_text(source)
    monkeypatch.setitem(MODULES, "tasks.probe", probe)  # relative to the redik.tasks package
    assert imports("tasks.probe") == expected


def test_a_violation_is_detected(monkeypatch, tmp_path):
    probe = tmp_path / "probe.py"
    probe.write_text("from .tasks.task import Task\nfrom .solvers.batch.solve import solve_batch\n")
    monkeypatch.setitem(MODULES, "probe", probe)
    at = [name for name, _ in LAYERS].index("criteria")
    layers = [*LAYERS[:at], ("criteria", ("criteria", "probe")), *LAYERS[at + 1 :]]
    monkeypatch.setattr(sys.modules[__name__], "LAYERS", layers)
    found = violations()
    assert "a higher layer" in found[("probe", "tasks.task")]
    assert ("probe", "solvers.batch.solve") in found
    assert set(found) - {("probe", "tasks.task"), ("probe", "solvers.batch.solve")} == set(ALLOWED)


def test_docs_architecture_table_states_these_layers():
    page = (ROOT.parent / "docs" / "architecture.md").read_text(encoding="utf-8")
    section = page.split("# Architecture", 1)[1].split("\n## ", 1)[0]
    table = section[section.index("| layer |") :].split("\n\n", 1)[0]  # the first table
    rows = re.findall(r"^\| ([a-z ]+) \| (.+) \|$", table, flags=re.MULTILINE)[1:]  # no header
    names = [name for name, _ in LAYERS if name != "package"]
    assert [name for name, _ in rows] == names
    for index, (_, cell) in enumerate(rows):
        while re.search(r"\([^()]*\)", cell):
            cell = re.sub(r"\([^()]*\)", "", cell)  # submodules and comments in parentheses
        for token in re.findall(r"`([^`]+)`", cell):
            module = token.rstrip("/").replace("/", ".")
            assert module in MODULES, (
                f"docs/architecture.md names redik/{token}, which does not exist"
            )
            assert layer_of(module) == index, (
                f"docs/architecture.md puts redik/{token} in {names[index]}"
            )
