"""MkDocs hooks: everything on the site that comes from the code is generated here, at build time.

- **API reference**: one page per public module of ``redik/`` (found on disk, so a module
  that appears, moves or goes changes the site with it), grouped by layer, rendered by
  mkdocstrings from the docstrings.
- **Measured**: ``docs/measured/*.json`` (written by ``redik bench NAME --record FILE``) rendered
  by :mod:`redik.apps.measured`, the same code that writes README's Measured table.
- **Example runs**: a page that includes ``runs/STEM/…`` (``--8<-- "runs/STEM/output.txt"`` for
  what ``examples/STEM.py`` prints, ``![…](../runs/STEM/FILE.png)`` for a figure it writes) makes
  the build run that example headless with ``REDIK_OUT`` set, into ``out/docs/runs/STEM/``. A run
  is reused, by the build and by the example tests, while what it depends on is unchanged.
- **Course**: ``<!-- course-examples NNN -->`` on a course page becomes every
  ``examples/course/NNN_*.py`` (NNN: the lecture-notes document), its docstring, its code and
  what it prints; ``<!-- course-readme -->`` becomes ``examples/course/README.md`` (its table of
  documents linked to their pages) and ``<!-- course-helpers -->`` the modules the scripts
  share (``examples/course/_*.py``).
- **MathJax** is copied from its Python package (``django-static-mathjax``), so equations
  render with no network.
"""

from __future__ import annotations

import concurrent.futures
import hashlib
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

from mkdocs.config.defaults import MkDocsConfig
from mkdocs.exceptions import PluginError
from mkdocs.structure.files import File, Files
from mkdocs.structure.pages import Page

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # this checkout's redik, whatever the environment has installed
RUNS = ROOT / "out" / "docs" / "runs"
COURSE = ROOT / "examples" / "course"
LAYERS = ("core", "lie", "models", "kinematics", "criteria", "tasks", "limits", "qp", "solvers",
          "apps")  # fmt: skip
"""redik's layers, lowest first (README's Architecture; ``tests/test_layers.py`` holds them)."""
RUN_REFERENCE = re.compile(r"runs/([A-Za-z0-9_]+)/")
COURSE_MARKER = re.compile(r"<!-- course-examples (\d{3}) -->")
RUN_TIMEOUT = 600


# --------------------------------------------------------------------------------------
# API reference


def public_modules() -> list[str]:
    """Every public module of redik (no part of its path starts with ``_``), by layer."""
    names = []
    for path in sorted((ROOT / "redik").rglob("*.py")):
        parts = list(path.relative_to(ROOT).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        if any(part.startswith("_") for part in parts):
            continue
        names.append(".".join(parts))

    def layer(name: str) -> tuple[int, str]:
        top = name.split(".")[1] if "." in name else ""
        return (LAYERS.index(top) + 1 if top in LAYERS else len(LAYERS) + 1, name)

    return sorted(names, key=layer)


def reference_page(module: str) -> str:
    """``reference/redik.x.y.md`` for the module ``redik.x.y``.

    One flat folder: a package's page and its submodules' cannot collide (a folder layout
    sends both ``redik.x`` and a module ``redik.x.index`` to ``reference/redik/x/index.html``).
    """
    return f"reference/{module}.md"


def reference_nav() -> list:
    """The API reference's navigation: the index, then each layer's modules."""
    modules = public_modules()
    nav: list = ["reference/index.md", {"redik": reference_page("redik")}]
    for top in LAYERS:
        group = [m for m in modules if m == f"redik.{top}" or m.startswith(f"redik.{top}.")]
        if group:
            nav.append({top: [{_nav_title(m, top): reference_page(m)} for m in group]})
    return nav


def _nav_title(module: str, top: str) -> str:
    """``tasks`` for the package itself, ``frame_task`` for ``redik.tasks.frame_task``."""
    return module.removeprefix(f"redik.{top}").lstrip(".") or f"redik.{top}"


def reference_index() -> str:
    """The API reference's index page: every public module, indented by depth."""
    lines = [
        "# API reference",
        "",
        "Generated from the docstrings: one page per public module, by layer, lowest first "
        "([Architecture](../architecture.md)). The names most code needs are on "
        "[`redik`](redik.md) itself.",
        "",
    ]
    for module in public_modules():
        depth = module.count(".")
        link = reference_page(module).removeprefix("reference/")
        lines.append(f"{'    ' * max(depth - 1, 0)}- [`{module}`]({link})")
    return "\n".join(lines) + "\n"


# --------------------------------------------------------------------------------------
# Example runs


def _source_key(script: Path) -> str:
    """A digest of what a run depends on: its validity.

    The script, the helpers beside it (``_*.py``), every source file of redik and the bundled
    scenes, so that a run kept under an unchanged key is the run the tests would make.
    """
    digest = hashlib.sha256(script.read_bytes())
    scenes = sorted(path for path in (ROOT / "scenes").rglob("*") if path.is_file())
    sources = [*sorted(script.parent.glob("_*.py")), *sorted((ROOT / "redik").rglob("*.py"))]
    for path in [*sources, *scenes]:
        digest.update(path.read_bytes())
    return digest.hexdigest()


def run_directory(script: Path) -> Path:
    """Where the site keeps a script's run: ``runs/STEM``, ``runs/course_STEM`` for the course."""
    prefix = "course_" if script.parent == COURSE else ""
    return RUNS / f"{prefix}{script.stem}"


def current_run(script: Path) -> Path | None:
    """The kept run of ``script`` when it is still valid (its key unchanged), else None.

    A valid run finished without error (only a finished run writes its key), so the example
    tests take it instead of running the script again after ``make docs``.
    """
    out = run_directory(script)
    stamp = out / ".key"
    if stamp.exists() and stamp.read_text() == _source_key(script):
        return out
    return None


def run_example(script: Path) -> None:
    """Run ``script`` headless into its run directory (figures, ``output.txt``) unless current."""
    if current_run(script) is not None:
        return
    out, key = run_directory(script), _source_key(script)
    out.mkdir(parents=True, exist_ok=True)
    env = {
        **os.environ,
        "MUJOCO_GL": "egl",
        "PYOPENGL_PLATFORM": "egl",
        "MPLBACKEND": "Agg",
        "REDIK_OUT": str(out),
        "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
    }
    completed = subprocess.run(
        [sys.executable, str(script)],
        cwd=out,
        env=env,
        capture_output=True,
        text=True,
        timeout=RUN_TIMEOUT,
        check=False,
    )
    if completed.returncode != 0:
        raise PluginError(
            f"{script.relative_to(ROOT)} failed while building the docs:\n"
            f"{completed.stdout[-2000:]}{completed.stderr[-4000:]}"
        )
    output = completed.stdout.replace(f"{out}{os.sep}", "").replace(str(out), ".")
    (out / "output.txt").write_text(output)
    (out / ".key").write_text(key)


def requested_runs(docs_dir: Path) -> dict[str, Path]:
    """The examples the pages ask for (``runs/STEM/``), and the course's scripts."""
    scripts = {}
    for page in docs_dir.rglob("*.md"):
        for stem in RUN_REFERENCE.findall(page.read_text(encoding="utf-8")):
            scripts[stem] = ROOT / "examples" / f"{stem}.py"
    for script in course_scripts():
        scripts[run_directory(script).name] = script
    missing = [str(path.relative_to(ROOT)) for path in scripts.values() if not path.exists()]
    if missing:
        raise PluginError(f"the docs show the runs of examples that do not exist: {missing}")
    return scripts


def run_examples(docs_dir: Path) -> None:
    """Run every requested example, two at a time (the examples are single-threaded)."""
    scripts = requested_runs(docs_dir)
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        futures = [pool.submit(run_example, path) for path in scripts.values()]
        for future in futures:
            future.result()


# --------------------------------------------------------------------------------------
# Course


def course_scripts(document: str | None = None) -> list[Path]:
    """``examples/course/NNN_*.py`` (every document's when ``document`` is None)."""
    if not COURSE.is_dir():
        return []
    pattern = f"{document}_*.py" if document else "[0-9][0-9][0-9]_*.py"
    return sorted(COURSE.glob(pattern))


def _docstring(script: Path) -> tuple[str, str]:
    """The script's docstring: its first line and the rest."""
    import ast

    text = ast.get_docstring(ast.parse(script.read_text(encoding="utf-8"))) or script.stem
    first, _, rest = text.partition("\n")
    return first.strip().rstrip("."), textwrap.dedent(rest).strip()


def course_section(document: str) -> str:
    """The markdown for the worked examples of one lecture-notes document."""
    scripts = course_scripts(document)
    if not scripts:
        return (
            '!!! note "Worked examples"\n'
            f"    The scripts reproducing this document's worked examples go in "
            f"`examples/course/{document}_*.py`; each appears here with what it prints.\n"
        )
    parts = []
    for script in scripts:
        title, body = _docstring(script)
        relative = script.relative_to(ROOT).as_posix()
        parts += [
            f"## {title}",
            "",
            body,
            "",
            f'```python title="{relative}"',
            f'--8<-- "{relative}"',
            "```",
            "",
            "It prints:",
            "",
            "```text",
            f'--8<-- "runs/course_{script.stem}/output.txt"',
            "```",
            "",
        ]
    return "\n".join(parts)


def course_helpers() -> str:
    """The modules the course's scripts share (``examples/course/_*.py``), folded away."""
    helpers = sorted(COURSE.glob("_*.py")) if COURSE.is_dir() else []
    parts = ["What the scripts share:", ""] if helpers else []
    for helper in helpers:
        title, _ = _docstring(helper)
        relative = helper.relative_to(ROOT).as_posix()
        parts += [
            f'??? note "`{relative}`: {title}"',
            "    ```python",
            f'    --8<-- "{relative}"',
            "    ```",
            "",
        ]
    return "\n".join(parts)


def course_readme() -> str:
    """``examples/course/README.md`` for the course's index page (empty when absent).

    Its headings go one level down (under the page's own title), and each document number
    that opens a row of its table of documents links to that document's page
    (``docs/course/NNN-*.md``), so that the table is written once, in the README.
    """
    readme = COURSE / "README.md"
    if not readme.exists():
        return ""
    text = re.sub(r"^#", "##", readme.read_text(encoding="utf-8"), flags=re.MULTILINE)
    pages = {page.name[:3]: page.name for page in (ROOT / "docs" / "course").glob("[0-9]*.md")}

    def link(row: re.Match) -> str:
        document = row.group(1)
        return f"| [{document}]({pages[document]}) |" if document in pages else row.group(0)

    return re.sub(r"^\| (\d{3}) \|", link, text, flags=re.MULTILINE)


# --------------------------------------------------------------------------------------
# Hooks


def on_config(config: MkDocsConfig) -> MkDocsConfig:
    """Put the generated reference pages into the navigation."""
    nav = config.nav or []
    for index, item in enumerate(nav):
        if isinstance(item, dict) and item.get("API reference") == "reference/index.md":
            nav[index] = {"API reference": reference_nav()}
    return config


def on_pre_build(config: MkDocsConfig) -> None:
    """Run the examples whose output or figures the pages show."""
    run_examples(Path(config.docs_dir))


def on_files(files: Files, config: MkDocsConfig) -> Files:
    """Add the generated pages, the example runs' figures and MathJax."""
    from redik.apps.measured import render_page

    files.append(File.generated(config, "reference/index.md", content=reference_index()))
    for module in public_modules():
        files.append(File.generated(config, reference_page(module), content=f"::: {module}\n"))
    measured = sorted((Path(config.docs_dir) / "measured").glob("*.json"))
    files.append(File.generated(config, "measured.md", content=render_page(measured)))
    for path in sorted(RUNS.rglob("*")):
        if path.is_file() and path.suffix in {".png", ".gif", ".svg"}:
            uri = "runs/" + path.relative_to(RUNS).as_posix()
            files.append(File.generated(config, uri, abs_src_path=str(path)))
    _add_mathjax(files, config)
    return files


def _add_mathjax(files: Files, config: MkDocsConfig) -> None:
    import mathjax

    es5 = Path(mathjax.__path__[0]) / "static" / "mathjax" / "es5"
    files.append(
        File.generated(config, "mathjax/tex-chtml.js", abs_src_path=str(es5 / "tex-chtml.js"))
    )
    fonts = es5 / "output" / "chtml" / "fonts" / "woff-v2"
    for font in sorted(fonts.glob("*.woff")):
        uri = f"mathjax/output/chtml/fonts/woff-v2/{font.name}"
        files.append(File.generated(config, uri, abs_src_path=str(font)))


def on_page_markdown(markdown: str, page: Page, config: MkDocsConfig, files: Files) -> str:
    """Expand the course hooks."""
    markdown = COURSE_MARKER.sub(lambda m: course_section(m.group(1)), markdown)
    markdown = markdown.replace("<!-- course-readme -->", course_readme())
    return markdown.replace("<!-- course-helpers -->", course_helpers())
