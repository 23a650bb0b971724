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
    for folder in ("redik", "tests", "examples", "specs", "docs"):
        files += sorted((ROOT / folder).rglob("*.py"))
    files += sorted((ROOT / "docs").rglob("*.md"))
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
