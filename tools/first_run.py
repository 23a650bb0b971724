"""A user's first minutes, timed on a fresh clone with an empty numba cache.

The repository is cloned into a temporary folder and every figure is measured in a new
process that imports redik from that clone (``PYTHONPATH``), with ``NUMBA_CACHE_DIR``
pointing to an empty folder of its own, so nothing compiled earlier is reused (numba would
otherwise cache next to the sources, in ``__pycache__``). The Python environment (numpy,
MuJoCo, numba, mink, …) is the one running this script: pip's install time is not counted.

Figures, each printed beside its goal:

- ``import redik`` against ``import mink`` (whole process, medians of ``--runs``
  interleaved runs, after one untimed import of each has written the bytecode);
- the first :func:`redik.solve_pose` (panda, a reachable target) on an empty cache;
- the first :func:`redik.solve_problem` (panda, a pose task and a posture task) on an
  empty cache;
- ``redik demo`` (``make demo``'s last step) on an empty cache.

The three first calls are then timed again after the compile-ahead step that ``make env``
runs as the last step of installing (``python -m redik.core.compile_ahead``: the
compile-ahead modules in parallel processes; its output, each module's seconds, is printed
with its own time), each on its own copy of the cache that step filled. ``make demo`` beyond
pip's own install time is that step and the demo after it.

Usage::

    python tools/first_run.py [--repository PATH_OR_URL] [--runs 7] [--keep] [--record FILE]
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from redik.apps import measured

INSTALL_STEP = ["-m", "redik.core.compile_ahead"]
"""What ``make env`` runs after pip: the compile-ahead of what the first calls use."""

GOALS = {"import": 1.5, "solve_pose": 5.0, "solve_problem": None, "demo": None, "make demo": 60.0}
"""The goals: a ratio for the import, seconds for the rest (None: reported only)."""

FIRST_SOLVE_POSE = """
import time
import numpy as np
import redik
robot = redik.load("panda")
T = robot.fk(robot.random_q(np.random.default_rng(0)))
start = time.perf_counter()
result = redik.solve_pose(robot, T, seed=0)
print(time.perf_counter() - start, result.success)
"""

FIRST_SOLVE_PROBLEM = """
import time
import numpy as np
import redik
robot = redik.load("panda")
T = robot.fk(robot.random_q(np.random.default_rng(0)))
problem = redik.Problem(robot, [redik.FrameTask("ee", target=T), redik.PostureTask(priority=1)])
start = time.perf_counter()
result = redik.solve_problem(problem, robot.home)
print(time.perf_counter() - start, result.success)
"""


def main() -> int:
    """Clone, time each figure, print it beside its goal; exit code 1 when one is missed."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repository", default=str(Path(__file__).resolve().parents[1]))
    parser.add_argument("--runs", type=int, default=7, help="interleaved import runs")
    parser.add_argument("--keep", action="store_true", help="keep the temporary folder")
    parser.add_argument(
        "--record", metavar="FILE", help="also write the figures as JSON (docs/measured/)"
    )
    args = parser.parse_args()
    measured.start()
    load = os.getloadavg()
    folder = Path(tempfile.mkdtemp(prefix="redik-first-run-"))
    try:
        clone = folder / "redik"
        subprocess.run(
            ["git", "clone", "--quiet", args.repository, str(clone)], check=True, cwd=folder
        )
        missed = _report(clone, folder, args.runs)
    finally:
        if args.keep:
            print(f"kept {folder}")
        else:
            shutil.rmtree(folder, ignore_errors=True)
    if args.record:
        argv = sys.argv[1:]
        measured.write(args.record, "first_run", argv, load, program="python tools/first_run.py")
    return int(missed)


def _report(clone: Path, folder: Path, runs: int) -> bool:
    """Measure and print every figure; True when one misses its goal after installing."""
    redik_time, mink_time = _imports(clone, folder, runs)
    ratio = redik_time / mink_time
    missed = ratio > GOALS["import"]
    measured.record(
        "import redik beside import mink",
        redik_s=redik_time, mink_s=mink_time, ratio=ratio, goal=GOALS["import"],
    )  # fmt: skip
    print(
        f"import redik {redik_time:.2f} s / import mink {mink_time:.2f} s = {ratio:.2f} "
        f"(goal ≤ {GOALS['import']}; medians of {runs})"
    )
    _firsts(clone, folder, None, "empty cache")
    installed = folder / "installed"
    start = time.perf_counter()
    output = _python(clone, folder, None, INSTALL_STEP, installed)
    install = time.perf_counter() - start
    print(f"install step {' '.join(INSTALL_STEP)}: {install:.2f} s")
    measured.record(
        "first run on a fresh clone", figure="install step", time_s=install, goal_s=None
    )
    print("  " + output.replace("\n", "\n  "))
    missed, demo = _firsts(clone, folder, installed, "after the install step")
    return missed | _line(
        "make demo beyond pip", install + demo, "make demo", "install step + redik demo"
    )


def _firsts(clone: Path, folder: Path, cache: Path | None, label: str) -> tuple[bool, float]:
    """The first solve_pose, solve_problem and demo, each on a copy of ``cache``.

    Returns:
        Whether one missed its goal, and the demo's seconds.
    """
    missed = False
    for name, code in (("solve_pose", FIRST_SOLVE_POSE), ("solve_problem", FIRST_SOLVE_PROBLEM)):
        seconds, success = _python(clone, folder, code, None, cache).splitlines()[-1].split()
        missed |= _line(f"first {name}, {label}", float(seconds), name, f"success {success}")
    start = time.perf_counter()
    _python(clone, folder, None, ["-m", "redik", "demo", "--out", str(folder / "demo")], cache)
    seconds = time.perf_counter() - start
    return missed | _line(f"redik demo, {label}", seconds, "demo"), seconds


def _line(label: str, seconds: float, goal_name: str, note: str = "") -> bool:
    """Print (and record) one figure beside its goal; True when it misses it."""
    goal = GOALS[goal_name]
    verdict = "" if goal is None else f" (goal ≤ {goal:g} s)"
    print(f"{label}{' (' + note + ')' if note else ''}: {seconds:.2f} s{verdict}")
    measured.record("first run on a fresh clone", figure=label, time_s=seconds, goal_s=goal)
    return goal is not None and seconds > goal


def _imports(clone: Path, folder: Path, runs: int) -> tuple[float, float]:
    """Median wall times of a process that imports redik and of one that imports mink."""
    times: dict[str, list[float]] = {"redik": [], "mink": []}
    for module in times:  # untimed: writes the bytecode of the clone
        _python(clone, folder, f"import {module}")
    for _ in range(runs):
        for module, samples in times.items():
            start = time.perf_counter()
            _python(clone, folder, f"import {module}")
            samples.append(time.perf_counter() - start)
    return statistics.median(times["redik"]), statistics.median(times["mink"])


def _python(
    clone: Path,
    folder: Path,
    code: str | None,
    arguments: list[str] | None = None,
    cache: Path | None = None,
) -> str:
    """Run this Python on ``code`` (or ``arguments``) in the clone; its output.

    The numba cache is a new empty folder, or a copy of ``cache`` when that exists; a
    ``cache`` that does not exist yet is created and used itself (by the install step).
    """
    if cache is None:
        cache = Path(tempfile.mkdtemp(prefix="numba-", dir=folder))
    elif not cache.exists():
        cache.mkdir()
    else:
        copy = Path(tempfile.mkdtemp(prefix="numba-", dir=folder))
        shutil.copytree(cache, copy, dirs_exist_ok=True)
        cache = copy
    environment = {
        **os.environ,
        "PYTHONPATH": str(clone),
        "NUMBA_CACHE_DIR": str(cache),
        "MPLBACKEND": "Agg",
    }
    command = [sys.executable, *(["-c", code] if code is not None else arguments or [])]
    done = subprocess.run(
        command, cwd=clone, env=environment, check=True, capture_output=True, text=True
    )
    return done.stdout.strip()


if __name__ == "__main__":
    raise SystemExit(main())
