"""Every script in examples/ (and examples/course/) runs to completion, headless, with no
arguments; files whose name starts with ``_`` are helpers the scripts import, not examples."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent / "examples"
EXAMPLES = sorted(path for path in ROOT.rglob("*.py") if not path.name.startswith("_"))


def test_there_are_examples():
    assert len(EXAMPLES) >= 3


@pytest.mark.slow
@pytest.mark.parametrize(
    "script", EXAMPLES, ids=[path.relative_to(ROOT).with_suffix("").as_posix() for path in EXAMPLES]
)
def test_example_runs(script, tmp_path):
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
