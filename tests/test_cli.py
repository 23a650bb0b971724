"""The command line: discovery, `redik info`, and errors reported without tracebacks."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import redik
from redik.cli import main


def test_info_lists_scenes(capsys):
    assert main(["info", "--list"]) == 0
    out = capsys.readouterr().out
    for name in redik.list_scenes():
        assert name in out


@pytest.mark.parametrize("scene", ["panda", "ur5e", "planar_2r"])
def test_info_describes_a_scene(capsys, scene):
    if scene not in redik.list_scenes():
        pytest.fail(f"bundled scene {scene!r} is missing")
    assert main(["info", scene]) == 0
    out = capsys.readouterr().out
    robot = redik.load(scene)
    for joint in robot.joint_names:
        assert joint in out
    assert "end-effector pose at home" in out
    line = next(line for line in out.splitlines() if line.startswith("position [m]:"))
    printed = np.array(line.split("[")[-1].rstrip("]").split(), dtype=float)
    np.testing.assert_allclose(printed, robot.fk(robot.home)[:3, 3], atol=1e-6)


def test_unknown_scene_is_a_clean_error(capsys):
    assert main(["info", "no_such_robot"]) == 2
    err = capsys.readouterr().err
    assert "no bundled scene named 'no_such_robot'" in err


def test_console_script_entry_point():
    completed = subprocess.run(
        [sys.executable, "-m", "redik", "--help"], capture_output=True, text=True, timeout=60
    )
    assert completed.returncode == 0
    for command in ("info", "bench"):
        assert command in completed.stdout
