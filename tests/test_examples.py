"""Every script in examples/ (and examples/course/) runs to completion, headless, with no
arguments; files whose name starts with ``_`` are helpers the scripts import, not examples.

The site build runs the examples its pages show (``docs/hooks/site.py``) and keeps each run
under a key of everything the run depends on; a script whose kept run is still valid is not
run a second time here (``make test`` builds the site first)."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent / "examples"
EXAMPLES = sorted(path for path in ROOT.rglob("*.py") if not path.name.startswith("_"))


def _site():
    """``docs/hooks/site.py``, the build hook that keeps the site's runs, as a module."""
    path = ROOT.parent / "docs" / "hooks" / "site.py"
    spec = importlib.util.spec_from_file_location("docs_site_hook", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_there_are_examples():
    assert len(EXAMPLES) >= 3


@pytest.mark.slow
@pytest.mark.parametrize(
    "script", EXAMPLES, ids=[path.relative_to(ROOT).with_suffix("").as_posix() for path in EXAMPLES]
)
def test_example_runs(script, tmp_path):
    kept = _site().current_run(script)
    if kept is not None:
        assert (kept / "output.txt").read_text().strip(), "an example should print what it shows"
        return
    env = {**os.environ, "MUJOCO_GL": "egl", "MPLBACKEND": "Agg", "REDIK_OUT": str(tmp_path)}
    completed = subprocess.run(
        [sys.executable, str(script)],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert completed.returncode == 0, completed.stdout[-2000:] + completed.stderr[-4000:]
    assert completed.stdout.strip(), "an example should print what it shows"
