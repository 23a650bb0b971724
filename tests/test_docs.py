"""The documentation's pages hold to the code, and its build hook finds what the pages ask for.

The site itself (every page built with warnings as errors and opened in a browser) is checked
by ``tests/test_docs_site.py``; these are the fast checks of what the pages state.
"""

from __future__ import annotations

import importlib
import importlib.util
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
GUIDES = DOCS / "guides" / "index.md"
ARCHITECTURE = DOCS / "architecture.md"


def _hook():
    """``docs/hooks/site.py``, the build hook, as a module."""
    spec = importlib.util.spec_from_file_location("docs_site_hook", DOCS / "hooks" / "site.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _public_api_names() -> list[str]:
    """The backticked names of the guides' "Public API" list (the ``- **Group**:`` lines)."""
    section = GUIDES.read_text(encoding="utf-8").split("## Public API\n", 1)[1]
    section = section.split("\n## ", 1)[0]
    lines = [line for line in section.splitlines() if line.startswith("- **")]
    return [name for line in lines for name in re.findall(r"`(\w+)`", line.split(":", 1)[1])]


def test_the_public_api_list_is_redik_all():
    import redik

    listed = _public_api_names()
    assert len(listed) == len(set(listed)), "a name is listed twice"
    assert set(listed) == set(redik.__all__), (
        f"in redik.__all__ only: {sorted(set(redik.__all__) - set(listed))}; "
        f"in docs/guides/index.md only: {sorted(set(listed) - set(redik.__all__))}"
    )
    for name in listed:
        assert hasattr(redik, name), name


def _attribute_exists(name: str) -> bool:
    """Whether ``redik.<name>`` exists: a module's attribute, or a class's."""
    module_path, attribute = name.rsplit(".", 1)
    try:
        owner = importlib.import_module(f"redik.{module_path}")
    except ModuleNotFoundError:  # a class attribute: redik.<module>.<Class>.<method>
        module_path, cls = module_path.rsplit(".", 1)
        owner = getattr(importlib.import_module(f"redik.{module_path}"), cls)
    return hasattr(owner, attribute)


def test_the_one_home_table_names_functions_and_tests_that_exist():
    text = ARCHITECTURE.read_text(encoding="utf-8")
    table = text[text.index("| formula | home |") : text.index("Reused rather than written")]
    rows = [line for line in table.splitlines()[2:] if line.startswith("|")]
    assert len(rows) >= 15
    tests = ROOT / "tests"
    for row in rows:
        _, _, home, twin, pinned, _ = row.split("|")
        for name in re.findall(r"`([a-z_][\w.]*\.\w+)`", home + twin):
            assert _attribute_exists(name), f"docs name redik.{name}, which does not exist"
        for file, test in re.findall(r"`(test_\w+\.py)::(test_\w+)`", pinned):
            source = (tests / file).read_text(encoding="utf-8")
            assert f"def {test}(" in source, f"docs name {file}::{test}, which does not exist"


def test_every_public_module_has_its_own_reference_page():
    hook = _hook()
    modules = hook.public_modules()
    assert {"redik", "redik.solvers.pose", "redik.lie.so3"} <= set(modules)
    pages = [hook.reference_page(module) for module in modules]
    assert len(set(pages)) == len(pages)
    assert not [m for m in modules if any(part.startswith("_") for part in m.split("."))]


def test_the_pages_show_runs_of_examples_that_exist():
    scripts = _hook().requested_runs(DOCS)
    assert "selfmotion_panda" in scripts
    for stem, script in scripts.items():
        assert script.is_file(), stem


@pytest.fixture
def course(tmp_path, monkeypatch):
    """The hook with an empty ``examples/course/`` of its own."""
    hook = _hook()
    folder = tmp_path / "examples" / "course"
    folder.mkdir(parents=True)
    monkeypatch.setattr(hook, "ROOT", tmp_path)
    monkeypatch.setattr(hook, "COURSE", folder)
    return hook, folder


def test_a_course_page_without_scripts_says_where_they_go(course):
    hook, _ = course
    section = hook.course_section("003")
    assert "examples/course/003_*.py" in section
    assert "--8<--" not in section  # nothing to include, so nothing to fail on
    assert hook.course_readme() == ""
    assert hook.course_helpers() == ""


def test_a_course_page_shows_each_script_of_its_document_in_order(course):
    hook, folder = course
    (folder / "003_b_table.py").write_text('"""Second.\n\nThe table of §6.2."""\nprint(2)\n')
    (folder / "003_a_newton.py").write_text('"""First example.\n\nNewton from θ⁰."""\nprint(1)\n')
    (folder / "004_other.py").write_text('"""Not this document."""\n')
    (folder / "README.md").write_text("# Course scripts\n\n## Running\n")
    (folder / "_shared.py").write_text('"""Tables."""\n')
    section = hook.course_section("003")
    assert section.index("## First example") < section.index("## Second")
    assert "Newton from θ⁰." in section
    assert '--8<-- "examples/course/003_a_newton.py"' in section
    assert '--8<-- "runs/course_003_a_newton/output.txt"' in section
    assert "004_other" not in section
    assert hook.course_readme() == "## Course scripts\n\n### Running\n"
    assert '--8<-- "examples/course/_shared.py"' in hook.course_helpers()
    scripts = ["003_a_newton.py", "003_b_table.py", "004_other.py"]
    assert [path.name for path in hook.course_scripts()] == scripts


def test_the_course_readme_links_each_document_to_its_page():
    hook = _hook()
    text = hook.course_readme()
    links = re.findall(r"^\| \[(\d{3})\]\(([^)]+)\) \|", text, flags=re.MULTILINE)
    assert [document for document, _ in links] == ["000", "001", "002", "003", "004"]
    for document, page in links:
        assert page.startswith(f"{document}-") and (DOCS / "course" / page).is_file(), page
    assert "| document |" not in (DOCS / "course" / "index.md").read_text(encoding="utf-8")
