"""The README's Python examples run as written, and its names hold across the repository."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parent.parent / "README.md"
BLOCKS = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.DOTALL)


def test_readme_has_python_examples():
    assert BLOCKS


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_readme_block_runs(index, capsys):
    exec(compile(BLOCKS[index], f"README.md block {index}", "exec"), {})
    assert capsys.readouterr().out.strip()


def _public_api_names() -> list[str]:
    """The backticked names of the README's "Public API" list (the ``- **Group**:`` lines)."""
    section = README.read_text().split("## Public API\n", 1)[1].split("\n## ", 1)[0]
    lines = [line for line in section.splitlines() if line.startswith("- **")]
    return [name for line in lines for name in re.findall(r"`(\w+)`", line.split(":", 1)[1])]


def test_readme_public_api_is_redik_all():
    import redik

    listed = _public_api_names()
    assert len(listed) == len(set(listed)), "a name is listed twice"
    assert set(listed) == set(redik.__all__), (
        f"in redik.__all__ only: {sorted(set(redik.__all__) - set(listed))}; "
        f"in the README only: {sorted(set(listed) - set(redik.__all__))}"
    )
    for name in listed:
        assert hasattr(redik, name), name


def test_the_one_home_table_names_functions_and_tests_that_exist():
    import importlib

    text = README.read_text()
    table = text[text.index("| formula | home |") : text.index("Reused rather than written")]
    rows = [line for line in table.splitlines()[2:] if line.startswith("|")]
    assert len(rows) >= 15
    tests = Path(__file__).resolve().parent
    for row in rows:
        _, _, home, twin, pinned, _ = row.split("|")
        for name in re.findall(r"`([a-z_][\w.]*\.\w+)`", home + twin):
            module_path, attribute = name.rsplit(".", 1)
            try:
                module = importlib.import_module(f"redik.{module_path}")
            except ModuleNotFoundError:  # a class attribute: redik.<module>.<Class>.<method>
                module_path, owner = module_path.rsplit(".", 1)
                module = getattr(importlib.import_module(f"redik.{module_path}"), owner)
            assert hasattr(module, attribute), f"README names redik.{name}, which does not exist"
        for file, test in re.findall(r"`(test_\w+\.py)::(test_\w+)`", pinned):
            source = (tests / file).read_text()
            assert f"def {test}(" in source, f"README names {file}::{test}, which does not exist"


ROOT = README.parent
RETIRED = {
    r"\bPoseTask\b": "FrameTask",
    r"\bFrameTargetTask\b": "SingleFrameTask",
    r"\bPositionLimit\b": "ConfigurationLimit",
    r"(?<!\w)weight=": "cost=",
    r"\bset_weights?\b": "set_cost",
    r"\bmax_iter\b": "max_iterations",
    r"\bMAX_ITER\b": "MAX_ITERATIONS",
    r"\btaskspec\b": "specs",
    r"\b_compat\b": "nothing: no shims before the first release",
    r"\bgradient_descent\b": 'solve_equations(method="transpose")',
    r"\bgradient_then_newton\b": "transpose_then_newton",
    r"\bBatchOptions\b": "DLSOptions",
    r"\bkinematics[./]dls\b": "solvers.dls",
}
"""Names that left, as patterns, and the one word that replaced each (README, *Names*)."""

THIRD_PARTY = ('"max_iter": 400000',)
"""Lines where another library's own option keeps its name (osqp's ``max_iter``)."""


def test_one_word_per_idea_across_the_repository():
    files = [ROOT / "README.md", ROOT / "CHANGELOG.md", ROOT / "Makefile", ROOT / "pyproject.toml"]
    for folder in ("redik", "tests", "examples", "specs"):
        files += sorted((ROOT / folder).rglob("*.py"))
    found = []
    for path in files:
        if path == Path(__file__).resolve():
            continue
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if any(kept in line for kept in THIRD_PARTY):
                continue
            for pattern, word in RETIRED.items():
                if re.search(pattern, line):
                    found.append(f"{path.relative_to(ROOT)}:{number}: use {word}: {line.strip()}")
    assert not found, "\n".join(found)
